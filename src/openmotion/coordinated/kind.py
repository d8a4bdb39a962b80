"""What the machine model shows of a Part 4 axes group: its TCP, its time law, its state.

Declared once here (``AxesGroup.MACHINE``), read by every edge (kernel/model.py, D-226):
``x``, ``y``, ``z`` (the TCP's set position in the MCS; 0 for a coordinate its kinematics
lacks, NaN without members), ``path_velocity`` and ``path_acceleration`` (of its time law,
along the path in the frame the path runs in: 0 while the TCP only rides on a moving PCS),
``state`` (the AxesGroupState number), ``blocker_id`` (MC_GroupReadBlockerStatus, TF5410
§9.3.1.2.8: the blocker the path stands at, 0: none).
"""

from __future__ import annotations

import math
import weakref
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.coordinated.states import AxesGroupState
from openmotion.kernel.model import Kind, SignalSpec

if TYPE_CHECKING:
    from openmotion.coordinated.group import AxesGroup

#: group -> (set positions, kinematics, MCS offset, TCP) of its last TCP reading
_TCP_CACHE: weakref.WeakKeyDictionary[AxesGroup, tuple[bytes, Any, bytes, np.ndarray]] = \
    weakref.WeakKeyDictionary()


def tcp(group: AxesGroup) -> np.ndarray:
    """The TCP's set position in the MCS; x, y and z read in one sample share one forward
    transform (the cache is keyed by all it depends on)."""
    spaces = group.spaces
    acs = group.acs_set()
    acs_key, offset_key = acs.tobytes(), spaces.mcs_offset.tobytes()
    cached = _TCP_CACHE.get(group)
    if cached is None or cached[0] != acs_key or cached[1] is not spaces.kinematics \
            or cached[2] != offset_key:
        cached = acs_key, spaces.kinematics, offset_key, spaces.xyz(spaces.to_mcs(acs))
        _TCP_CACHE[group] = cached
    return cached[3]


def _coordinate(index: int):  # noqa: ANN202 - a reader factory
    def read(group: AxesGroup) -> float:
        return float(tcp(group)[index]) if group.members else math.nan

    return read


def _law(prop: str):  # noqa: ANN202 - a reader factory
    return lambda group: float(getattr(group.motion, prop))


AXES_GROUP = Kind(
    "axes_group",
    signals=(
        *(SignalSpec(name, "mm", float, _coordinate(index), f"TCP set position {name} (MCS)",
                     default=True, scope=True) for index, name in enumerate("xyz")),
        SignalSpec("path_velocity", "mm/s", float, _law("path_velocity"),
                   "path velocity of the time law", default=True, scope=True),
        SignalSpec("path_acceleration", "mm/s²", float, _law("path_acceleration"),
                   "path acceleration of the time law"),
        SignalSpec("state", "", AxesGroupState, lambda group: float(group.state),
                   "AxesGroupState (Part 4 §2)"),
        SignalSpec("blocker_id", "", int, lambda group: float(group.blocker_status()[1]),
                   "the blocker the path stands at, 0: none (TF5410 §9.3.1.2.8)"),
    ),
    handles=("Command",),
    identify=lambda group: group.group_id,  # counted per runtime (D-223)
)
