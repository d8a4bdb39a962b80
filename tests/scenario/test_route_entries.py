"""``planar.router`` and ``route`` entries: the router reached from scenario files and the CLI
(docs/planar-routing.md "From a scenario file", docs/scenarios.md#routing)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from openmotion.cli import app
from openmotion.scenario import run_scenario
from openmotion.scenario.load import ScenarioError, parse_scenario
from openmotion.scenario.planar_routing import Route
from openmotion.scenario.schema import TIMELINE_COMMANDS

FIELD = """\
name: routes
planar:
  environment: {columns: 4, rows: 2}
  movers: [{name: a, x: 120, y: 120}, {name: b, x: 840, y: 120}]
  groups: [{name: g}]
"""
ROUTER = "  router: {pitch: 240, obstacles: [{name: post, x: 600, y: 360, width: 100, height: " \
         "100}]}\n"


def problems(text: str) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text, "bad.yaml")
    return [str(problem) for problem in info.value.problems]


def run(text: str):  # noqa: ANN201 - a ScenarioResult
    return run_scenario(parse_scenario(text, "routes.yaml"))


def test_route_is_a_timeline_command_with_its_targets() -> None:
    assert TIMELINE_COMMANDS["route"] is Route
    scenario = parse_scenario(FIELD + ROUTER + "timeline:\n  - {id: go, at: 0, command: route, "
                              "targets: {a: {x: 360, y: 360, c: 90}, b: {x: 840, y: 360}}, "
                              "time_budget: 0.01}\n")
    entry = scenario.timeline[0]
    assert isinstance(entry, Route)
    assert entry.axis == "a, b"
    assert (entry.targets["a"].c, entry.targets["b"].c) == (90.0, None)
    assert entry.time_budget == 0.01
    router = scenario.planar.router
    assert router.pitch == 240.0 and router.time_budget == 0.0  # the first plan only
    assert router.obstacles[0].geometry().bounds == (550.0, 310.0, 650.0, 410.0)


@pytest.mark.parametrize(("extra", "expected"), [
    ("timeline:\n  - {at: 0, command: route, targets: {z: {x: 1, y: 2}}}\n",
     "bad.yaml:7: timeline[0].targets: unknown planar mover 'z' (planar.movers: a, b)"),
    ("timeline:\n  - {at: 0, command: route, targets: {a: {x: .inf, y: 2}}}\n",
     "bad.yaml:7: timeline[0].targets.a.x: must be a finite number, got inf"),
    ("timeline:\n  - {at: 0, command: route, targets: {a: {x: 1, y: .nan}}}\n",
     "bad.yaml:7: timeline[0].targets.a.y: must be a finite number, got nan"),
    ("timeline:\n  - {at: 0, command: route, targets: {a: {x: 1, y: 2}}, time_budget: -1}\n",
     "bad.yaml:7: timeline[0].time_budget: must be greater than or equal to 0, got -1"),
    ("timeline:\n  - {at: 0, command: route, targets: {}}\n",
     "bad.yaml:7: timeline[0].targets: name at least one mover and its target"),
    ("timeline:\n  - {at: 0, command: route, targets: {a: {x: 1}}}\n",
     "bad.yaml:7: timeline[0].targets.a.y: required field is missing"),
    ("  router: {time_budget: -0.5}\n",
     "bad.yaml:6: planar.router.time_budget: must be greater than or equal to 0, got -0.5"),
    ("  router: {pitch: 100}\n",
     "bad.yaml:6: planar.router.pitch: 100 mm is less than the side of the largest mover of "
     "group 'g' (155 mm)"),
    ("  router: {seed: -1}\n",
     "bad.yaml:6: planar.router.seed: must be greater than or equal to 0, got -1"),
    ("  router: {group: q}\n",
     "bad.yaml:6: planar.router.group: unknown planar group 'q' (planar.groups: g)"),
    ("  router: {obstacles: [{name: p, x: 1, y: 1, width: 10, height: 10, points: [[0, 0], "
     "[1, 0], [1, 1]]}]}\n",
     "bad.yaml:6: planar.router.obstacles[0]: give a rectangle ('x', 'y', 'width', 'height') "
     "or 'points', not both"),
    ("  router: {obstacles: [{name: p, x: 1, y: 1}]}\n",
     "bad.yaml:6: planar.router.obstacles[0]: give 'x', 'y', 'width' and 'height' (a "
     "rectangle), or 'points'"),
    ("  router: {obstacles: [{name: p, points: [[0, 0], [10, 10], [10, 0], [0, 10]]}]}\n",
     "bad.yaml:6: planar.router.obstacles[0].points: the polygon crosses itself"),
    ("  router: {obstacles: [{name: p, x: 1, y: 1, width: 10, height: 10}, {name: p, x: 100, "
     "y: 1, width: 10, height: 10}]}\n",
     "bad.yaml:6: planar.router.obstacles: obstacle name 'p' is used twice"),
    ("  router: {obstacles: [{name: p, x: 1, y: 1, width: -10, height: 10}]}\n",
     "bad.yaml:6: planar.router.obstacles[0].width: must be greater than 0, got -10"),
    ("  router: {pitch: 240, velocty: 3}\n",
     "bad.yaml:6: planar.router.velocty: unknown field 'velocty' (did you mean 'velocity'?)"),
])
def test_bad_route_input_names_its_field(extra: str, expected: str) -> None:
    assert problems(FIELD + extra) == [expected]


def test_a_route_needs_a_stator_surface_and_a_group_it_can_take() -> None:
    bare = "name: t\nplanar:\n  movers: [{name: a}]\n  groups: [{name: g}]\n"
    route = "timeline:\n  - {at: 0, command: route, targets: {a: {x: 1, y: 2}}}\n"
    assert problems(bare + route) == [
        "bad.yaml:6: timeline[0]: a route needs planar.environment: the router plans on the "
        "stator surface"]
    assert problems(bare + "  router: {}\n") == [
        "bad.yaml:5: planar.router: the router plans on the stator surface: give "
        "planar.environment"]
    two = FIELD.replace("groups: [{name: g}]", "groups: [{name: g, movers: [a]}, "
                        "{name: h, movers: [b], environment: false}]")
    assert problems(two + route) == [
        "bad.yaml:7: timeline[0]: a route needs planar.router with the 'group' whose movers it "
        "routes (planar.groups: g, h)"]
    assert problems(two + "  router: {}\n") == [
        "bad.yaml:6: planar.router.group: name the planar group whose movers it routes "
        "(planar.groups: g, h)"]
    parse_scenario(two + "  router: {group: h}\n" + route)  # named: it loads


SWAP = FIELD + ROUTER + """\
timeline:
  - {id: swap, at: 0, command: route, targets: {a: {x: 840, y: 120}, b: {x: 120, y: 120, c: 90}}}
  - {id: off, when: swap.done, command: route, targets: {a: {x: 1000, y: 120}}}
  - {id: post, when: off.finished, command: route, targets: {a: {x: 600, y: 360}}}
  - {id: back, when: post.finished, command: route, targets: {a: {x: 120, y: 360}}}
