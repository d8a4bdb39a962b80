"""C rotation of a planar mover: the four C windows, the CRotation command modes and the
conversion of a modulo C target into an absolute one (TF5430 §4.2, §6.1.1, §6.1.9).

The square mover looks the same every 90°, so the hidden C position limits [minimum, maximum]
give four windows, one per quarter turn (§4.2: ±15° → [-15, 15], [75, 105], [165, 195],
[255, 285]). Membership is judged modulo 360° (digest §8 q17), which for four windows 90° apart
is a test modulo 90°. A C motion that does not stay inside one window puts the mover into a
CRotation mode, where X and Y are locked; it returns to its base mode when a C motion ends
inside any window.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Integral

from openmotion.core.enums import ModuloDirection, convert_enum
from openmotion.core.errors import CommandRejected, ConfigError, ErrorId
from openmotion.core.modulo import mc3_modulo_target
from openmotion.planar.enums import MoverCommandMode
from openmotion.planar.tolerances import ANGLE_PRECISION, COUNTER_RESIDUE
from openmotion.trajectory.segments import Profile

QUARTER = 90.0  #: [°] symmetry of the square mover: the windows repeat at this spacing

_C_ROTATION = {
    MoverCommandMode.FREE_MOVEMENT: MoverCommandMode.C_ROTATION_FREE_MOVEMENT,
    MoverCommandMode.ON_TRACK: MoverCommandMode.C_ROTATION_ON_TRACK,
}
_BASE = {rotation: base for base, rotation in _C_ROTATION.items()}


@dataclass(frozen=True, slots=True)
class CWindows:
    """The C windows built from the mover's hidden C position limits (§4.2, §6.1.1).

    The defaults ±15° are inferred from §6.1.8 (the manual shows no value).
    """

    minimum: float = -15.0  #: lower C position limit [°]
    maximum: float = 15.0  #: upper C position limit [°]

    def __post_init__(self) -> None:
        if not (math.isfinite(self.minimum) and math.isfinite(self.maximum)):
            raise ConfigError("c limits: minimum and maximum must be finite")
        if self.minimum > self.maximum:
            raise ConfigError(f"c limits: minimum {self.minimum} above maximum {self.maximum}")

    def windows(self) -> tuple[tuple[float, float], ...]:
        """The four windows [lower, upper] in degrees, one per quarter turn."""
        return tuple((self.minimum + k * QUARTER, self.maximum + k * QUARTER) for k in range(4))

    def contains(self, c: float) -> bool:
        """Whether orientation ``c`` [°] lies in one of the windows (modulo 360°)."""
        return self.contains_interval(c, c)

    def contains_interval(self, low: float, high: float) -> bool:
        """Whether every orientation in [low, high] lies in ONE window (a swept C interval)."""
        k = math.floor((low - self.minimum + ANGLE_PRECISION) / QUARTER)
        shift = k * QUARTER
        return (low >= self.minimum + shift - ANGLE_PRECISION
                and high <= self.maximum + shift + ANGLE_PRECISION)

    def contains_motion(self, c: Profile, never_turns_back: bool | None = None) -> bool:
        """Whether a planned C motion stays inside one window for its whole duration
        (``never_turns_back``: ``monotonic(c)`` if the caller knows it)."""
        return self.contains_interval(*_swept_c(c, never_turns_back))


def monotonic(profile: Profile) -> bool:
    """Whether a planned motion never turns back: its velocity keeps one sign, up to float
    residue of 1e-9 of its peak (a residue of ~1e-13 mm/s ends many ruckig brakes)."""
    low, high = profile.velocity_extrema()
    residue = COUNTER_RESIDUE * max(-low, high, 1.0)
    return low >= -residue or high <= residue


def _swept_c(c: Profile, never_turns_back: bool | None = None) -> tuple[float, float]:
    """Lowest and highest c of a planned motion. One that never turns back (the usual case)
    has its extremes at segment boundaries, far cheaper to read than
    ``Profile.position_extrema``'s search for turning points."""
    if monotonic(c) if never_turns_back is None else never_turns_back:
        positions = c.p.tolist()
        return min(positions), max(positions)
    return c.position_extrema()


