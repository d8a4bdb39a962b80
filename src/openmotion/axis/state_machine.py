"""Which command each PLCopen state accepts (PLCopen Part 1 diagram; TcMC digest §1.2).

One table, written once: the axis asks it before a command starts and turns a refusal into
the FB's error id.
"""

from __future__ import annotations

from openmotion.core.enums import AxisState
from openmotion.core.errors import CommandRejected, ErrorId

S = AxisState
MOVING = {S.DISCRETE_MOTION, S.CONTINUOUS_MOTION, S.SYNCHRONIZED_MOTION}

#: command family -> states that accept it
ACCEPTS: dict[str, frozenset[AxisState]] = {
    "move": frozenset({S.STANDSTILL} | MOVING),
    "stop": frozenset({S.STANDSTILL, S.HOMING, S.STOPPING} | MOVING),
    "home": frozenset({S.STANDSTILL}),
    "modify": frozenset(MOVING),  # MC_NewPos, MC_NewPosAndVelo, MC_ChangeDynParam
    "set_position": frozenset({S.STANDSTILL, S.DISABLED, S.ERROR_STOP}),
}

_REFUSAL = {
    S.DISABLED: (ErrorId.AXIS_DISABLED, "the axis is disabled: enable it with MC_Power"),
    S.ERROR_STOP: (ErrorId.AXIS_IN_ERROR_STOP, "the axis is in ErrorStop: MC_Reset first"),
    S.STOPPING: (ErrorId.AXIS_STOPPING, "the axis is stopping: MC_Stop holds it"),
    S.HOMING: (ErrorId.AXIS_HOMING, "the axis is homing"),
}


def admit(state: AxisState, family: str) -> None:
    """Raise ``CommandRejected`` unless ``state`` accepts a command of ``family``."""
    if state in ACCEPTS[family]:
        return
    if state in _REFUSAL:
        raise CommandRejected(*_REFUSAL[state])
    if family == "modify":
        raise CommandRejected(ErrorId.AXIS_NOT_MOVING, f"needs a moving axis, state {state.name}")
    raise CommandRejected(
        ErrorId.AXIS_NOT_STANDSTILL, f"needs an axis at standstill, state {state.name}"
    )