checks:
  - {command: swap, result: done}
  - {command: off, result: error, error_id: PLANAR_COLLISION}
  - {command: post, result: error, error_id: PLANAR_COLLISION}
  - {command: back, result: done}
  - {signal: a.x, expect: 120}
  - {signal: a.y, expect: 360}
  - {signal: b.x, expect: 120}
  - {signal: b.c, expect: 90}
"""


def test_a_swap_arrives_and_failed_routes_name_their_blocker_while_the_router_goes_on() -> None:
    result = run(SWAP)
    assert result.passed, [check for check in result.checks if not check.passed]
    rows = {row.id: row for row in result.commands}
    assert rows["swap"].axis == "a, b" and rows["swap"].result == "DONE"
    assert rows["off"].error == "PLANAR_COLLISION"
    assert rows["off"].message == "a: its target (1000, 120, 0) leaves the stator surface " \
                                  "(blocker: the stator surface)"
    assert rows["off"].ended_at == rows["off"].issued_at  # refused when it is planned
    assert rows["post"].message == "a: its target (600, 360) is occupied by post " \
                                   "(blocker: post)"
    assert rows["back"].result == "DONE" and rows["back"].ended_at > rows["back"].issued_at
    # each mover's route has its own events, named by the entry
    ends = [(e.object, e.result, e.label) for e in result.trace.events
            if e.command == "Route" and e.result != "ISSUED"]
    assert ("a", "DONE", "swap") in ends and ("b", "DONE", "swap") in ends
    assert ("a", "ERROR", "off") in ends
    # the trace's layout keeps every plan with its time, and the obstacles
    planar = result.trace.layout["planar"]
    plans = planar["planned_routes"]
    assert [(p["mover"], p["time"]) for p in plans[:2]] == [("a", 0.0), ("b", 0.0)]
    assert plans[0]["points"][0] == [120.0, 120.0] and plans[0]["points"][-1] == [840.0, 120.0]
    assert [p["mover"] for p in plans if p["time"] > 0.0] == ["a"]  # back (off, post: none)
    assert planar["obstacles"] == [{"name": "post", "rings": [
        [[550.0, 310.0], [650.0, 310.0], [650.0, 410.0], [550.0, 410.0], [550.0, 310.0]]]}]


def test_a_mover_of_another_group_is_refused_at_run_time_and_the_others_arrive() -> None:
    text = FIELD.replace("groups: [{name: g}]", "groups: [{name: g, movers: [a]}, "
                         "{name: h, movers: [b], environment: false}]") + """\
  router: {group: g}
timeline:
  - {id: both, at: 0, command: route, targets: {a: {x: 360, y: 360}, b: {x: 840, y: 360}}}
