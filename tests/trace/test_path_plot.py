"""The path figure of axes groups: the TCP path coloured by the active command, hand-overs,
refused commands and the axis profiles are the trace's numbers; the group's signals reach
the trace, the default figure and the CLI."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from openmotion.cli import app
from openmotion.scenario import ScenarioResult, parse_scenario, run_scenario
from openmotion.trace import Event, Trace, default_figure, figure_signals, plot_trace
from openmotion.trace.path import IDLE_COLOR, Span, command_spans, path_figure
from openmotion.trace.scope import scope_figure

SQUARE = """\
name: path plot
cycle_time: 0.002
axes: [{name: x}, {name: y}]
axes_groups:
  - name: xy
    axes: [x, y]
    dynamics: {velocity: 200, acceleration: 2000, deceleration: 2000, jerk: 40000}
timeline:
  - {id: out, at: 0, group: xy, command: move_linear_absolute, position: [50, 0]}
  - {id: up, at: 0, group: xy, command: move_linear_absolute, position: [50, 50],
     buffer_mode: buffered}
  - {id: refused, when: up.done, group: xy, command: move_linear_absolute, position: [1]}
  - {id: back, when: up.done, group: xy, command: move_circular_absolute,
     aux_point: [25, 75], end_point: [0, 50]}
record: {signals: [x.set_position, y.set_velocity]}
checks:
  - {signal: xy.x, expect: 0.0, tolerance: 1e-9}
"""


@pytest.fixture(scope="module")
def square() -> ScenarioResult:
    return run_scenario(parse_scenario(SQUARE), figure=True)


def lines_of(panel) -> dict[str, object]:
    return {line.get_gid(): line for line in panel.get_lines()}


def test_a_run_with_an_axes_group_records_the_path_figure_and_draws_it(square) -> None:
    trace = square.trace
    assert square.passed and default_figure(trace) == "path"
    assert trace.layout["axes_groups"] == {"xy": {"axes": ["x", "y"], "coordinates": ["x", "y"]}}
    assert trace.layout["objects"]["xy"] == "axes_group"
    needed = figure_signals(trace.layout)
    assert needed == ["xy.x", "xy.y", "xy.path_velocity", "x.set_position", "x.set_velocity",
                      "x.set_acceleration", "y.set_position", "y.set_velocity",
                      "y.set_acceleration"]
    assert trace.signals[:2] == ("x.set_position", "y.set_velocity")  # the scenario's first
    assert set(needed) <= set(trace.signals)
    assert len(plot_trace(trace).axes) == 4  # the plane and three profile panels


def test_each_command_colours_its_span_of_the_path(square) -> None:
    trace = square.trace
    spans = command_spans(trace, "xy")
    assert [span.label for span in spans] == ["out", "up", "back"]
    assert [span.result for span in spans] == ["DONE"] * 3
    rows = {row.id: row for row in square.commands}
    assert spans[0].start == 0.0 and spans[0].end == rows["out"].ended_at
    assert spans[1].start == rows["out"].ended_at and spans[1].end == rows["up"].ended_at
    assert spans[2].start == rows["back"].issued_at  # issued later than up ended
    plane = path_figure(trace).axes[0]
    lines = lines_of(plane)
    x, y = lines["xy:tcp"].get_data()
    assert np.array_equal(x, trace["xy.x"]) and np.array_equal(y, trace["xy.y"])
    assert lines["xy:tcp"].get_color() == IDLE_COLOR
    for span in spans:
        inside = (trace.time > span.start) & (trace.time <= span.end)
        x, y = lines[f"xy:{span.label}"].get_data()
        assert np.array_equal(x[1:], trace["xy.x"][inside]), span.label  # x[0]: the joint
    assert {"xy:handover:up", "xy:handover:back", "xy:start", "xy:end"} <= set(lines)
    assert "xy:handover:out" not in lines  # the path starts there


def test_a_refused_command_is_a_cross_where_the_tcp_was(square) -> None:
    trace = square.trace
    plane = path_figure(trace).axes[0]
    cross = lines_of(plane)["refused:refused"]
    assert tuple(cross.get_xdata()) == (50.0,) and tuple(cross.get_ydata()) == (50.0,)


def test_the_profiles_are_the_members_setpoints_and_the_path_velocity(square) -> None:
    trace = square.trace
    position, velocity, acceleration = path_figure(trace).axes[1:]
    for panel, signal in ((position, "set_position"), (velocity, "set_velocity"),
                          (acceleration, "set_acceleration")):
        lines = lines_of(panel)
        for axis in ("x", "y"):
            assert np.array_equal(lines[f"{axis}.{signal}"].get_ydata(),
                                  trace[f"{axis}.{signal}"])
    assert np.array_equal(lines_of(velocity)["xy.path_velocity"].get_ydata(),
                          trace["xy.path_velocity"])
    shaded = [patch.get_gid() for patch in position.patches]
    assert shaded == ["span:out", "span:up", "span:back"]


def test_command_spans_follow_the_events() -> None:
    """Buffered commands start where the one before ended; an aborting one where it is
    issued; a refused one has no span; one still busy runs to the end of the trace."""
    trace = Trace(["time", "g.x", "g.y"], np.zeros((6, 3)) + np.arange(6)[:, None], [
        Event(0.0, "g", "MC_MoveLinearAbsolute", "ISSUED", "a"),
        Event(0.0, "g", "MC_MoveLinearAbsolute", "ISSUED", "b"),
        Event(0.0, "g", "group_enable", "ISSUED", "on"),
        Event(0.0, "g", "group_enable", "DONE", "on"),
        Event(1.0, "g", "MC_MoveCircularAbsolute", "ISSUED", "no"),
        Event(1.0, "g", "MC_MoveCircularAbsolute", "ERROR", "no"),
        Event(2.0, "g", "MC_MoveLinearAbsolute", "DONE", "a"),
        Event(3.0, "g", "MC_MoveDirectAbsolute", "ISSUED", "c"),
        Event(3.0, "g", "MC_MoveLinearAbsolute", "ABORTED", "b"),
        Event(0.5, "h", "MC_MoveLinearAbsolute", "ISSUED", "other group"),
    ])
    assert command_spans(trace, "g") == [Span("a", 0.0, 2.0, "DONE"),
                                         Span("b", 2.0, 3.0, "ABORTED"),
                                         Span("c", 3.0, 5.0, "BUSY")]


def test_the_scope_puts_group_signals_in_their_panels(square) -> None:
    figure = scope_figure(square.trace, ["xy"])
    titles = [panel.get_ylabel() for panel in figure.axes]
    assert titles == ["position [mm]", "velocity [mm/s]"]  # x, y; path_velocity


def test_plot_redraws_the_path_figure_from_the_npz(tmp_path: Path,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "square.yaml").write_text(SQUARE)
    runner = CliRunner()
    result = runner.invoke(app, ["run", "square.yaml", "--trace", "t.npz", "--plot", "p.png",
                                 "-q"])
    assert result.exit_code == 0, result.output
    result = runner.invoke(app, ["plot", "t.npz", "-o", "again.svg"])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"xy: axes x, y" in (tmp_path / "again.svg").read_bytes()
