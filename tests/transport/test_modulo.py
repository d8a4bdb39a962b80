"""T14: modulo targets of MC_MoveAbsoluteCA on a ring (TF5410 §11.3, §9.1.2.2; digest D4.2).

The table's rows with rail length M = 100 (the movers' modulo factor) and tolerance window
T = 1, run as moves of a group member: the end is start + the relative path. The three ✱ rows
are errata of the manual (EN and DE alike): their printed absolute end does not equal start +
relative path; the relative path is taken as right (digest D8 item 12).
"""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    MC_MoveAbsoluteCA,
    ModuloDirection,
    ST_MoveAbsoluteCAOptions,
)

ErrorId = om.ErrorId
P, N, S = ModuloDirection.POSITIVE, ModuloDirection.NEGATIVE, ModuloDirection.SHORTEST_WAY
INVALID_TARGET, INVALID_TURNS = ErrorId.INVALID_TARGET_POSITION, ErrorId.INVALID_ADDITIONAL_TURNS

#: direction, start, target, additional turns, relative path (or the error), manual's end
TABLE = [
    (P, 110.0, 10.0, 0, 0.0, 110.0),
    (P, 110.9, 10.0, 0, -0.9, 110.0),
    (P, 112.0, 10.0, 0, 98.0, 110.0),  # ✱ erratum: 112 + 98 = 210
    (P, 95.0, 10.0, 0, 15.0, 110.0),
    (P, 110.0, 110.0, 0, INVALID_TARGET, None),
    (P, 110.0, 10.0, 3, 300.0, 410.0),
    (P, 110.9, 10.0, 3, 299.1, 410.0),
    (P, 112.0, 10.0, 3, 398.0, 410.0),  # ✱ erratum: 112 + 398 = 510
    (P, 95.0, 10.0, 3, 315.0, 410.0),
    (P, 110.0, 110.0, 3, INVALID_TARGET, None),
    (N, 110.0, 10.0, 0, 0.0, 110.0),
    (N, 109.9, 10.0, 0, 0.1, 110.0),
    (N, 108.0, 10.0, 0, -98.0, 10.0),
    (N, 95.0, 10.0, 0, -85.0, 10.0),
    (N, 110.0, 110.0, 0, INVALID_TARGET, None),
    (N, 410.0, 10.0, 3, -300.0, 110.0),
    (N, 409.9, 10.0, 3, -299.9, 110.0),
    (N, 408.0, 10.0, 3, -398.0, 10.0),
    (N, 495.0, 10.0, 3, -385.0, 10.0),  # ✱ erratum: 495 - 385 = 110
    (N, 410.0, 110.0, 3, INVALID_TARGET, None),
    (S, 440.0, 50.0, 0, 10.0, 450.0),
    (S, 440.0, 10.0, 0, -30.0, 410.0),
    (S, 440.0, 50.0, 1, INVALID_TURNS, None),
]
ERRATA = {2, 7, 18}  #: rows whose printed absolute end is wrong


def member(start: float, rail_length: float = 100.0, **parameters) -> tuple[om.Runtime, CaGroup,
                                                                             om.Axis]:
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=rail_length, default_gap=10.0, **parameters)
    axis = rt.add_axis("m1", position=start, max_velocity=1000.0, max_deceleration=20000.0,
                       max_jerk=1.0e6, modulo_tolerance_window=1.0)
    axis.power()
    assert group.add_axis(axis, UDINT_TO_IDENTINGROUP(1)).done
    assert group.enable().done
    return rt, group, axis


def row_id(row: tuple) -> str:
    direction, start, target, turns, relative, _ = row
    mark = "-erratum" if TABLE.index(row) in ERRATA else ""
    return f"{direction.name}-{start:g}-to-{target:g}-turns{turns}{mark}"


def test_the_table_has_the_manuals_23_rows():
    assert len(TABLE) == 23
    assert sum(isinstance(row[4], ErrorId) for row in TABLE) == 5


@pytest.mark.parametrize("row", TABLE, ids=[row_id(row) for row in TABLE])
def test_move_modulo_matches_manual_table(row):
    direction, start, target, turns, relative, printed_end = row
    rt, group, axis = member(start)
    command = group.move_absolute(axis, target, 1000.0, direction=direction,
                                  additional_turns=turns)
    if isinstance(relative, ErrorId):
        assert command.error and command.error_id is relative
        return
    rt.run_until(lambda: command.done, timeout=5.0)
    end = start + relative
    assert axis.set_position == pytest.approx(end, abs=1e-9)
    assert axis.set_position % 100.0 == pytest.approx(target % 100.0, abs=1e-9)
    if TABLE.index(row) in ERRATA:
        assert end != printed_end
    else:
        assert end == pytest.approx(printed_end)


def test_additional_turns_example_of_the_options():
    """§9.1.2.2: modulo factor 360, start 5, two full turns then stop at 10: end 730."""
    rt, _, axis = member(5.0, rail_length=360.0)
    move = MC_MoveAbsoluteCA(axis)
    move(execute=True, position=10.0, velocity=1000.0, direction=P,
         options=ST_MoveAbsoluteCAOptions(additional_turns=2))
    while not move.done:
        assert move.busy
        rt.step()
        move()
    assert axis.set_position == pytest.approx(730.0)


def test_a_modulo_direction_on_an_open_rail_is_an_error():
    _, _, axis = member(5.0, rail_length=360.0, rail_is_ring=False)
    move = MC_MoveAbsoluteCA(axis)
    move(execute=True, position=10.0, velocity=100.0, direction=P)
    assert move.error and move.error_id is ErrorId.MODULO_ON_OPEN_RAIL
    move(execute=False)
    move(execute=True, direction=ModuloDirection.NON_MODULO)
    assert move.busy