"""
    result = run(text)
    row = result.commands[0]
    assert (row.result, row.error) == ("ERROR", "PLANAR_WRONG_STATE")
    assert row.message == "b: is not in the router's group"
    movers = {m.mover: m for m in result.planar_movers}
    assert (movers["a"].x, movers["a"].y) == (360.0, 360.0)  # routed all the same
    assert (movers["b"].x, movers["b"].y) == (840.0, 120.0)


def test_without_planar_router_the_only_group_is_routed_with_the_defaults() -> None:
    text = FIELD + "timeline:\n  - {id: go, at: 0, command: route, targets: " \
                   "{a: {x: 360, y: 360}}}\n"
    result = run(text)
    assert result.commands[0].result == "DONE"
    assert (result.planar_movers[0].x, result.planar_movers[0].y) == (360.0, 360.0)
    assert result.trace.layout["planar"]["obstacles"] == []


def test_two_runs_are_bit_identical() -> None:
    first, second = run(SWAP), run(SWAP)
    assert first.summary() == second.summary()
    assert first.trace.equals(second.trace)
    assert first.trace.layout == second.trace.layout


def test_a_scenario_without_routes_has_no_router() -> None:
    result = run(FIELD + "timeline:\n  - {at: 0, mover: a, command: move_to_position, x: 360, "
                         "y: 360}\n")
    assert "planned_routes" not in result.trace.layout["planar"]
    assert "route plans" not in result.trace.layout["objects"]


def test_the_cli_runs_routes_and_refuses_bad_ones_with_exit_code_2(tmp_path: Path) -> None:
    runner = CliRunner()
    good = tmp_path / "good.yaml"
    good.write_text(SWAP)
    done = runner.invoke(app, ["run", str(good), "--json", "--trace",
                               str(tmp_path / "routes.npz")])
    assert done.exit_code == 0, done.output
    assert '"result": "ERROR"' in done.stdout and "(blocker: post)" in done.stdout
    bad = tmp_path / "bad.yaml"
    bad.write_text(FIELD + "timeline:\n  - {at: 0, command: route, targets: {a: {x: 1, y: 2}},"
                           " time_budget: -1}\n")
    for command in ("run", "check"):
        refused = runner.invoke(app, [command, str(bad)])
        assert refused.exit_code == 2
        assert "timeline[0].time_budget: must be greater than or equal to 0" in refused.stderr
        assert refused.stdout == ""
    assert runner.invoke(app, ["check", str(good)]).exit_code == 0  # usable next


def test_the_pages_scenario_runs_as_it_says() -> None:
    """docs/planar-routing.md "From a scenario file": its block runs, and the rows it shows
    are the run's."""
    page = (Path(__file__).resolve().parents[2] / "docs" / "planar-routing.md").read_text()
    block = re.findall(r"## From a scenario file\n\n```yaml\n(.*?)```", page, re.S)[0]
    result = run("name: doc\n" + block)
    assert result.passed
    rows = [f"{row.id}: {row.result}" + (f" {row.error}: {row.message}" if row.error else "")
            for row in result.commands]
    assert rows == ["swap: DONE", "post: ERROR PLANAR_COLLISION: a: its target (600, 360) is "
                                  "occupied by post (blocker: post)"]
    assert "\n".join(rows) in page


def test_the_scenario_pages_routing_block_runs() -> None:
    """docs/scenarios.md#routing: every option as written loads, and the swap arrives."""
    page = (Path(__file__).resolve().parents[2] / "docs" / "scenarios.md").read_text()
    block = re.findall(r"### Routing\n\n```yaml\n(.*?)```", page, re.S)[0]
    result = run("name: doc\n" + block)
    assert [row.result for row in result.commands] == ["DONE"]
    movers = {m.mover: m for m in result.planar_movers}
    assert (movers["a"].x, movers["b"].x, movers["b"].c) == (1080.0, 120.0, 90.0)
    assert [o["name"] for o in result.trace.layout["planar"]["obstacles"]] == ["press", "chute"]


def test_a_route_row_joins_its_movers_outcomes() -> None:
    """Busy while one route runs; Error over Aborted over Done; each failure named once."""
    from openmotion.axis.commands import Command, CommandStatus
    from openmotion.core.errors import ErrorId
    from openmotion.scenario.planar_routing import follow_route

    class Handle(Command):
        def __init__(self, name: str) -> None:
            super().__init__("Route", 0.0)
            self.mover = type("M", (), {"name": name})()
            self.blocker = None

    a, b, c = Handle("a"), Handle("b"), Handle("c")
    row = Command("route", 0.0)
    follow_route(row, {"a": a, "b": b, "c": c}, 0.0)
    assert row.status is CommandStatus.BUFFERED
    a.start()
    b.end(CommandStatus.ABORTED, 0.1)
    c.end(CommandStatus.ERROR, 0.1, ErrorId.PLANAR_COLLISION, "c: no route found")
    c.blocker = "other movers"
    follow_route(row, {"a": a, "b": b, "c": c}, 0.1)
    assert row.active  # a still travels
    a.end(CommandStatus.DONE, 0.5)
    follow_route(row, {"a": a, "b": b, "c": c}, 0.5)
    assert (row.status, row.error_id, row.ended_at) == (CommandStatus.ERROR,
                                                       ErrorId.PLANAR_COLLISION, 0.5)
    assert row.message == "c: no route found (blocker: other movers); b: aborted"
    follow_route(row, {"a": a, "b": b, "c": c}, 0.6)  # an ended row stays as it ended
    assert row.ended_at == 0.5
