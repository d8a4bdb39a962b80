"""Enumerations against the numbers the manuals print (rule 144).

Each table row is one enumerator as the manual spells it, the member that stands for it, and
the manual's value (IEC 61131-3 numbers an enumerator without ``:=`` one above the previous
one, from 0 for the first). Sources: TcMC §3.21 (E_DecoupleMode), §6.2 (MC_Direction), §6.3
(E_TouchProbe, E_SignalEdge, E_TouchProbeState), §6.4 (E_ReadMode), §6.5
(E_SuperpositionMode), §6.7 (E_DestallMode), §6.8 (E_DestallDetectMode); TF5410 §9.4.1.1
(MC_BUFFER_MODE, which TcMC does not define).
"""

from __future__ import annotations

from enum import IntEnum

import pytest

import openmotion as om
from openmotion.plcopen import DestallDetectMode, DestallMode, JogMode
from openmotion.plcopen.touch_probe import SignalEdge, TouchProbeSource, TouchProbeState

D, DM, SM = om.Direction, om.DecoupleMode, om.SuperpositionMode

#: manual type name -> (enum, [(manual enumerator, member, manual value)])
MANUAL_ENUMS: dict[str, tuple[type[IntEnum], list[tuple[str, IntEnum, int]]]] = {
    "MC_Direction": (D, [  # TcMC §6.2
        ("MC_Positive_Direction", D.POSITIVE, 1),
        ("MC_Shortest_Way", D.SHORTEST_WAY, 2),
        ("MC_Negative_Direction", D.NEGATIVE, 3),
        ("MC_Current_Direction", D.CURRENT, 4),
    ]),
    "E_ReadMode": (om.ReadMode, [  # TcMC §6.4
        ("ReadMode_Once", om.ReadMode.ONCE, 1),
        ("ReadMode_Cyclic", om.ReadMode.CYCLIC, 2),
    ]),
    "E_TouchProbe": (TouchProbeSource, [  # TcMC §6.3
        ("TouchProbe1", TouchProbeSource.TOUCH_PROBE_1, 1),
        ("TouchProbe2", TouchProbeSource.TOUCH_PROBE_2, 2),
        ("TouchProbe3", TouchProbeSource.TOUCH_PROBE_3, 3),
        ("TouchProbe4", TouchProbeSource.TOUCH_PROBE_4, 4),
        ("PlcEvent", TouchProbeSource.PLC_EVENT, 10),
    ]),
    "E_SignalEdge": (SignalEdge, [  # TcMC §6.3, implicit numbering
        ("RisingEdge", SignalEdge.RISING, 0),
        ("FallingEdge", SignalEdge.FALLING, 1),
    ]),
    "E_TouchProbeState": (TouchProbeState, [  # TcMC §6.3, implicit numbering
        ("TouchProbeInactive", TouchProbeState.INACTIVE, 0),
        ("TouchProbeActivated", TouchProbeState.ACTIVATED, 1),
        ("TouchProbeAborted", TouchProbeState.ABORTED, 2),
    ]),
    "E_SuperpositionMode": (SM, [  # TcMC §6.5
        ("SUPERPOSITIONMODE_VELOREDUCTION_ADDITIVEMOTION", SM.VELOREDUCTION_ADDITIVEMOTION, 1),
        ("SUPERPOSITIONMODE_VELOREDUCTION_LIMITEDMOTION", SM.VELOREDUCTION_LIMITEDMOTION, 2),
        ("SUPERPOSITIONMODE_LENGTHREDUCTION_ADDITIVEMOTION",
         SM.LENGTHREDUCTION_ADDITIVEMOTION, 3),
        ("SUPERPOSITIONMODE_LENGTHREDUCTION_LIMITEDMOTION", SM.LENGTHREDUCTION_LIMITEDMOTION, 4),
    ]),
    "E_DestallMode": (DestallMode, [  # TcMC §6.7
        ("PwStMode_None", DestallMode.NONE, 0),
        ("PwStMode_SetError", DestallMode.SET_ERROR, 1),
        ("PwStMode_SetErrNonRef", DestallMode.SET_ERR_NON_REF, 2),
        ("PwStMode_UseOverride", DestallMode.USE_OVERRIDE, 3),
    ]),
    "E_DestallDetectMode": (DestallDetectMode, [  # TcMC §6.8
        ("PwStDetectMode_None", DestallDetectMode.NONE, 0),
        ("PwStDetectMode_Encoderless", DestallDetectMode.ENCODERLESS, 1),
        ("PwStDetectMode_Lagging", DestallDetectMode.LAGGING, 2),
    ]),
    "E_DecoupleMode": (DM, [  # TcMC §3.21, values in the comments
        ("MC_DECOUPLEMODE_STOP", DM.STOP, 0),
        ("MC_DECOUPLEMODE_ORIENTEDSTOP", DM.ORIENTED_STOP, 1),
        ("MC_DECOUPLEMODE_ENDLESS", DM.ENDLESS, 2),
        ("MC_DECOUPLEMODE_ENDLESS_NEWVELO", DM.ENDLESS_NEW_VELOCITY, 3),
        ("MC_DECOUPLEMODE_NEWPOS", DM.NEW_POSITION, 4),
        ("MC_DECOUPLEMODE_NEWPOSANDVELO", DM.NEW_POSITION_AND_VELOCITY, 5),
        ("MC_DECOUPLEMODE_INSTANTANEOUSSTOP", DM.INSTANTANEOUS_STOP, 6),
    ]),
    "MC_BUFFER_MODE": (om.BufferMode, [  # TF5410 §9.4.1.1
        ("mcAborting", om.BufferMode.ABORTING, 0x00),
        ("mcBuffered", om.BufferMode.BUFFERED, 0x01),
        ("mcBlendingLow", om.BufferMode.BLENDING_LOW, 0x12),
        ("mcBlendingPrevious", om.BufferMode.BLENDING_PREVIOUS, 0x13),
        ("mcBlendingNext", om.BufferMode.BLENDING_NEXT, 0x14),
        ("mcBlendingHigh", om.BufferMode.BLENDING_HIGH, 0x15),
    ]),
}


