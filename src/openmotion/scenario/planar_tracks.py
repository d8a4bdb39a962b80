"""Planar tracks in scenario files (TF5430 §6.2, §7.2.2.10): the ``planar.tracks`` list, the
order the run builds them in, and the summary's ``Tracks`` table.

A track is built with the MC_PlanarTrack methods in the order the manual's programs call them:
StartFromTrack, then its geometry elements one by one (AppendPosition, AppendLine,
AppendCircle), CloseLoop, EndAtTrack. Links need the other track to exist:

- StartFromTrack takes the end pose of a *finished* track, and freezes it;
- EndAtTrack only takes the start pose, so the other track needs its geometry, not its links.

``build_order`` finds a sequence of (track, stage) that satisfies both, so a file may list its
tracks in any order, and two tracks may end at each other (a loop of two: the second starts
from the first and ends at it). A ring of StartFromTrack links has no such order and is an
error. The run sends every track's commands in that sequence, then enables them all, so that
the automatic collision ranges see the whole network (planar_machine.py).

Tracks are created after the environment and the planar groups, so their OIDs follow the
groups' (16#05120010 ...). A mover's ``track`` signal is the track's number in
``planar.tracks`` (1, 2, ...; 0: on no track); conditions and checks take the track's name.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Annotated, Any, Literal, NamedTuple

from pydantic import AfterValidator, Field, StrictBool, StrictInt, StrictStr, model_validator

from openmotion.planar import PositionXYC
from openmotion.planar.options import (
    ST_EndAtTrackAdvancedOptions,
    ST_StartFromTrackAdvancedOptions,
)
from openmotion.planar.track import MAX_MOVER_SIZE, MC_PlanarTrack
from openmotion.scenario.planar_parts import ObjectId, _check_planar_part
from openmotion.scenario.schema import _NAMES, Identifier, Number, _Model, _unique

if TYPE_CHECKING:
    from rich.table import Table

    from openmotion.planar import PlanarCommand
    from openmotion.runtime.runtime import Runtime

Loc = tuple[str | int, ...]
Point = tuple[Number, Number]
Stage = Literal["geometry", "end"]  #: StartFromTrack to CloseLoop; EndAtTrack


def _check_planar_track(name: str) -> str:
    names = _NAMES.get()
    if names is not None and name not in names.planar_tracks:
        known = ", ".join(sorted(names.planar_tracks)) or "none"
        raise ValueError(f"unknown planar track {name!r} (planar.tracks: {known})")
    return name


TrackName = Annotated[StrictStr, AfterValidator(_check_planar_track)]


def _own_track_name(name: str) -> str:
    names = _NAMES.get()
    for kind, what in (("planar_movers", "a planar mover"), ("planar_groups", "a planar group")):
        if names is not None and name in getattr(names, kind):
            raise ValueError(f"{name!r} is already the name of {what}")
    return name


class TrackRef(NamedTuple):
    """A track argument of an entry, by name; the run passes the track of that name."""

    name: str


def starts_where_ends(first: str, second: str) -> bool:
    """Whether track ``second`` starts where track ``first`` ends, by the links of
    planar.tracks as the file gives them (starts_from, ends_at, closed_loop); True while no
    names are being validated. The network joins linked ends into one vertex (network.py);
    this is the same union over names, so a trail can be checked before the run. A link
    across parts may still break at run time, where the trail is built again."""
    names = _NAMES.get()
    if names is None:
        return True
    parent: dict[tuple[str, str], tuple[str, str]] = {}

    def root(end: tuple[str, str]) -> tuple[str, str]:
        while parent.get(end, end) != end:
            end = parent[end]
        return end

    def join(a: tuple[str, str], b: tuple[str, str]) -> None:
        parent[root(a)] = root(b)

    for name, (starts_from, ends_at, closed_loop) in names.track_links.items():
        if isinstance(starts_from, str):
            join((starts_from, "end"), (name, "start"))
        if isinstance(ends_at, str):
            join((name, "end"), (ends_at, "start"))
        if closed_loop is True:
            join((name, "end"), (name, "start"))
    return root((first, "end")) == root((second, "start"))


# -- planar.tracks ------------------------------------------------------------------------------


class CircleSpec(_Model):
    """AppendCircle (§7.2.2.10.4): the arc about ``center`` from ``start`` to ``end``."""

    blocks = ("MC_PlanarTrack.append_circle",)

    start: Point
    """[mm]."""
    end: Point
    """[mm]; equal to ``start``: the full circle."""
    center: Point
    """[mm]; equidistant from start and end."""
    clockwise: StrictBool
    """The direction of travel round the centre."""


class TrackElementSpec(_Model):
    """One geometry element: exactly one of ``line``, ``circle``, ``position``."""

    blocks = ("MC_PlanarTrack.append_line", "MC_PlanarTrack.append_position")

    line: tuple[Point, Point] | None = None
    """AppendLine (§7.2.2.10.3): [[x, y], [x, y]], start and end [mm]."""
    circle: CircleSpec | None = None
    """AppendCircle: {start, end, center, clockwise}."""
    position: Point | None = None
    """AppendPosition (§7.2.2.10.2): [x, y] [mm]; the first is the start point, a later one
    adds the line to it from the track's end."""

    @model_validator(mode="after")
    def _one_element(self) -> TrackElementSpec:
        if sum(element is not None for element in (self.line, self.circle, self.position)) != 1:
            raise ValueError("give exactly one of 'line', 'circle' or 'position'")
        return self

    @property
    def kind(self) -> str:
        return "line" if self.line is not None else "circle" if self.circle is not None \
            else "position"

    def send(self, track: MC_PlanarTrack, reference_id: int = 0) -> PlanarCommand:
        """Call the append method of this element on ``track``, its points in the frame of
        ``reference_id`` (the track's part, or 0)."""

        def at(point: Point) -> PositionXYC:
            return PositionXYC(point[0], point[1], 0.0, reference_id)

        if self.line is not None:
            return track.append_line(*(at(point) for point in self.line))
        if self.circle is not None:
            circle = self.circle
            return track.append_circle(at(circle.start), at(circle.end), at(circle.center),
                                       circle.clockwise)
        assert self.position is not None  # one element each (_one_element)
        return track.append_position(at(self.position))


