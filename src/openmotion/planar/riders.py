"""Riders: movers coupled to a track, the legs of their routes, and what the traffic needs of
tracks, of the track network and of the mover a rider belongs to (traffic.py).

A rider moves along an *odometer* q = base + s: s is the arc length on the track it is on,
``base`` where that track starts on its route (a :class:`Leg`). A route forwards has legs of
increasing base; a route back over the seam of a closed track (D-147) has legs of decreasing
base: the loop at 0, -L, -2L, ...
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:
    from openmotion.planar.feedback import PlanarCommand
    from openmotion.trajectory.plan import Limits

#: What a rider does this cycle (the traffic's ``mode`` array): stands, follows its profile,
#: is held by gap control or a switch zone (a tracking step), or follows its master (geared).
IDLE, FOLLOW, HELD, GEAR = 0, 1, 2, 3


class Rail(Protocol):
    """What the traffic needs of a track: its length and its curve (the track atlas reads
    the curve's flat table and the placement, ``track_atlas.Atlas``)."""

    index: int  #: its place in the network's ``tracks``
    length: float
    path: Any  #: its TrackPath (``max_curvature`` [1/mm])

    def frame_at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                               np.ndarray]:
        """x, y, heading [rad] and curvature [1/mm] at the arc lengths ``s``."""
        ...

    def placement(self) -> Any:
        """Where the track's part frame lies now (a planar Pose; the identity without
        parts): ``frame_at`` is the curve placed so."""
        ...


class Network(Protocol):
    """The connections of the tracks."""

    tracks: list[Any]  #: every track, at its ``index``
    version: int  #: changes whenever links, a geometry or a track state change

    def successors(self, track: Rail) -> list[Rail]:
        """Tracks that start where ``track`` ends and may be entered now."""
        ...

    def switches(self, track: Rail) -> tuple[Any, Any]:
        """The switch at the start and at the end of ``track`` (None where there is none)."""
        ...

    def collision_ranges(self, track: Rail) -> tuple[float, float]:
        """Collision range at the start and at the end of ``track`` [mm]."""
        ...

    def refresh(self) -> None:
        """Once per cycle: notice parts that changed position (links across parts)."""
        ...

    def closed_loop(self, track: Rail) -> bool:
        """Whether ``track`` ends where it starts."""
        ...

    def way_on(self, track: Rail, limit: int) -> list[Rail]:
        """The tracks after ``track`` while there is a single way on, ``limit`` at most."""
        ...

    def placed(self) -> bool:
        """Whether parts can place the tracks (else each lies where its geometry says)."""
        ...


class Owner(Protocol):
    """The mover a rider belongs to: told when its command ends, asked before its geared
    way goes on over tracks it did not hold at the start (followMover, D-149)."""

    awake: bool  #: publish its status at the end of this cycle
    #: ``track_finished(command)``: its track command ended (or its halt);
    #: ``admit_way(tracks)``: raises ``CommandRejected`` when it may not move onto ``tracks``
    port: Any


@dataclass
class Leg:
    """One track of a route and where it starts on the odometer."""

    track: Rail
    base: float


@dataclass
class Rider:
    """A mover coupled to a track."""

    owner: Owner
    track: Rail
    s: float  #: arc length on ``track`` [mm] (the position before the first cycle)
    row: int  #: the planar system's table row of the odometer profile
    rows: tuple[int, int, int]  #: rows of x, y and c
    gap: float
    brake: tuple[float, float]  #: deceleration and jerk gap control brakes with
    oriented: bool  #: c follows the track's heading
    c: float  #: c [deg] (set when the orientation follows the track)
    route: list[Leg] = field(default_factory=list)  #: the legs ahead, the current first
    command: PlanarCommand | None = None
    limits: Limits | None = None
    target: float = 0.0  #: odometer target of the command
    halting: bool = False
    gear: Any = None  #: a gearing.Coupling while the rider is geared to a master
    slot: int = -1
    #: the gap its switch zones are measured with (NaN: its gap): a larger gap widens them
    #: only once the rider is outside the wider ones, so that it enters them by the entry
    #: check like any other rider (D-136)
    zone_gap: float = math.nan
    half: tuple[float, float] = (77.5, 77.5)  #: half its width and height [mm] (footprint)


def backwards(route: list[Leg]) -> bool:
    """Whether ``route`` goes back over the seam of its closed track: its legs descend."""
    return len(route) > 1 and route[1].base < route[0].base


def ahead_legs(route: list[Leg]) -> list[Leg]:
    """The legs of ``route`` ahead on the odometer: all of a route forwards, the current one
    of a route back (its other legs lie behind)."""
    return route[:1] if backwards(route) else route


def ascending(route: list[Leg]) -> list[Leg]:
    """The legs of ``route`` by their base, lowest first (a route back, reversed)."""
    return route[::-1] if backwards(route) else route


def brakes_harder(speed: np.ndarray, acceleration: np.ndarray, deceleration: np.ndarray,
                  jerk: np.ndarray) -> np.ndarray:
    """Whether a rider moving at ``speed`` with ``acceleration`` (both towards its target)
    brakes harder than the ``deceleration`` and ``jerk`` of its command take back without
    turning it round: then only its own brake (gap control's, the hardest) stops it without
    going back."""
    return (acceleration < -deceleration) | \
        (speed + acceleration * np.abs(acceleration) / (2.0 * jerk) < 0.0)
