"""Modulo positioning on the set position with a tolerance window (TcMC §3.4, §3.5).

The manual gives two tables, not a formula; ``modulo_target`` reproduces all 37 rows
(tests/core/test_modulo.py). The window lets the axis move a little against the commanded
direction instead of a whole extra turn when the set position is just past the target.
"""

from __future__ import annotations

import math

from openmotion.core.enums import Direction, ModuloDirection, convert_enum
from openmotion.core.errors import CommandRejected, ErrorId


def modulo_position(position: float, period: float) -> float:
    """The modulo view of an absolute position, in [0, period) (TcMath MODABS)."""
    value = math.fmod(position, period)
    if value < 0.0:
        value += period
    return 0.0 if value >= period else value


def modulo_turns(position: float, period: float) -> int:
    """Whole turns of an absolute position (TcMath MODTURNS)."""
    return math.floor(position / period)


def modulo_target(
    start: float, target: float, period: float, tolerance: float, direction: Direction
) -> float:
    """Absolute end position of MC_MoveModulo from set position ``start``.

    ``target`` >= period adds whole turns (TcMC §3.5: 450 on 360 is 90 plus one turn);
    ``tolerance`` is the half-width of the window around the set position.
    """
    if not period > 0.0 or not math.isfinite(period):
        raise CommandRejected(ErrorId.INVALID_MODULO_PERIOD, f"modulo period {period} must be > 0")
    if not math.isfinite(target) or target < 0.0:
        raise CommandRejected(
            ErrorId.INVALID_MODULO_TARGET, f"modulo target {target} must be finite and >= 0"
        )
    turns = math.floor(target / period)
    base = target - turns * period
    if direction == Direction.SHORTEST_WAY:
        if turns:
            raise CommandRejected(
                ErrorId.INVALID_MODULO_TARGET,
                f"shortest way needs a target in [0, {period}), got {target}",
            )
        delta = (base - start) % period
        if delta > period / 2.0:
            delta -= period
        return snap_to_period(start + delta, base, period)
    if direction == Direction.POSITIVE:
        delta = (base - start) % period
        if tolerance > 0.0 and delta >= period - tolerance:
            delta -= period
        return snap_to_period(start + delta + turns * period, base, period)
    if direction == Direction.NEGATIVE:
        back = (start - base) % period
        if tolerance > 0.0 and back >= period - tolerance:
            back -= period
        return snap_to_period(start - back - turns * period, base, period)
    raise CommandRejected(ErrorId.INVALID_DIRECTION, f"direction {direction!r} is not allowed here")


def snap_to_period(approximate_end: float, base: float, period: float) -> float:
    """The exact absolute position base + n*period nearest to the computed end."""
    return base + period * round((approximate_end - base) / period)


def mc3_modulo_target(start: float, position: float, direction: ModuloDirection,
                      additional_turns: int, period: float, window: float) -> float:
    """Absolute target of an MC3 modulo move (TF5410 §11.3; also XPlanar's C axis).

    ``direction``: an MC_DIRECTION, NonModulo (``position`` is absolute), Positive,
    ShortestWay or Negative; a number is its value, a member of another enumeration (TcMC's
    ``Direction``, MC_SYNC_MODE) its name (D-225). A modulo ``position`` must lie in
    [0, period]. Inside ``window`` around the target the move takes the short way whatever
    the direction (no unintended turn); additional turns are added to that. Raises
    ``CommandRejected`` with INVALID_TARGET_POSITION or INVALID_ADDITIONAL_TURNS.
    """
    direction = convert_enum(ModuloDirection, direction)
    if direction is ModuloDirection.NON_MODULO:
        if additional_turns:
            raise CommandRejected(ErrorId.INVALID_ADDITIONAL_TURNS,
                                  "additional turns need direction positive or negative")
        return position
    if not 0.0 <= position <= period:
        raise CommandRejected(ErrorId.INVALID_TARGET_POSITION,
                              f"modulo target {position:g} outside [0, {period:g}]")
    if direction is ModuloDirection.SHORTEST_WAY and additional_turns:
        raise CommandRejected(ErrorId.INVALID_ADDITIONAL_TURNS,
                              "additional turns need direction positive or negative")
    s = start % period
    short = (position - s + period / 2.0) % period - period / 2.0
    if direction is ModuloDirection.SHORTEST_WAY or abs(short) <= window:
        delta = short
    elif direction is ModuloDirection.POSITIVE:
        delta = (position - s) % period
    else:
        delta = -((s - position) % period)
    if direction is ModuloDirection.POSITIVE:
        delta += additional_turns * period
    elif direction is ModuloDirection.NEGATIVE:
        delta -= additional_turns * period
    return start + delta