class TrackLinkSpec(_Model):
    """The options of StartFromTrackAdvanced / EndAtTrackAdvanced (§7.2.1.2.14,
    §7.2.1.2.5, §6.2.13): for which part positions a link across parts is built."""

    this_track_part_position_index: Annotated[StrictInt, Field(ge=0)] = 0
    """The position of this track's part the link is built for (1-based; 0: the active
    one)."""
    other_track_part_position_index: Annotated[StrictInt, Field(ge=0)] = 0
    """The same for the other track's part."""
    link_only_in_specified_part_positions: StrictBool = False
    """The link holds only in those positions, not wherever the two ends meet."""

    def values(self) -> tuple[int, int, bool]:
        return (self.this_track_part_position_index, self.other_track_part_position_index,
                self.link_only_in_specified_part_positions)


class TrackSpec(_Model):
    """One MC_PlanarTrack (§6.2): its links and geometry, and its init parameters."""

    blocks = ("MC_PlanarTrack.start_from_track", "MC_PlanarTrack.end_at_track",
              "MC_PlanarTrack.start_from_track_advanced", "MC_PlanarTrack.end_at_track_advanced",
              "MC_PlanarTrack.close_loop", "MC_PlanarTrack.enable", "MC_PlanarTrack.update")

    name: Annotated[Identifier, _unique("planar_tracks"), AfterValidator(_own_track_name)]
    """Unique, not the name of a planar mover or group; entries refer to it."""
    starts_from: TrackName | None = None
    """StartFromTrack (§6.2.10): the track begins where this one ends, smoothly."""
    geometry: list[TrackElementSpec] = []
    """The elements in order; the gaps and corners between them are blended (§6.2.10)."""
    closed_loop: StrictBool = False
    """CloseLoop: join the end back to the start; s counts modulo the length."""
    ends_at: TrackName | None = None
    """EndAtTrack: the track ends smoothly where this one starts."""
    starts_from_options: TrackLinkSpec | None = None
    """StartFromTrackAdvanced instead of StartFromTrack, with these options."""
    ends_at_options: TrackLinkSpec | None = None
    """EndAtTrackAdvanced instead of EndAtTrack, with these options."""
    part: Annotated[ObjectId, AfterValidator(_check_planar_part)] | None = None
    """The part the track lies on (§6.2.3; MC_PlanarTrack's part_oid): its geometry is
    then given in the part frame and moves with the part."""
    collision_ranges: tuple[Annotated[Number, Field(ge=0.0)],
                            Annotated[Number, Field(ge=0.0)]] | None = None
    """[start, end] [mm] (collision range mode Manual, §6.2.2); default: computed from the
    geometry when the track is enabled (Automatic)."""
    max_mover_width: Annotated[Number, Field(gt=0.0)] = MAX_MOVER_SIZE
    """The widest mover that travels on it [mm] (its surface and automatic ranges)."""
    max_mover_height: Annotated[Number, Field(gt=0.0)] = MAX_MOVER_SIZE
    """[mm], along y as the movers' ``mover_height``."""

    @model_validator(mode="after")
    def _links(self) -> TrackSpec:
        for field, other in (("starts_from", self.starts_from), ("ends_at", self.ends_at)):
            if other == self.name:
                raise ValueError(f"{field}: a track cannot link to itself; a loop is "
                                 "closed_loop: true")
        for field, other in (("starts_from_options", self.starts_from),
                             ("ends_at_options", self.ends_at)):
            if getattr(self, field) is not None and other is None:
                raise ValueError(f"{field}: options of a link that is not there (give "
                                 f"{field.removesuffix('_options')})")
        if self.closed_loop and (self.starts_from or self.ends_at):
            raise ValueError("closed_loop: a closed loop neither starts from nor ends at "
                             "another track")
        if not self.geometry and not (self.starts_from and self.ends_at):
            raise ValueError("geometry: give at least one line, circle or position (a track "
                             "with none must have both starts_from and ends_at: the curve "
                             "between them)")
        return self

    def build(self, rt: Runtime) -> MC_PlanarTrack:
        ranges = None if self.collision_ranges is None else \
            (float(self.collision_ranges[0]), float(self.collision_ranges[1]))
        return MC_PlanarTrack(rt, self.name, max_mover_width=self.max_mover_width,
                              max_mover_height=self.max_mover_height, collision_ranges=ranges,
                              part_oid=self.part or 0)

    def stage(self, stage: Stage, tracks: dict[str, MC_PlanarTrack]
              ) -> Iterator[tuple[Loc, PlanarCommand]]:
        """Send the commands of one stage to the track; each with its field path."""
        track = tracks[self.name]
        if stage == "end":
            if self.ends_at is not None and self.ends_at_options is not None:
                yield ("ends_at",), track.end_at_track_advanced(
                    tracks[self.ends_at],
                    ST_EndAtTrackAdvancedOptions(*self.ends_at_options.values()))
            elif self.ends_at is not None:
                yield ("ends_at",), track.end_at_track(tracks[self.ends_at])
            return
        if self.starts_from is not None and self.starts_from_options is not None:
            yield ("starts_from",), track.start_from_track_advanced(
                tracks[self.starts_from],
                ST_StartFromTrackAdvancedOptions(*self.starts_from_options.values()))
        elif self.starts_from is not None:
            yield ("starts_from",), track.start_from_track(tracks[self.starts_from])
        for index, element in enumerate(self.geometry):
            yield ("geometry", index), element.send(track, self.part or 0)
        if self.closed_loop:
            yield ("closed_loop",), track.close_loop()


