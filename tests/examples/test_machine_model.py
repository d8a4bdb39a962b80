"""One signal vocabulary (issue: the machine model; D-226, D-227, D-228): for every shipped
example, the trace and the viewer expose exactly the signals of the machine model, and name
its objects with the model's kinds.

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
