"""The System contract (kernel/system.py): how systems join the runtime, the order they run
in, and identities no other system shifts."""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.axis.system import AxisSystem
from openmotion.coordinated.group import AxesGroup
from openmotion.core.errors import ConfigError
from openmotion.kernel.runtime import CyclicRuntime
from openmotion.planar import MC_PlanarMover
from openmotion.planar.system import PlanarSystem
from openmotion.transport import CaGroup


class Recorder:
    """A system that writes down each phase it is called in."""

    def __init__(self, name: str, log: list[tuple[str, str, int]], monitor: bool) -> None:
        self.name = name
        self._log = log
        if monitor:
            self.monitor = lambda now: log.append((name, "monitor", round(now * 1000)))

    def advance(self, now: float) -> None:
        self._log.append((self.name, "advance", round(now * 1000)))

    def objects(self) -> tuple[()]:
        return ()


def test_systems_run_in_the_order_added_motion_phase_before_drive_phase():
    rt = CyclicRuntime()
    log: list[tuple[str, str, int]] = []
    first = rt.add_system(Recorder("a", log, monitor=True))
    rt.add_system(Recorder("b", log, monitor=False))
    rt.add_system(Recorder("c", log, monitor=True))
    rt.add_program(lambda: log.append(("program", "", rt.cycle)))
    rt.step()
    assert log == [("program", "", 1), ("a", "advance", 1), ("b", "advance", 1),
                   ("c", "advance", 1), ("a", "monitor", 1), ("c", "monitor", 1)]
    assert [system.name for system in rt.systems] == ["a", "b", "c"]
    assert rt.systems[0] is first


def test_the_axes_are_the_first_system_and_every_other_system_joins_after_them():
    rt = om.Runtime()
    x, y = rt.add_axis("x"), rt.add_axis("y")
    group = AxesGroup(rt, "g")
    ca = CaGroup(rt, "ca")
    mover = MC_PlanarMover(rt)
    systems = rt.systems
    assert isinstance(systems[0], AxisSystem) and systems[0] is rt.axis_system
    assert systems[0].objects() == (x, y)
    assert systems[1:3] == (group, ca)
    assert isinstance(systems[3], PlanarSystem) and mover in systems[3].objects()
    assert group.objects() == (group,) and ca.objects() == (ca,)


def test_a_bad_system_is_refused_and_the_runtime_runs_on():
    rt = om.Runtime()
    x = rt.add_axis("x")
    with pytest.raises(ConfigError, match=r"no advance\(now\) and objects\(\)"):
        rt.add_system(object())  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="added already"):
        rt.add_system(rt.axis_system)
    assert len(rt.systems) == 1
    x.power()
    rt.run_until(x.move_absolute(5.0, velocity=100.0), timeout=1.0)
    assert x.set_position == 5.0


def test_the_systems_view_cannot_change_the_runtime():
    rt = om.Runtime()
    with pytest.raises(AttributeError):
        rt.systems.append(object())  # type: ignore[attr-defined]
    assert len(rt.systems) == 1


def test_a_ca_group_number_does_not_depend_on_the_systems_made_before_it():
    """The OID was 16#05030000 + the count of all systems: an axes group made first
    shifted it. Now each kind counts its own objects."""
    plain, busy = om.Runtime(), om.Runtime()
    AxesGroup(busy, "g")
    MC_PlanarMover(busy)
    assert CaGroup(plain, "ca").oid == CaGroup(busy, "ca").oid == 0x05030001
    assert CaGroup(busy, "ca2").oid == 0x05030002


def test_serial_counts_each_kind_on_its_own():
    rt = CyclicRuntime()
    assert [rt.serial("a"), rt.serial("b"), rt.serial("a")] == [1, 1, 2]


def test_rewind_after_set_up_cycles_starts_the_first_axis_plan_at_zero():
    """Set-up cycles (a scenario enabling planar objects) run before t = 0. After the clock
    goes back, an axis made then starts moving in cycle 1 and never backwards: the first
    sample was -1.7e-6 mm before, a plan placed at the end of the set-up (D-231)."""
    rt = om.Runtime()
    rt.run(0.002)
    rt.rewind()
    assert (rt.cycle, rt.now) == (0, 0.0)
    belt = rt.add_axis("belt")
    belt.power()
    belt.move_velocity(400.0, acceleration=1000.0, deceleration=1000.0, jerk=10000.0)
    rt.step()
    assert belt.set_position == pytest.approx(10000.0 * 0.001**3 / 6, rel=1e-9)


def test_rewind_is_refused_once_an_axis_exists_and_the_clock_stays():
    rt = om.Runtime()
    rt.add_axis("x")
    rt.run(0.003)
    with pytest.raises(ConfigError, match="before the first axis is made; there are x"):
        rt.rewind()
    assert rt.cycle == 3
    rt.step()
    assert rt.cycle == 4


def test_axes_groups_are_numbered_in_their_own_count():
    """Each kind counts its own objects (D-223): axes groups 1, 2 whatever else exists; the
    machine model shows that number as the group's id."""
    from openmotion.kernel.model import machine

    rt = om.Runtime()
    CaGroup(rt, "ca")
    first, second = AxesGroup(rt, "g1"), AxesGroup(rt, "g2")
    assert (first.group_id, second.group_id) == (1, 2)
    ids = {obj.name: obj.id for obj in machine(rt) if obj.kind == "axes_group"}
    assert ids == {"g1": 1, "g2": 2}
