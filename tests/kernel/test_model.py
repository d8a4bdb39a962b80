"""The machine model (kernel/model.py, D-226): one description of every object, its signals
and its commands, declared next to each class and read by every edge."""

from __future__ import annotations

import ast
import math
from enum import IntEnum
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import pytest

import openmotion as om
from openmotion.kernel import model
from openmotion.kernel.model import (
    REQUIRED,
    Input,
    Kind,
    MachineObject,
    SignalSpec,
    derive_commands,
    kind_of,
    machine,
)
from openmotion.planar import MC_PlanarEnvironment, MC_PlanarGroup, MC_PlanarMover, Pose
from openmotion.planar.parts import Part, PartLayout, PartPosition
from openmotion.trace import TraceRecorder
from openmotion.transport import CaGroup
from openmotion.transport.group import UDINT_TO_IDENTINGROUP

SYSTEM_PACKAGES = ("axis", "plcopen", "transport", "coordinated", "planar")


def ca_runtime() -> tuple[om.Runtime, CaGroup]:
    rt = om.Runtime()
    rt.add_axis("free")
    a, b = rt.add_axis("a"), rt.add_axis("b", position=300.0)
    group = CaGroup(rt, "xts", rail_length=3000.0)
    for ident, axis in enumerate((a, b), start=1):
        axis.power()
        assert group.add_axis(axis, UDINT_TO_IDENTINGROUP(ident)).done
    group.enable()
    return rt, group


def test_the_kernel_model_imports_no_system_package() -> None:
    """D-226: the model is the kernel's; it finds kinds through the objects (``MACHINE``)."""
    tree = ast.parse(Path(model.__file__).read_text(encoding="utf-8"))
    imported = [node.module or "" for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)]
    imported += [alias.name for node in ast.walk(tree) if isinstance(node, ast.Import)
                 for alias in node.names]
    assert not [name for name in imported
                if name.split(".")[:2] in ([["openmotion", pkg] for pkg in SYSTEM_PACKAGES])]


def test_every_object_in_system_order_with_kind_id_parent() -> None:
    """Axes first (creation order), then each system as it was added; a CA group's movers
    follow it in CA order, with the group as their parent and their axis's id."""
    rt, _ = ca_runtime()
    found = [(obj.kind, obj.name, obj.id, obj.parent) for obj in machine(rt)]
    assert found[:3] == [("axis", "free", 1, ""), ("axis", "a", 2, ""), ("axis", "b", 3, "")]
    assert found[3][:2] == ("ca_group", "xts") and found[3][2] > 0
    assert found[4:] == [("ca_mover", "b", 3, "xts"), ("ca_mover", "a", 2, "xts")]


def test_planar_parts_are_children_of_their_environment() -> None:
    layout = PartLayout([0x01010010], [Part(0x01010020, [(0.0, 0.0), (240.0, 0.0)],
                                            [PartPosition(0x01010010, Pose())])])
    rt = om.Runtime()
    MC_PlanarEnvironment(rt, layout=layout)
    MC_PlanarMover(rt, name="m")
    MC_PlanarGroup(rt, "field")
    found = [(obj.kind, obj.name, obj.parent) for obj in machine(rt)]
    assert found == [("planar_environment", "environment", ""),
                     ("planar_part", "part 16#01010020", "environment"),
                     ("planar_mover", "m", ""), ("planar_group", "field", "")]


def test_signals_read_what_the_trace_records_bit_for_bit() -> None:
    """One snapshot per cycle: ``Signal.read()`` after a cycle is the trace's value."""
    rt, _ = ca_runtime()
    rt.axes["free"].power()
    move = rt.axes["free"].move_absolute(40.0, velocity=100.0)
    names = list(machine(rt).signals())
    recorder = TraceRecorder(rt, names)
    rt.add_observer(recorder)
    rt.run(0.05)
    row = recorder.trace.data[-1, 1:]
    now = [signal.read() for signal in machine(rt).signals().values()]
    assert row.tobytes() == np.array(now).tobytes()
    assert move.busy and rt.axes["free"].set_velocity > 0.0


def test_a_signal_declares_unit_dtype_and_reads_a_float() -> None:
    rt, _ = ca_runtime()
    shown = machine(rt)
    state = shown.signal("free.state")
    disabled = float(om.AxisState.DISABLED)
    assert (state.unit, state.dtype, state.read()) == ("", om.AxisState, disabled)
    gap = shown.find("a", kind="ca_mover").signal("gap")
    assert (gap.unit, gap.dtype, gap.read()) == ("mm", float, 300.0)
    assert shown.signal("free.set_position").spec.actual == "position"


@pytest.mark.parametrize(("name", "message"), [
    ("free.speed", r"'free': no signal 'speed'; one of set_position, set_velocity, "),
    ("free.positon", r"no signal 'positon' \(did you mean 'position'\?\)"),
    ("nobody.position", r"no object 'nobody'; one of free, a, b, xts"),
    ("free", r"'free' is not '<object>.<signal>'"),
])
def test_an_unknown_signal_is_a_config_error_naming_the_choices(name: str, message: str) -> None:
    rt, _ = ca_runtime()
    shown = machine(rt)
    with pytest.raises(om.ConfigError, match=message):
        shown.signal(name)
    assert shown.signal("free.position").read() == 0.0  # the model stays usable


