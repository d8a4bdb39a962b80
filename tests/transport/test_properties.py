"""Properties of gap control over random rails, movers, dynamics and command streams.

For every generated case and every cycle: no setpoint gap below the gap, no mover beyond its
own limits. Once the commands stop coming and the movers come to rest, every command has
ended Done, or its mover waits exactly one gap behind the mover in its way (its queue
position, docs/collision-avoidance.md).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.core.enums import BufferMode
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    GapControlDirection,
    GapControlMode,
    MoverTemplate,
    StarterKitGeometry,
)

SETTLE_CYCLES = 30_000
QUEUE_TOLERANCE = 1e-9  #: [mm] a queued mover waits exactly one gap behind (D-066)


@st.composite
def cases(draw: st.DrawFn) -> dict:
    n = draw(st.integers(2, 6))
    gap = draw(st.floats(0.0, 150.0))
    spacing = draw(st.floats(gap + 1.0, gap + 400.0))
    ring = draw(st.booleans())
    length = n * spacing + (0.0 if ring else 0.0)
    starts = [i * spacing + draw(st.floats(0.0, (spacing - gap) / 2)) for i in range(n)]
    movers = []
    for _ in range(n):
        acc = draw(st.floats(500.0, 20000.0))
        dec = draw(st.floats(500.0, 20000.0))
        jerk = draw(st.floats(5e3, 1e6))
        movers.append({"max_velocity": draw(st.floats(500.0, 4000.0)),
                       "acceleration": acc, "deceleration": dec, "jerk": jerk,
                       "max_acceleration": acc * draw(st.floats(1.0, 2.0)),
                       "max_deceleration": dec * draw(st.floats(1.0, 2.0)),
                       "max_jerk": jerk * draw(st.floats(1.0, 2.0))})
    commands = draw(st.lists(st.tuples(
        st.integers(0, 1500),  # cycle
        st.integers(0, n - 1),  # mover
        st.sampled_from(["absolute", "relative", "halt"]),
        st.floats(-1.0, 1.0),  # target or distance, in half rail lengths
        st.floats(0.3, 1.0),  # velocity, fraction of the mover's maximum
        st.sampled_from([BufferMode.ABORTING, BufferMode.BUFFERED]),
        st.sampled_from([GapControlMode.STANDARD, GapControlMode.FAST]),
    ), min_size=1, max_size=12))
    # geo-compensation on a ring: some movers measure their gap on a TCP path (D-073)
    y_shifts = [draw(st.sampled_from([0.0, 30.0, 100.0])) for _ in range(n)] \
        if ring and draw(st.booleans()) else None
    return {"n": n, "gap": gap, "ring": ring, "length": max(length, n * spacing),
            "starts": starts, "movers": movers, "commands": sorted(commands,
                                                                    key=lambda c: c[0]),
            "y_shifts": y_shifts}


def _run(case: dict, liveness: bool = True) -> None:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=case["length"], rail_is_ring=case["ring"],
                    default_gap=case["gap"], gap_control_direction=GapControlDirection.BOTH)
    axes = []
    for i, (start, limits) in enumerate(zip(case["starts"], case["movers"], strict=True)):
        axis = rt.add_axis(f"m{i}", position=start, **limits)
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
        axes.append(axis)
    if case.get("y_shifts"):
        _compensate(group, axes, case["y_shifts"])
    assert group.enable().done
    gap, length = case["gap"], case["length"]
    rows = np.array([a.row for a in axes])
    k = rt.axis_system.kernel
    vmax = np.array([m["max_velocity"] for m in case["movers"]])
    amax = np.array([max(m["max_acceleration"], m["max_deceleration"]) for m in case["movers"]])
    jmax = np.array([m["max_jerk"] for m in case["movers"]])
    pending = list(case["commands"])
    issued: list[tuple[om.Axis, om.Command]] = []
    last = pending[-1][0]

    def check() -> None:
        gaps = group.gaps()
        assert gaps.min() >= gap - 1e-9, f"gap {gaps.min()} below {gap} at t={rt.now}"
        v, a, j = k.set_v[rows], k.set_a[rows], k.set_j[rows]
        assert np.all(np.abs(v) <= vmax * (1 + 1e-9)), f"velocity {v} beyond {vmax}"
        assert np.all(np.abs(a) <= amax * (1 + 1e-9)), f"acceleration {a} beyond {amax}"
        assert np.all(np.abs(j) <= jmax * (1 + 1e-9)), f"jerk {j} beyond {jmax}"

    quiet = 0
    for cycle in range(last + SETTLE_CYCLES):
        while pending and pending[0][0] <= cycle:
            _, i, kind, amount, speed, buffer_mode, mode = pending.pop(0)
            axis = axes[i]
            velocity = speed * case["movers"][i]["max_velocity"]
            if kind == "absolute":
                command = group.move_absolute(axis, axis.set_position + amount * length / 2,
                                              velocity, buffer_mode=buffer_mode,
                                              gap_control_mode=mode)
            elif kind == "relative":
                command = group.move_relative(axis, amount * length / 2, velocity,
                                              buffer_mode=buffer_mode, gap_control_mode=mode)
            else:
                command = group.halt_axis(axis, gap_control_mode=mode)
            assert not command.error, command.message
            issued.append((axis, command))
        rt.step()
        check()
        quiet = quiet + 1 if group.all_axes_standing else 0
        if cycle > last and (quiet >= 10 or not liveness):  # a buffered command may follow
            break
    if liveness:
        assert group.all_axes_standing, "the movers never came to rest"
        _assert_ended_or_queued(group, issued, gap)


def _compensate(group: CaGroup, axes: list[om.Axis], y_shifts: list[float]) -> None:
    """A starter-kit geometry on the ring (curves of R = length / 10) and a template per
    y-shift; movers with y > 0 register theirs, so group.gaps() gives their TCP gap."""
    geo = group.tracks.geo
    geo.set_geometry(StarterKitGeometry(rail_length=group.parameters.rail_length,
                                        curve_radius=group.parameters.rail_length / 10.0))
    for template_id, y in enumerate(sorted(set(y_shifts)), 1):
        geo.add_template(MoverTemplate(template_id, y_shift=y))
        for axis, shift in zip(axes, y_shifts, strict=True):
            if shift == y and y > 0.0:
                assert geo.register_compensation(axis, template_id).done


def _assert_ended_or_queued(group: CaGroup, issued: list, gap: float) -> None:
    gaps = group.gaps()
    for axis, command in issued:
        if command.finished:
            continue
        slot = group.mover_of(axis).slot
        mover = group.movers[slot]
        if not command.active:  # buffered behind a command that waits in a queue
            assert mover.job is not None and mover.job.command.active, command
            continue
        forward = mover.job.target >= axis.set_position
        if forward:
            assert abs(gaps[slot] - gap) <= QUEUE_TOLERANCE, \
                f"{axis.name} stopped short of its target {mover.job.target} with gap " \
                f"{gaps[slot]} to its predecessor"
        else:
            behind = [m for m in group.movers if group.predecessor(m.axis) is axis]
            assert behind and abs(gaps[behind[0].slot] - gap) <= QUEUE_TOLERANCE, \
                f"{axis.name} stopped short of its target {mover.job.target}"


#: a case where an earlier gap filter undershot by 7e-5 mm (slow run; fixed with the FAST
#: predecessor rule of D-060 and the no-turning-back rule of D-066)
_UNDERSHOT = {
    "n": 4, "gap": 38.25129701141893, "ring": False, "length": 1166.796204328518,
    "starts": [42.34603591747109, 291.6990510821295, 583.398102164259, 875.0971532463884],
    "movers": [
        {"max_velocity": 500.0, "acceleration": 500.0, "deceleration": 500.0, "jerk": 5000.0,
         "max_acceleration": 500.0, "max_deceleration": 500.0, "max_jerk": 9173.023065073252},
        {"max_velocity": 500.0, "acceleration": 500.0, "deceleration": 9913.676699625234,
         "jerk": 20000.0, "max_acceleration": 500.0, "max_deceleration": 9913.676699625234,
         "max_jerk": 30889.85761769308},
        *[{"max_velocity": 500.0, "acceleration": 500.0, "deceleration": 500.0,
           "jerk": 5000.0, "max_acceleration": 500.0, "max_deceleration": 500.0,
           "max_jerk": 5000.0}] * 2],
    "commands": [
        (0, 0, "absolute", 0.0, 0.5959573165341905, BufferMode.BUFFERED,
         GapControlMode.STANDARD),
        (0, 0, "absolute", 0.0, 1 / 3, BufferMode.ABORTING, GapControlMode.STANDARD),
        (0, 0, "absolute", 0.0, 0.3174510466491823, BufferMode.ABORTING,
         GapControlMode.STANDARD),
        (0, 0, "absolute", 0.0, 0.3, BufferMode.ABORTING, GapControlMode.STANDARD),
        (0, 0, "absolute", 0.5, 0.7855930621910687, BufferMode.ABORTING, GapControlMode.FAST),
        (6, 1, "absolute", -1.0, 1.0, BufferMode.ABORTING, GapControlMode.STANDARD),
        (1448, 0, "absolute", 0.0, 1.0, BufferMode.ABORTING, GapControlMode.STANDARD)]}


#: found by the 10 000-case run of session 3: the successor's new command turned its pair
#: from FAST to STANDARD while the pair was safe only in the FAST sense (the predecessor
#: backing towards it); the pair now stays FAST until it is STANDARD-safe (D-106)
_FAST_TO_STANDARD = {'n': 3,
     'gap': 29.881108204132342,
     'ring': False,
     'length': 915.642163575546,
     'starts': [0.0, 305.214054525182, 610.428109050364],
     'movers': [{'max_velocity': 500.0,
       'acceleration': 500.0,
       'deceleration': 500.0,
       'jerk': 5000.0,
       'max_acceleration': 500.0,
       'max_deceleration': 500.0,
       'max_jerk': 5000.0},
      {'max_velocity': 3999.9999999999995,
       'acceleration': 8822.57547952765,
       'deceleration': 8844.53315544077,
       'jerk': 218929.60617905296,
       'max_acceleration': 8822.57547952765,
       'max_deceleration': 13266.799733161155,
       'max_jerk': 415147.29463367},
      {'max_velocity': 3400.0038856891138,
       'acceleration': 6930.224499868551,
       'deceleration': 19932.157954585196,
       'jerk': 50000.0,
       'max_acceleration': 6930.224499868551,
       'max_deceleration': 19932.157954585196,
       'max_jerk': 75000.0}],
     'commands': [(0,
          0,
          'absolute',
          0.0,
          0.8025756298406699,
          BufferMode.ABORTING,
          GapControlMode.STANDARD),
      (0,
          0,
          'absolute',
          0.0,
          0.765451894222625,
          BufferMode.ABORTING,
          GapControlMode.STANDARD),
      (0,
          0,
          'absolute',
          0.0,
          1.0,
          BufferMode.ABORTING,
          GapControlMode.STANDARD),
      (0,
          0,
          'absolute',
          0.0,
          1.0,
          BufferMode.ABORTING,
          GapControlMode.STANDARD),
      (134,
          1,
          'absolute',
          0.8744512566737863,
          1.0,
          BufferMode.ABORTING,
          GapControlMode.STANDARD),
      (164,
          2,
          'absolute',
          -0.9000949415938382,
          0.9135531927935063,
          BufferMode.ABORTING,
          GapControlMode.STANDARD),
      (308,
          1,
          'absolute',
          -0.38271451310611926,
          1.0,
          BufferMode.ABORTING,
          GapControlMode.FAST),
      (723,
          1,
          'absolute',
          0.0,
          1.0,
          BufferMode.ABORTING,
          GapControlMode.STANDARD),
      (948,
          0,
          'absolute',
          0.0,
          1.0,
          BufferMode.ABORTING,
          GapControlMode.STANDARD)],
     'y_shifts': None}


@settings(deadline=None, max_examples=40)
@given(case=cases())
@example(case=_UNDERSHOT)
@example(case=_FAST_TO_STANDARD)
def test_gaps_and_limits_hold_every_cycle(case: dict) -> None:
    _run(case, liveness=False)


@pytest.mark.slow
@settings(deadline=None, max_examples=10_000)
@given(case=cases())
def test_gaps_and_limits_hold_over_many_cases(case: dict) -> None:
    _run(case, liveness=False)


_SOFT = {"max_velocity": 500.0, "acceleration": 500.0, "deceleration": 500.0, "jerk": 5000.0,
         "max_acceleration": 500.0, "max_deceleration": 500.0, "max_jerk": 5000.0}
#: head on: m1 forwards and m2 backwards into the same room, which only m1 may take (D-066)
_HEAD_ON = {
    "n": 4, "gap": 0.0, "ring": False, "length": 4.0, "starts": [0.0, 1.0, 2.0, 3.0],
    "movers": [_SOFT, {**_SOFT, "jerk": 53549.0, "max_jerk": 53549.0},
               {**_SOFT, "max_jerk": 8750.0}, _SOFT],
    "commands": [(0, 1, "absolute", 1.0, 1.0, BufferMode.ABORTING, GapControlMode.STANDARD),
                 (0, 2, "absolute", -1.0, 1.0, BufferMode.ABORTING, GapControlMode.STANDARD)]}


@settings(deadline=None, max_examples=25)
@given(case=cases())
@example(case=_HEAD_ON)
def test_commands_end_or_wait_in_their_queue(case: dict) -> None:
    _run(case)


@pytest.mark.slow
@settings(deadline=None, max_examples=2000)
@given(case=cases())
def test_commands_end_or_wait_in_their_queue_over_many_cases(case: dict) -> None:
    _run(case)
