"""What the machine model shows of a CA group and of its movers (TF5410; D-226, D-227).

A CA mover is an axis in a CA group: its own signals (``gap``, ``track_position``,
``tcp_position``) read the axis's group at the time of reading, so they read NaN once the
axis leaves its group (or for an axis in none). Declared once here (``CaGroup.MACHINE``,
``Mover.MACHINE``), read by every edge (kernel/model.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from openmotion.core.errors import CommandRejected
from openmotion.kernel.model import Kind, SignalSpec
from openmotion.transport.enums import GroupState

if TYPE_CHECKING:
    from openmotion.axis.axis import Axis


def _gap(group: Any, axis: Axis) -> float:
    return float(group.gaps()[group.mover_of(axis).slot])


def _track_position(group: Any, axis: Axis) -> float:
    try:
        return float(group.tracks.read_track_positions(axis).track_position)
    except CommandRejected:  # NOT_ON_TRACK: the mover left its open track
        return math.nan


def _tcp_position(group: Any, axis: Axis) -> float:
    geo = group.tracks.geo
    template = geo.registered(axis)
    return math.nan if template is None else geo.to_tcp(template, axis.set_position)


def _member(read: Callable[[Any, Axis], float]) -> Callable[[Axis], float]:
    """A reader of one CA mover signal of an axis: NaN while the axis is in no CA group."""
    def member(axis: Axis) -> float:
        group = axis.group
        in_ca = getattr(type(group), "MACHINE", None) is CA_GROUP  # not an axes group
        return read(group, axis) if in_ca else math.nan

    return member


CA_MOVER = Kind(
    "ca_mover",
    signals=(
        SignalSpec("gap", "mm", float, _member(_gap),
                   "setpoint gap to the predecessor in the group (inf: none)", scope=True),
        SignalSpec("track_position", "mm", float, _member(_track_position),
                   "set position on the active track, as MC_ReadTrackPositions gives it; the "
                   "absolute set position without one; NaN once off an open track"),
        SignalSpec("tcp_position", "mm", float, _member(_tcp_position),
                   "TCP arc length of the set position on the path of the registered mover "
                   "template (MC_TransformPosition); NaN without one"),
    ),
    identify=lambda mover: mover.axis.row + 1,  # the AxisId of the axis it is
    subject=lambda mover: mover.axis,
)

CA_GROUP = Kind(
    "ca_group",
    signals=(SignalSpec("state", "", GroupState, lambda group: float(group.state),
                        "GroupState of the cyclic interface (§7.2)"),),
    handles=("Command",),
    children=lambda group: tuple(group.movers),  # in CA order once enabled
)