def build_order(tracks: Sequence[TrackSpec]) -> tuple[list[tuple[int, Stage]], list[int]]:
    """(track index, stage) in an order in which every link finds its other track ready, and
    the indices of the tracks that cannot be built (a ring of links)."""
    index = {track.name: k for k, track in enumerate(tracks)}
    done: set[tuple[int, Stage]] = set()

    def complete(k: int) -> bool:
        return (k, "end") in done

    def shaped(k: int) -> bool:
        """The track has its start pose: geometry of its own, or it is complete."""
        return (k, "geometry") in done and bool(tracks[k].geometry) or complete(k)

    ready: dict[Stage, Callable[[TrackSpec], bool]] = {
        "geometry": lambda t: t.starts_from is None or complete(index[t.starts_from]),
        "end": lambda t: (index[t.name], "geometry") in done and (
            t.ends_at is None or shaped(index[t.ends_at]))}
    order: list[tuple[int, Stage]] = []
    stages: tuple[Stage, ...] = ("geometry", "end")
    while True:  # the first stage in file order that can go next, so dependants follow soon
        step = next(((k, stage) for k, track in enumerate(tracks) for stage in stages
                     if (k, stage) not in done and ready[stage](track)), None)
        if step is None:
            return order, [k for k in range(len(tracks)) if not complete(k)]
        done.add(step)
        order.append(step)


