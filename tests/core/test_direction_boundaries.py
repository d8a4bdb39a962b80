"""Two direction types of the same manual name, converted by meaning where they meet (D-225).

TcMC's MC_Direction (§6.2: Positive 1, ShortestWay 2, Negative 3, Current 4) is
``openmotion.Direction``; the MC3 libraries' MC_DIRECTION (TF5410 §9.4.1.3, TF5430
§7.2.1.1.2: NonModulo 0, Positive 1, ShortestWay 2, Negative 3) is ``ModuloDirection``, and
MC_SYNC_MODE (TF5410 §9.4.1.4: NonModulo 0, Positive 1, Negative 3) reuses its directions.
Their numbers agree only because both manuals chose them so. Every input that takes one of
them converts a member of another enumeration by its name, a plain number by its value:
``Flipped`` below, whose numbers are swapped, shows which of the two a boundary uses.
"""

from __future__ import annotations

from enum import IntEnum

import pytest

import openmotion as om
from openmotion.core.enums import Direction, ModuloDirection, convert_enum
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.core.modulo import mc3_modulo_target
from openmotion.planar import ST_MoveCOptions, ST_MoveOnTrackOptions
from openmotion.planar.rotation import move_c_target
from openmotion.transport import UDINT_TO_IDENTINGROUP, CaGroup, SyncMode


class Flipped(IntEnum):
    """Directions numbered the other way round: only a conversion by name reads them right."""

    NEGATIVE = 1
    POSITIVE = 3


def test_a_member_converts_by_name_a_number_by_value() -> None:
    assert convert_enum(ModuloDirection, Direction.NEGATIVE) is ModuloDirection.NEGATIVE
    assert convert_enum(Direction, ModuloDirection.SHORTEST_WAY) is Direction.SHORTEST_WAY
    assert convert_enum(ModuloDirection, SyncMode.NEGATIVE) is ModuloDirection.NEGATIVE
    assert convert_enum(ModuloDirection, Flipped.NEGATIVE) is ModuloDirection.NEGATIVE
    assert convert_enum(ModuloDirection, 3) is ModuloDirection.NEGATIVE  # a PLC's UINT
    with pytest.raises(ValueError, match="CURRENT.*is not a ModuloDirection"):
        convert_enum(ModuloDirection, Direction.CURRENT)  # MC3 has no current direction
    with pytest.raises(ValueError, match="NON_MODULO.*is not a Direction"):
        convert_enum(Direction, ModuloDirection.NON_MODULO)  # TcMC has no NonModulo
    with pytest.raises(ValueError):
        convert_enum(Direction, 0)


def test_the_axis_reads_a_direction_by_its_name() -> None:
    """MC_MoveVelocity's Direction (TcMC §3.3) at the axis' door."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    axis.power()
    command = axis.move_velocity(100.0, direction=Flipped.NEGATIVE)
    rt.run(0.2)
    assert not command.error and axis.set_velocity < 0.0
    refused = axis.move_modulo(90.0, 100.0, direction=ModuloDirection.NON_MODULO)
    assert refused.error and refused.error_id is ErrorId.INVALID_DIRECTION
    assert not axis.move_velocity(50.0, direction=ModuloDirection.POSITIVE).error  # usable


def test_the_mc3_modulo_target_reads_a_direction_by_its_name() -> None:
    """TF5410 §11.3: from 10 to 90 on a 360 ring, Negative goes back 280."""
    assert mc3_modulo_target(10.0, 90.0, Flipped.NEGATIVE, 0, 360.0, 0.0) == -270.0
    assert mc3_modulo_target(10.0, 90.0, SyncMode.NEGATIVE, 0, 360.0, 0.0) == -270.0
    assert mc3_modulo_target(10.0, 90.0, Direction.POSITIVE, 0, 360.0, 0.0) == 90.0


def test_the_ca_group_reads_a_direction_by_its_name() -> None:
    """MC_MoveAbsoluteCA's Direction (TF5410 §9.1.2) on a ring of 100 mm: Negative from 30
    to 20 is 10 mm back, Positive would be 90 mm forward."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=100.0, default_gap=10.0)
    axis = rt.add_axis("m1", position=30.0, max_velocity=1000.0, max_deceleration=20000.0,
                       max_jerk=1.0e6)
    axis.power()
    assert group.add_axis(axis, UDINT_TO_IDENTINGROUP(1)).done
    assert group.enable().done
    move = group.move_absolute(axis, 20.0, 1000.0, direction=Flipped.NEGATIVE)
    rt.run_until(lambda: move.done, timeout=5.0)
    assert axis.set_position == pytest.approx(20.0)
    wrong = group.move_absolute(axis, 20.0, 1000.0, direction=om.Direction.CURRENT)
    assert wrong.error and wrong.error_id is ErrorId.INVALID_DIRECTION
    again = group.move_absolute(axis, 10.0, 1000.0, direction=om.Direction.NEGATIVE)
    rt.run_until(lambda: again.done, timeout=5.0)
    assert axis.set_position == pytest.approx(10.0)


def test_planar_options_read_a_direction_by_its_name() -> None:
    """The MC_DIRECTION options of MoveC and MoveOnTrack (TF5430 §7.2.1.2.9, §7.2.1.2.11)."""
    assert ST_MoveCOptions(direction=Flipped.NEGATIVE).direction is ModuloDirection.NEGATIVE
    assert ST_MoveOnTrackOptions(direction=Direction.SHORTEST_WAY).direction is \
        ModuloDirection.SHORTEST_WAY
    assert move_c_target(10.0, 90.0, Flipped.NEGATIVE, 0) == -270.0
    with pytest.raises(CommandRejected, match="no MC_DIRECTION"):
        move_c_target(10.0, 90.0, Direction.CURRENT, 0)