def test_an_object_names_its_signals_and_commands_when_one_is_unknown() -> None:
    rt, _ = ca_runtime()
    axis = machine(rt).find("free")
    with pytest.raises(om.ConfigError, match=r"axis 'free': no signal 'gap'; one of set_pos"):
        axis.signal("gap")  # a CA mover's signal: the free axis is in no group
    with pytest.raises(om.ConfigError, match=r"no command 'move_absolut' \(did you mean "
                                              r"'move_absolute'\?\); one of reset, "):
        axis.command("move_absolut")
    with pytest.raises(om.ConfigError, match="no object 'q'"):
        machine(rt).find("q")


def test_commands_come_from_the_methods_with_their_inputs() -> None:
    """A command is a public method returning the kind's command handle; its inputs are the
    signature's, with the unit its name gives (UNITS) and an enum's members as choices."""
    rt, _ = ca_runtime()
    move = machine(rt).find("free").command("move_absolute")
    inputs = {put.name: put for put in move.inputs}
    assert list(inputs) == ["position", "velocity", "acceleration", "deceleration", "jerk",
                            "buffer_mode"]
    assert inputs["position"] == Input("position", "InputValue", "mm", REQUIRED)
    assert inputs["jerk"].unit == "mm/s³" and not inputs["jerk"].required
    assert inputs["buffer_mode"].default is om.BufferMode.ABORTING
    assert inputs["buffer_mode"].choices == tuple(mode.name for mode in om.BufferMode)
    assert "MC_MoveAbsolute" in move.doc
    names = [command.name for command in machine(rt).find("xts").commands]
    assert {"enable", "move_absolute", "halt_axis", "gear_in_pos"} <= set(names)
    mover = [command.name for command in MC_PlanarMover.MACHINE.commands(MC_PlanarMover)]
    assert {"move_to_position", "join_track", "enable", "reset"} <= set(mover)
    assert "power" not in names and "restart" not in [c.name for c in
                                                       machine(rt).find("free").commands]


def test_a_command_starts_through_the_model_and_follows_the_handshake() -> None:
    rt, _ = ca_runtime()
    axis = rt.axes["free"]
    axis.power()
    move = machine(rt).find("free").command("move_absolute")
    with pytest.raises(TypeError, match=r"move_absolute has no input 'positon' \(did you mean "
                                        r"'position'\?\)"):
        move.start(positon=10.0, velocity=50.0)
    command = move.start(position=10.0, velocity=50.0)
    rt.run_until(command, timeout=2.0)
    assert command.done and axis.set_position == 10.0


def test_derive_commands_reads_signatures_in_definition_order() -> None:
    class Speed(IntEnum):
        SLOW = 0
        FAST = 1

    class Handle:
        pass

    class Base:
        def enable(self) -> Handle:
            return Handle()

    class Thing(Base):
        def go(self, target_position: float, speed: Speed = Speed.SLOW, **more: Any) -> Handle:
            """Go there.

            More text."""
            return Handle()

        def look(self) -> float:  # a query, no command
            return 0.0

        def _hidden(self) -> Handle:
            return Handle()

    found = derive_commands(Thing, ["Handle"], {"go.target_position": "°"})
    assert [command.name for command in found] == ["enable", "go"]
    (target, speed) = found[1].inputs
    assert (target.unit, target.dtype, target.required) == ("°", "float", True)
    assert speed.choices == ("SLOW", "FAST") and found[1].doc == "Go there."


def test_a_kind_declares_each_signal_once() -> None:
    spec = SignalSpec("level", "mm", float, lambda obj: 1.0)
    with pytest.raises(om.ConfigError, match="signal is declared twice"):
        Kind("tank", signals=(spec, spec))
    with pytest.raises(om.ConfigError, match=r"tank: no signal 'lvl' \(did you mean 'level'"):
        Kind("tank", signals=(spec,)).signal("lvl")


def test_a_signal_declared_next_to_a_class_reaches_the_trace() -> None:
    """Adding a signal touches only the object: a kind of one's own is recorded at once."""
    class Tank:
        MACHINE: ClassVar[Kind] = Kind(
            "tank", signals=(SignalSpec("level", "mm", float, lambda tank: tank.level),),
            identify=lambda tank: 7)
        name = "tank"
        level = 2.5

    tank = Tank()
    assert kind_of(tank) is Tank.MACHINE and kind_of(object()) is None
    shown = Tank.MACHINE.describe(tank)
    assert isinstance(shown, MachineObject) and (shown.kind, shown.id) == ("tank", 7)
    rt = om.Runtime()
    recorder = TraceRecorder(rt, ["tank.level"], objects=[tank])
    recorder.sample(rt)
    assert recorder.trace["tank.level"].tolist() == [2.5]
    assert recorder.trace.layout["objects"] == {"tank": "tank"}


def test_a_ca_signal_reads_nan_once_its_axis_leaves_the_group() -> None:
    """D-227: a CA mover's signals read the axis's group when read."""
    rt, group = ca_runtime()
    gap = machine(rt).find("a", kind="ca_mover").signal("gap")
    assert gap.read() == 300.0
    group.disable()
    rt.step()
    assert group.remove_axis(UDINT_TO_IDENTINGROUP(1)).done
    rt.step()
    assert math.isnan(gap.read())
