"""Queued movers glide into their queue place: no stop and restart short of it (D-210).

A queue scene: movers on a rail, each sent once to a common target (some a little short of
it), at cycle 0 or a little later, with their own dynamics. Nothing else happens, so a mover
that comes to rest while it is still short of the place one gap behind its predecessor and
later moves on again has stopped for nothing ahead: the review saw such movers stop dead for
one cycle 2-27 mm short of their place. Every cycle is checked; a stop counts where the set
velocity falls to rest (|v| <= 1e-9 of the maximum), short of the place by more than
``SHORT``. Both gap control modes are drawn (D-211 for Fast pairs).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    GapControlDirection,
    GapControlMode,
)

SHORT = 0.01  #: [mm] farther than this from its place one gap behind is short of it; the
#: tracking steps (+J, 0, -J) may leave a few µm behind a predecessor that creeps off
REST = 1e-9  #: relative to the maximum velocity: at rest
MAX_CYCLES = 6000
MODES = [GapControlMode.STANDARD, GapControlMode.FAST]
XTS = {"max_velocity": 4000.0, "acceleration": 10000.0, "deceleration": 10000.0,
       "jerk": 100000.0, "max_acceleration": 10000.0, "max_deceleration": 10000.0,
       "max_jerk": 100000.0}


@st.composite
def queues(draw: st.DrawFn) -> dict:
    n = draw(st.integers(2, 7))
    gap = draw(st.sampled_from([0.0, 50.0, 100.0, 140.0]))
    spacing = draw(st.floats(gap + 1.0, gap + 400.0))
    ring = draw(st.booleans())
    length = n * spacing + draw(st.floats(0.0, 600.0))
    starts = [i * spacing + draw(st.floats(0.0, (spacing - gap) / 2)) for i in range(n)]
    movers = []
    for _ in range(n):
        acc = draw(st.floats(500.0, 20000.0))
        dec = draw(st.floats(500.0, 20000.0))
        jerk = draw(st.floats(5e3, 1e6))
        harder = st.one_of(st.just(1.0), st.floats(1.0, 2.0))  # CA may brake beyond the job
        movers.append({"max_velocity": draw(st.floats(500.0, 4000.0)), "acceleration": acc,
                       "deceleration": dec, "jerk": jerk,
                       "max_acceleration": acc * draw(harder),
                       "max_deceleration": dec * draw(harder),
                       "max_jerk": jerk * draw(harder)})
    target = max(starts) + draw(st.floats(0.0, length / 2)) if ring else \
        length - draw(st.floats(0.0, 200.0))
    # forwards only: a mover sent back into the queue would meet it head on (D-066)
    commands = [(draw(st.sampled_from([0, 0, 100, 400])), i,
                 max(target - draw(st.sampled_from([0.0, 0.0, 0.0, 150.0, 300.0])), starts[i]),
                 draw(st.floats(0.3, 1.0)), draw(st.sampled_from(MODES))) for i in range(n)]
    return {"gap": gap, "ring": ring, "length": length, "starts": starts, "movers": movers,
            "commands": sorted(commands, key=lambda c: c[0]),
            "direction": draw(st.sampled_from(list(GapControlDirection)))}


def stops_short(case: dict) -> list[tuple[str, int, float]]:
    """(mover, cycle, how far short) of every stop short of the queue place followed by a
    restart."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=case["length"], rail_is_ring=case["ring"],
                    default_gap=case["gap"], gap_control_direction=case["direction"])
    axes = []
    for i, (start, limits) in enumerate(zip(case["starts"], case["movers"], strict=True)):
        axis = rt.add_axis(f"m{i}", position=start, **limits)
        axis.power()
        group.add_axis(axis, UDINT_TO_IDENTINGROUP(i + 1))
        axes.append(axis)
    assert group.enable().done
    rest = np.array([m["max_velocity"] for m in case["movers"]]) * REST
    pending = list(case["commands"])
    moving = np.zeros(len(axes), dtype=bool)
    stopped: dict[int, tuple[int, float]] = {}  # mover -> (cycle, how far short) of its stop
    found = []
    for cycle in range(MAX_CYCLES):
        while pending and pending[0][0] <= cycle:
            _, i, target, speed, mode = pending.pop(0)
            command = group.move_absolute(axes[i], target,
                                          speed * case["movers"][i]["max_velocity"],
                                          gap_control_mode=mode)
            assert not command.error, command.message
        rt.step()
        gaps = group.gaps()
        for i, axis in enumerate(axes):
            now = abs(axis.set_velocity) > rest[i]
            if moving[i] and not now:
                stopped[i] = (cycle, gaps[group.mover_of(axis).slot] - case["gap"])
            elif now and not moving[i] and i in stopped:
                at, short = stopped.pop(i)
                if short > SHORT:
                    found.append((axis.name, at, short))
            moving[i] = now
        if cycle > 400 and not pending and group.all_axes_standing:
            break
    return found


#: the starter kit's XTS movers, Standard, a ring: m2 was sent to a queue place behind m3,
#: which stood then (too close to m4); m4 and m3 moved on, and m2 still stopped at the old
#: place, 318.8 mm short, before it went on (D-210)
_STALE_PLACE = {
    "gap": 140.0, "ring": True, "length": 3000.0,
    "starts": [606.7370218658352, 1175.1612122871188, 1692.3948368566255, 1764.9580016637153],
    "movers": [XTS] * 4, "direction": GapControlDirection.BOTH,
    "commands": [(0, i, 2454.7554385216404, 0.5, GapControlMode.STANDARD) for i in range(4)]}

