"""The CA group's Default Velocity, Acceleration, Deceleration and Jerk (TF5410 §6): they
serve standby gap control only, the moves of movers without a command."""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.transport import UDINT_TO_IDENTINGROUP, CaGroup


def give_way(**defaults: float) -> dict:
    """Standby gap control, default gap 500: the rear mover stands 20 mm behind the front
    one when the group is enabled, so it moves back to 500 on its own. Its peaks."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_is_ring=False, rail_length=10000.0,
                    standby_gap_control=True, default_gap=500.0, **defaults)
    front = rt.add_axis("front", position=1000.0)
    rear = rt.add_axis("rear", position=980.0)
    for i, axis in enumerate((front, rear)):
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
    group.enable()
    peak = {"velocity": 0.0, "acceleration": 0.0, "deceleration": 0.0, "jerk": 0.0}
    before = 0.0
    while not (rear.set_position <= 500.0 + 1e-9 and rear.set_velocity == 0.0):
        rt.step()
        a = rear.set_acceleration  # moving backwards: speeding up is a < 0
        peak["velocity"] = max(peak["velocity"], -rear.set_velocity)
        peak["acceleration"] = max(peak["acceleration"], -a)
        peak["deceleration"] = max(peak["deceleration"], a)
        peak["jerk"] = max(peak["jerk"], abs(a - before) / rt.cycle_time)
        before = a
        assert rt.now < 20.0
    peak["position"] = rear.set_position
    return peak


def test_the_defaults_of_the_manual() -> None:
    """150 mm/s, 1000 mm/s², 1000 mm/s², 10000 mm/s³ (§6 defaults)."""
    assert give_way() == {"velocity": pytest.approx(150.0), "acceleration": pytest.approx(1000.0),
                          "deceleration": pytest.approx(1000.0), "jerk": pytest.approx(1e4),
                          "position": pytest.approx(500.0)}


def test_each_default_dynamics_parameter_shapes_the_standby_move() -> None:
    """100 mm/s, 400 mm/s² speeding up, 200 mm/s² slowing down, 2000 mm/s³: each peak is
    its own parameter's value."""
    peak = give_way(default_velocity=100.0, default_acceleration=400.0,
                    default_deceleration=200.0, default_jerk=2000.0)
    assert peak == {"velocity": pytest.approx(100.0), "acceleration": pytest.approx(400.0),
                    "deceleration": pytest.approx(200.0), "jerk": pytest.approx(2000.0),
                    "position": pytest.approx(500.0)}