def mode_at_enable(c: float, windows: CWindows) -> MoverCommandMode:
    """Command mode after Enable: FreeMovement, or CRotationFreeMovement when the mover is
    turned outside every window (§4.2)."""
    if windows.contains(c):
        return MoverCommandMode.FREE_MOVEMENT
    return MoverCommandMode.C_ROTATION_FREE_MOVEMENT


def mode_during_c_motion(mode: MoverCommandMode, c: Profile,
                         windows: CWindows) -> MoverCommandMode:
    """Command mode while the C motion ``c`` runs: a base mode turns into its CRotation mode
    when the motion leaves its window (§4.2); every other mode is kept."""
    if mode in _C_ROTATION and not windows.contains_motion(c):
        return _C_ROTATION[mode]
    return mode


def mode_after_c_motion(mode: MoverCommandMode, c_end: float,
                        windows: CWindows) -> MoverCommandMode:
    """Command mode when a C motion (MoveC, a halt) has ended at ``c_end``: back to the base
    mode if the end lies in any window, else the CRotation mode stays (§4.2)."""
    if mode in _BASE and windows.contains(c_end):
        return _BASE[mode]
    return mode


def xy_locked(mode: MoverCommandMode) -> bool:
    """Whether X and Y cannot be moved in ``mode`` (the CRotation modes, §4.2)."""
    return mode in _BASE


def modulo_target(start: float, position: float, direction: ModuloDirection,
                  additional_turns: int, modulus: float, tolerance: float) -> float:
    """Absolute target of a modulo move with the MC3 option rules (§6.1.9).

    ``additional_turns`` must be 0 unless the direction is Positive or Negative, and
    ``tolerance`` must be 0 with NonModulo: both are INVALID_MODULO_OPTIONS. A modulo
    ``position`` outside [0, modulus] is INVALID_TARGET_POSITION (core.modulo).
    """
    direction = _direction(direction)
    if not math.isfinite(position):
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT, f"target {position} is not finite")
    if not (isinstance(additional_turns, Integral) and additional_turns >= 0):
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"additional turns {additional_turns!r} must be an integer >= 0")
    if not (math.isfinite(tolerance) and tolerance >= 0.0):
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"modulo tolerance {tolerance} must be finite and >= 0")
    if additional_turns and direction not in (ModuloDirection.POSITIVE, ModuloDirection.NEGATIVE):
        raise CommandRejected(ErrorId.INVALID_MODULO_OPTIONS,
                              f"additional turns need direction positive or negative, "
                              f"not {direction.name}")
    if tolerance and direction == ModuloDirection.NON_MODULO:
        raise CommandRejected(ErrorId.INVALID_MODULO_OPTIONS,
                              "a modulo tolerance needs a modulo direction, not NON_MODULO")
    return mc3_modulo_target(start, position, direction, int(additional_turns), modulus,
                             tolerance)


def move_c_target(start: float, position: float, direction: ModuloDirection,
                  additional_turns: int, modulus: float = 360.0,
                  tolerance_window: float = 0.0) -> float:
    """Absolute C target of MoveC from set position ``start`` (§6.1.1, §6.1.9).

    ``modulus`` and ``tolerance_window`` are the mover's init parameters, not command options:
    a configured window applies to the modulo directions and is ignored by an absolute
    (NonModulo) target, which it could not change.
    """
    if not (math.isfinite(modulus) and modulus > 0.0):
        raise ConfigError(f"c coordinate modulus {modulus} must be > 0")
    window = 0.0 if _direction(direction) == ModuloDirection.NON_MODULO else tolerance_window
    return modulo_target(start, position, direction, additional_turns, modulus, window)


def _direction(direction: ModuloDirection) -> ModuloDirection:
    try:
        return convert_enum(ModuloDirection, direction)
    except ValueError:
        raise CommandRejected(ErrorId.PLANAR_INVALID_INPUT,
                              f"direction {direction!r} is no MC_DIRECTION") from None
