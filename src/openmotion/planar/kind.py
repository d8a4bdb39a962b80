"""What the machine model shows of the planar objects (TF5430; D-226).

Declared once here and set as ``MACHINE`` on each class; read by every edge
(kernel/model.py). A mover's signals: x, y, z [mm], a, b, c [°] (its published set
position), ``velocity`` (path velocity |(vx, vy)| [mm/s]), ``state`` (the PlanarState number),
``coordinate_system`` (the OID of the coordinate system x, y, c are in; 0 without parts:
PhysicalAreaID), ``track`` (the number of the track it is coupled to: 1 for the first track
made on the runtime, 2 for the next ...; 0 on none) and ``s`` (its set arc length on that
track [mm]; NaN on none). Groups, tracks and parts show their state.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from openmotion.kernel.model import Kind, SignalSpec
from openmotion.planar.enums import PlanarState

if TYPE_CHECKING:
    from openmotion.planar.mover import MC_PlanarMover

_HANDLES = ("PlanarCommand",)  #: what the manual's methods return (feedback.py)


def _pose(prop: str):  # noqa: ANN202 - a reader factory
    return lambda mover: float(getattr(mover.position, prop))


def _speed(mover: MC_PlanarMover) -> float:
    velocity = mover.mc_to_plc.set.set_velo
    return math.hypot(velocity.x, velocity.y)


def _track_number(mover: MC_PlanarMover) -> float:
    oid = mover.mc_to_plc.set_on_track.track_oid
    if not oid:
        return 0.0
    tracks = mover.system.network.tracks  # creation order, as the numbers count
    return float(next(k for k, track in enumerate(tracks, start=1) if track.oid == oid))


def _arc_length(mover: MC_PlanarMover) -> float:
    on_track = mover.mc_to_plc.set_on_track
    return float(on_track.set_pos) if on_track.track_oid else math.nan


def _state(obj: Any) -> float:
    return float(obj.state)


def _state_signal() -> SignalSpec:
    return SignalSpec("state", "", PlanarState, _state, "PlanarState (§4.1)")


PLANAR_MOVER = Kind(
    "planar_mover",
    signals=(
        SignalSpec("x", "mm", float, _pose("x"), "published set position x", default=True,
                   scope=True),
        SignalSpec("y", "mm", float, _pose("y"), "published set position y", default=True,
                   scope=True),
        SignalSpec("z", "mm", float, _pose("z"), "published set position z (lift)",
                   scope=True),
        SignalSpec("a", "°", float, _pose("a"), "published set position a (tilt about x)"),
        SignalSpec("b", "°", float, _pose("b"), "published set position b (tilt about y)"),
        SignalSpec("c", "°", float, _pose("c"), "published set position c (rotation)",
                   default=True, scope=True),
        SignalSpec("velocity", "mm/s", float, _speed, "path velocity |(vx, vy)|", scope=True),
        _state_signal(),
        SignalSpec("coordinate_system", "", int,
                   lambda mover: float(mover.mc_to_plc.set.physical_area_id),
                   "OID of the coordinate system x, y, c are in (0: PhysicalAreaID)"),
        SignalSpec("track", "", int, _track_number,
                   "number of the track it is on (1: the first made; 0: none)"),
        SignalSpec("s", "mm", float, _arc_length, "set arc length on its track (NaN: none)"),
    ),
    handles=_HANDLES,
    units={"move_c.target_position": "°", "move_a.target_position": "°",
           "move_b.target_position": "°"},
)

PLANAR_GROUP = Kind("planar_group", signals=(_state_signal(),), handles=_HANDLES)

PLANAR_TRACK = Kind("planar_track", signals=(_state_signal(),), handles=_HANDLES)

PLANAR_PART = Kind(
    "planar_part",
    signals=(_state_signal(),
             SignalSpec("position_index", "", int, lambda part: float(part.position_index),
                        "the active position (1-based, §5.1)")),
)

PLANAR_ENVIRONMENT = Kind(
    "planar_environment",
    handles=_HANDLES,
    #: its parts (§5.2), which no system lists: an environment's layout holds them
    children=lambda environment: () if environment.layout is None
    else tuple(environment.layout.parts.values()),
)
