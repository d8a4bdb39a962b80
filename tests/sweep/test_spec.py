"""Sweep files: what loads, and the specific error each mistake gives (file, line, field)."""

from __future__ import annotations

from pathlib import Path

import pytest

from openmotion.core.errors import ConfigError
from openmotion.sweep import SweepError, load_sweep

VELOCITY = {"path": "timeline[go].velocity", "values": [100.0, 200.0]}


def test_a_valid_sweep_loads_with_its_base_scenario(write_sweep) -> None:
    sweep = load_sweep(write_sweep(parameters=[VELOCITY], seed=3))
    assert sweep.spec.seed == 3 and sweep.scenario_file.name == "short_move.yaml"
    assert sweep.base["timeline"][1]["velocity"] == 200.0
    assert [m.key for m in sweep.metrics] == ["signal", "signal", "commands", "run",
                                              "cycle_cost"]


def test_the_base_scenario_may_be_a_shipped_example(write_sweep) -> None:
    sweep = load_sweep(write_sweep(scenario="single_move",
                                   parameters=[{"path": "timeline[out].velocity",
                                                "values": [100.0]}]))
    assert sweep.scenario_file.name == "single_move.yaml"


def _error(path: Path) -> SweepError:
    with pytest.raises(SweepError) as caught:
        load_sweep(path)
    assert isinstance(caught.value, ConfigError)
    return caught.value


@pytest.mark.parametrize(("fields", "expected"), [
    ({"paramters": []}, "paramters: unknown field 'paramters'"),
    ({"metrics": None}, "metrics: required field is missing"),
    ({"scenario": "no_such_example"}, "scenario: 'no_such_example': no such file (beside the "
                                      "sweep file) and no shipped example of that name"),
    ({"parameters": [{"values": [1]}]},
     "parameters[0]: give either path (the value's place in the scenario) or first"),
    ({"parameters": [{"path": "axes[0].position", "values": [1], "uniform": [0, 1]}]},
     "parameters[0]: give exactly one of values, linspace, uniform, integers, choice (got "
     "values, uniform)"),
    ({"parameters": [{"path": "axes[0]position", "values": [1]}]},
     "parameters[0]: 'axes[0]position' is not a path like axes[0].position"),
    ({"parameters": [{"path": "axes[3].position", "values": [1]}]},
     "parameters[0].path: axes[3].position: axes[3]: index out of range (axes has 1 items)"),
    ({"parameters": [{"path": "timeline[stop].velocity", "values": [1]}]},
     "parameters[0].path: timeline[stop].velocity: timeline has no item with name or id "
     "'stop'"),
    ({"parameters": [{"path": "axes[0].parameters.nope.x", "values": [1]}]},
     "axes[0].parameters has no key 'nope'"),
    ({"parameters": [{"path": "axes[0].position", "uniform": [2.0, 1.0]}]},
     "uniform: must be [low, high] with low < high, got [2.0, 1.0]"),
    ({"parameters": [{"path": "axes[0].position", "values": []}]},
     "parameters[0].values: List should have at least 1 item"),
    ({"parameters": [{"first": ["timeline"], "values": [1]}]},
     "parameters[0]: name: required with first"),
    ({"parameters": [{"first": ["timeline"], "name": "n", "values": [3]}]},
     "parameters[0].first: timeline: has 2 items, fewer than 3"),
    ({"parameters": [{"first": ["axes[0].parameters"], "name": "n", "values": [1]}]},
     "parameters[0].first: axes[0].parameters: not a list"),
    ({"parameters": [{"first": ["timeline"], "name": "n", "values": [0.5]}]},
     "parameters[0]: first: the values must be whole numbers >= 0"),
    ({"metrics": [{"signals": "x.position"}]},
     "metrics[0]: give exactly one of signal, commands, run, station, cycle_cost"),
    ({"metrics": [{"signal": "x.position", "stats": ["median"]}]},
     "metrics[0].stats[0]: must be 'min', 'max', 'mean' or 'final', got 'median'"),
    ({"metrics": [{"commands": ["finished"]}]}, "metrics[0].commands[0]: must be 'done'"),
    ({"metrics": [{"run": ["end_time"]}, {"run": ["end_time"]}]},
     "column 'run.end_time' given twice"),
    ({"parameters": [{"path": "axes[0].position", "name": "seed", "values": [1]}]},
     "column 'seed' given twice (or a reserved name"),
    ({"combine": "zip", "parameters": [VELOCITY, {"path": "axes[0].position",
                                                  "values": [1.0]}]},
     "combine zip: the list parameters must have equal lengths"),
    ({"repeat": 0}, "repeat: must be greater than or equal to 1, got 0"),
])
def test_a_mistake_is_a_sweep_error_naming_the_field(write_sweep, fields: dict,
                                                     expected: str) -> None:
    path = write_sweep(**fields)
    message = str(_error(path))
    assert message.startswith(f"{path}:"), message
    assert expected in message


def test_the_error_names_the_line_of_the_field(tmp_path: Path) -> None:
    path = tmp_path / "sweep.yaml"
    path.write_text("scenario: single_move\nmetrics:\n  - {run: [end_time]}\n"
                    "parameters:\n  - {path: 'timeline[out].velocity', values: [1.0]}\n"
                    "  - path: axes[9].position\n    values: [1.0]\n", encoding="utf-8")
    error = _error(path)
    assert str(error).startswith(f"{path}:6: parameters[1].path: axes[9].position")
    assert len(error.problems) == 1


def test_every_problem_is_listed(write_sweep) -> None:
    error = _error(write_sweep(repeat=0, samples=0, paramters=[]))
    assert [p.path for p in error.problems] == ["repeat", "samples", "paramters"]
    assert str(error).endswith("(and 2 more)")


def test_an_invalid_base_scenario_is_named(tmp_path: Path, write_sweep) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: bad\naxes:\n  - {name: x, parameters: {max_velocity: -1.0}}\n",
                   encoding="utf-8")
    message = str(_error(write_sweep(scenario="bad.yaml")))
    assert "scenario: the base scenario is invalid" in message
    assert "axes[0].parameters.max_velocity" in message


def test_files_that_are_no_sweep(tmp_path: Path) -> None:
    path = tmp_path / "list.yaml"
    path.write_text("- 1\n- 2\n", encoding="utf-8")
    assert "must hold a mapping with at least 'scenario' and 'metrics'" in str(_error(path))
    path.write_text("scenario: [\n", encoding="utf-8")
    assert "invalid YAML" in str(_error(path))
    assert "cannot read" in str(_error(tmp_path / "missing.yaml"))
    path.write_text("scenario: single_move\nmetrics: [{run: [cycles]}]\n", encoding="utf-8")
    assert load_sweep(path).spec.scenario == "single_move"  # usable after the errors