def order_problems(tracks: Sequence[TrackSpec]) -> Iterator[tuple[Loc, str]]:
    """A ring of links that no order can build, at the link of each track in it."""
    _, stuck = build_order(tracks)
    names = {tracks[k].name for k in stuck}
    listed = ", ".join(tracks[k].name for k in stuck)
    for k in stuck:
        field = "starts_from" if tracks[k].starts_from in names else "ends_at"
        yield ("tracks", k, field), f"tracks {listed} wait for each other: StartFromTrack " \
                                    "needs the other track finished, EndAtTrack its geometry"


# -- the summary ------------------------------------------------------------------------------


@dataclass(frozen=True)
class PlanarTrackRow:
    """One planar track at the end of a run."""

    track: str
    oid: int
    group: str  #: the planar group it is in; "" for none
    length: float  #: [mm]
    state: str  #: PlanarState name in lower case
    operation_mode: str  #: TrackOperationMode name in lower case
    closed_loop: bool
    collision_ranges: tuple[float, float]  #: [mm] at its start and end, as in force
    movers: tuple[str, ...]  #: the movers on it, by their arc length


def track_table(rows: list[PlanarTrackRow], number: Callable[[float], str]) -> Table:
    """The summary's ``Tracks`` table: the collision ranges in force (to 0.1 mm) and how
    many movers are on each track (``Movers on tracks`` names them)."""
    from rich import box
    from rich.table import Table
    from rich.text import Text

    table = Table(box=box.SIMPLE, title_justify="left", title="Tracks")
    for name in ("track", "oid", "group", "length [mm]", "ranges [mm]", "state", "mode",
                 "movers"):
        table.add_column(Text(name), justify="left" if name in ("track", "oid", "group",
                                                                "state", "mode") else "right",
                         no_wrap=True)
    for row in rows:
        loop = " loop" if row.closed_loop else ""
        table.add_row(row.track, f"16#{row.oid:08X}", row.group or "-",
                      number(row.length) + loop,
                      " / ".join(f"{value:.1f}" for value in row.collision_ranges),
                      row.state, row.operation_mode, str(len(row.movers)))
    return table


def riders_table(rows: Sequence[Any], number: Callable[[float], str]) -> Table:
    """The summary's ``Movers on tracks`` table: each mover's track and arc length s there
    (``rows``: the PlanarMoverRows)."""
    from rich import box
    from rich.table import Table
    from rich.text import Text

    table = Table(box=box.SIMPLE, title_justify="left", title="Movers on tracks")
    for name in ("mover", "track", "s [mm]"):
        table.add_column(Text(name), justify="right" if name == "s [mm]" else "left",
                         no_wrap=True)
    for row in rows:
        table.add_row(row.mover, row.track or "-", "-" if row.s is None else number(row.s))
    return table

