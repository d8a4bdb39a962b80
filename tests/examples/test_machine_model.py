"""One signal vocabulary (issue: the machine model; D-226, D-227, D-228, D-234): for every
shipped example, the trace, the viewer and the scenario layer expose exactly the signals of
the machine model, and name its objects with the model's kinds.

Each example is set up as ``openmotion run`` sets it up (the viewer's ``scenario_machine`` is
the runner's set-up half) and stepped a little, so that the values are not all at rest.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from openmotion.kernel.model import MachineModel, machine
from openmotion.scenario import examples_dir
from openmotion.scenario.reading import ScenarioLoader
from openmotion.scenario.schema import COMMAND_FLAGS, Scenario, names_in
from openmotion.scenario.signals import RunSignals, check_signal, scenario_signals
from openmotion.trace import TraceRecorder
from openmotion.trace.signals import MOVER_SIGNALS, describe, source_of
from openmotion.viewer import Session, scenario_machine

EXAMPLES = sorted(examples_dir().glob("*.yaml"))
CYCLES = 200  #: stepped before the signals are compared


def built(path: Path) -> tuple[Session, MachineModel]:
    made = scenario_machine(path)
    rt = made.runtime
    for _ in range(CYCLES):
        if made.finished():
            break
        rt.step()
    session = Session(made, clock=lambda: 100.0, paused=True)
    return session, machine(rt)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda path: path.stem)
def test_trace_and_viewer_expose_exactly_the_machine_model(path: Path) -> None:
    session, model = built(path)
    rt = session.machine.runtime
    signals = model.signals()
    assert signals, "every example has signals"
    # the trace records every signal of the model, bit for bit what the model reads
    recorder = TraceRecorder(rt, list(signals))
    recorder.sample(rt)
    expected = np.array([signal.read() for signal in signals.values()], dtype=np.float64)
    assert recorder.trace.data[-1, 1:].tobytes() == expected.tobytes()
    for obj in model:
        # an object's trace vocabulary is its kind's; an axis adds a CA mover's (D-227)
        source = source_of(obj.target)
        assert source is not None and source.kind == obj.kind
        extra = MOVER_SIGNALS if obj.kind == "axis" else ()
        assert source.signals == (*(signal.name for signal in obj.signals), *extra)
        # the trace's layout names it as the model does
        assert describe([obj.target])["objects"] == {obj.name: obj.kind}
    # the viewer's scope offers exactly the model's scope signals, in model order
    offered = json.loads(session.hello())["signals"]
    assert offered == [name for name, signal in signals.items() if signal.scope]
    # the viewer's table lists exactly the model's objects
    session.tick()
    assert session.frame is not None
    rows = json.loads(session.frame.text)["rows"]
    assert {row["name"] for row in rows} == {obj.name for obj in model}


#: names no model signal has: a scenario that accepted one would offer a signal of its own
#: (a command handle's outputs are conditions' flags, never signals)
NOT_SIGNALS = ("speed", "arc", "set_gap", "position_1", *COMMAND_FLAGS)


def _by_name(model: MachineModel) -> dict[str, tuple[str, ...]]:
    """Each object name with its signals (an axis and the CA mover it is share a name)."""
    found: dict[str, tuple[str, ...]] = {}
    for obj in model:
        found[obj.name] = found.get(obj.name, ()) + tuple(signal.name for signal in obj.signals)
    return {name: signals for name, signals in found.items() if signals}


def _comparison(model: MachineModel, name: str) -> str:
    """A condition on signal ``name`` the scenario must accept: a member's name for an
    enumeration (a group's state conditions take one), else a number."""
    dtype = model.signal(name).dtype
    members = getattr(dtype, "__members__", None)
    return f"{name} == {next(iter(members)).lower()}" if members else f"{name} >= 0"


def _data(path: Path) -> dict:
    loader = ScenarioLoader(path.read_text(encoding="utf-8"))
    try:
        return loader.get_single_data()
    finally:
        loader.dispose()


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda path: path.stem)
def test_the_scenario_layer_accepts_exactly_the_machine_model_signals(path: Path) -> None:
    """Per object, what a scenario may record, check and wait on is its model signals: no
    more (no scenario-only signal), no fewer (no model signal a scenario cannot reach)."""
    _, model = built(path)
    data = _data(path)
    names = names_in(data)
    expected = _by_name(model)
    assert scenario_signals(names) == expected
    candidates = {signal.name for obj in model for signal in obj.signals} | set(NOT_SIGNALS)
    for owner, signals in expected.items():
        for prop in sorted(candidates):
            name = f"{owner}.{prop}"
            if prop in signals:
                assert check_signal(name, names) == name
            else:
                with pytest.raises(ValueError, match="one of|among|no CA group"):
                    check_signal(name, names)
    # the file itself records every model signal, checks each one every cycle and once a
    # condition on it holds; the run resolves them in the model and reads the same values
    every = [f"{owner}.{prop}" for owner, signals in expected.items() for prop in signals]
    data.setdefault("record", {})["signals"] = every
    data["checks"] = [*data.get("checks", []),
                      *({"signal": name, "min": -1e300, "at": "always"} for name in every),
                      *({"signal": name, "min": -1e300, "when": _comparison(model, name)}
                        for name in every)]
    scenario = Scenario.model_validate(data)
    assert scenario.signals == every
    made = scenario_machine(scenario)
    rt = made.runtime
    for _ in range(CYCLES // 10):
        rt.step()
    tracks = [obj.name for obj in machine(rt) if obj.kind == "planar_track"]
    signals, now = RunSignals(rt, lambda: tracks), machine(rt)
    for name in every:
        assert np.array([signals.read(name)]).tobytes() == \
            np.array([now.signal(name).read()]).tobytes(), name