#: CA braked m0 with its maximum deceleration (1098 mm/s², its job's 648); it rode that brake
#: to rest 233 mm short of its place, with the way ahead open, then started again (D-210)
_RIDDEN_BRAKE = {
    "gap": 50.0, "ring": True, "length": 1324.3355855090622,
    "starts": [76.11159017605169, 325.37996628584244, 745.4976367318523],
    "movers": [
        {"max_velocity": 3250.0346822641486, "acceleration": 16468.01172406877,
         "deceleration": 647.9330090008062, "jerk": 433034.3829109612,
         "max_acceleration": 16468.01172406877, "max_deceleration": 1098.3784470534351,
         "max_jerk": 825262.5128518789},
        {"max_velocity": 2910.5852262563544, "acceleration": 11906.847935736067,
         "deceleration": 1422.3745493080482, "jerk": 457200.5210711059,
         "max_acceleration": 11906.847935736067, "max_deceleration": 1422.3745493080482,
         "max_jerk": 457200.5210711059},
        {"max_velocity": 954.7189550594087, "acceleration": 9016.692158143369,
         "deceleration": 3400.4089251255245, "jerk": 23981.54656288501,
         "max_acceleration": 11615.439872069333, "max_deceleration": 5569.460521017886,
         "max_jerk": 25591.59121355906}],
    "direction": GapControlDirection.POSITIVE,
    "commands": [(0, 0, 806.3220710273574, 0.3900989910742548, GapControlMode.STANDARD),
                 (0, 2, 733.7841267585745, 0.6343135743049655, GapControlMode.STANDARD),
                 (201, 1, 594.2843848933636, 0.7214178747045333, GapControlMode.STANDARD)]}


#: Fast pairs of XTS movers on an open rail: m2, braked by its FAST pair check, tracked its
#: predecessor within the STANDARD room afterwards, came to rest 72 mm short of its place while
#: the predecessor drove on at 700 mm/s, then started again (D-211)
_FAST_HELD = {
    "gap": 50.0, "ring": False, "length": 3000.0,
    "starts": [322.36930660803773, 707.573955683207, 1525.770967666142, 1579.4952749235265,
               1813.187299795122, 1923.8018757964514, 1961.9531461442532],
    "movers": [XTS] * 7, "direction": GapControlDirection.BOTH,
    "commands": [(0, i, 2678.603664486685, 0.5, GapControlMode.FAST) for i in range(7)]}


@pytest.mark.parametrize("case", [_STALE_PLACE, _RIDDEN_BRAKE, _FAST_HELD],
                         ids=["stale", "ridden", "fast"])
def test_regressions_glide_into_their_place(case: dict) -> None:
    assert stops_short(case) == []


#: found by the property after the session-11 merges, on the caqueue branch as well: a ring
#: of five, m2 in a FAST pair with acceleration 500 and deceleration 8002, comes to rest
#: 0.21 mm short of its place in cycle 2434 and moves on (open, see the xfail below)
_SHORT_ON_A_RING = {'gap': 0.0,
'ring': True,
'length': 1456.2611755382122,
'starts': [0.0,
291.25223510764243,
695.8570913808504,
873.7567053229272,
1240.0854353817526],
'movers': [{'max_velocity': 500.0,
'acceleration': 500.0,
'deceleration': 500.0,
'jerk': 5000.0,
'max_acceleration': 500.0,
'max_deceleration': 500.0,
'max_jerk': 5000.0},
{'max_velocity': 500.0,
'acceleration': 500.0,
'deceleration': 500.0,
'jerk': 5000.0,
'max_acceleration': 500.0,
'max_deceleration': 500.0,
'max_jerk': 5000.0},
{'max_velocity': 3910.378066419481,
'acceleration': 500.0,
'deceleration': 8002.032216007551,
'jerk': 110780.77262274655,
'max_acceleration': 500.0,
'max_deceleration': 12493.353276645206,
'max_jerk': 139197.44765150672},
{'max_velocity': 501.0,
'acceleration': 4999.691998345082,
'deceleration': 1801.0010138187592,
'jerk': 467116.98974418675,
'max_acceleration': 4999.691998345082,
'max_deceleration': 1801.0010138187592,
'max_jerk': 467116.98974418675},
{'max_velocity': 500.0,
'acceleration': 10873.795633538013,
'deceleration': 500.0,
'jerk': 653128.0434721553,
'max_acceleration': 10873.795633538013,
'max_deceleration': 500.0,
'max_jerk': 653128.0434721553}],
'commands': [(0,
0,
1740.0854353817526,
0.6016413192156767,
GapControlMode.STANDARD),
(0, 1, 1740.0854353817526, 0.4, GapControlMode.STANDARD),
(0, 2, 1740.0854353817526, 0.3, GapControlMode.FAST),
(0,
3,
1590.0854353817526,
0.6923214194989937,
GapControlMode.STANDARD),
(0, 4, 1740.0854353817526, 0.3, GapControlMode.STANDARD)],
'direction': GapControlDirection.POSITIVE}


@pytest.mark.xfail(strict=True, reason="open (D-210): a FAST mover with acceleration far below "
                   "its deceleration still stops 0.21 mm short of its place on this ring")
def test_a_fast_mover_on_a_ring_glides_into_its_place() -> None:
    assert stops_short(_SHORT_ON_A_RING) == []


@settings(deadline=None, max_examples=30)
@given(case=queues())
@example(case=_STALE_PLACE)
def test_queued_movers_never_stop_short_of_their_place(case: dict) -> None:
    assert stops_short(case) == []


@pytest.mark.slow
@settings(deadline=None, max_examples=2000)
@given(case=queues())
def test_queued_movers_never_stop_short_over_many_cases(case: dict) -> None:
    assert stops_short(case) == []