@pytest.mark.parametrize("type_name", sorted(MANUAL_ENUMS))
def test_enum_values_are_the_manuals(type_name: str) -> None:
    """Every enumerator has the manual's number, and the enum has no other values."""
    enum, rows = MANUAL_ENUMS[type_name]
    wrong = {name: int(member) for name, member, value in rows if int(member) != value}
    assert not wrong, f"{type_name}: differs from the manual: {wrong}"
    assert all(isinstance(member, enum) for _, member, _ in rows)
    assert {int(m) for m in enum} == {value for _, _, value in rows}, type_name


def test_jog_mode_has_the_manuals_four_modes() -> None:
    """TcMC §3.13 names E_JogMode's enumerators but prints no values (the numbers 0-3 are
    Tc2_MC2's, checked in tests/plcopen/test_jog.py): one distinct member per name."""
    manual = ["MC_JOGMODE_STANDARD_SLOW", "MC_JOGMODE_STANDARD_FAST", "MC_JOGMODE_CONTINUOUS",
              "MC_JOGMODE_INCHING"]
    members = [JogMode[name.removeprefix("MC_JOGMODE_")] for name in manual]
    assert len(set(members)) == len(manual) == len({int(m) for m in JogMode})


@pytest.mark.parametrize(("member", "value"), [
    (om.ErrorId.SUPERPOSITION_INCOMPLETE, 16963),  # TcMC §3.9, §3.10: 16#4243 (16963)
    (om.ErrorId.DYN_TARGET_OVERSHOT, 0x427F),  # TcMC §4.20
    (om.ErrorId.DYN_STRICTER_STOP_ACTIVE, 0x425D),
    (om.ErrorId.DYN_VELOCITY_EXCEEDED, 0x423A),
    (om.ErrorId.DYN_DIRECTION_REVERSAL, 0x4289),
    (om.ErrorId.DYN_OPTIMISATION_FAILED, 0x427E),
    (om.ErrorId.STEPPER_STALL, 0x4636),  # TcMC §6.7
], ids=lambda x: x.name if isinstance(x, om.ErrorId) else hex(x))
def test_vendor_error_ids_are_the_manuals(member: om.ErrorId, value: int) -> None:
    assert int(member) == value
