"""MC_PathSelect's PathData: a path given as data, prepared once for MC_MovePath (§5.26).

A path description is a sequence of elements, each a mapping:

- ``{"line": [x, y, z]}``: a straight line to that point;
- ``{"arc": [x, y, z], "aux": [x, y, z], "circ_mode": "BORDER", "path_choice": ...}``: an
  arc to that point, with the CircModes of MC_MoveCircularAbsolute;
- optional on either: ``"transition_mode"`` and ``"transition_parameter"`` for the corner
  at the element's start (defaults: those given to ``select_path``).

Points are MCS or PCS coordinates (x, y, z of the TCP; missing ones 0). The first element
starts where the TCP is when MC_MovePath begins. All geometry after the first element, the
contours included, is built here, so that MC_MovePath starts a 10 000-element path without
building anything in the cycle (decisions D-112). Contours are those of the group FBs
(geometry/blend.py) with TMCornerDistance or TMMaxCornerDeviation; a corner without contour
is an exact stop. A run of lines with one blending transition is rounded in bulk
(coordinated/dense.py, D-290): the same contours to round-off, a hundredth of the time.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.coordinated.dense import DENSE_MIN, blend_lines, blendable
from openmotion.coordinated.inputs import (
    CoordSystem,
    TransitionMode,
    enum_value,
    transition_mode,
    transition_parameter,
)
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.geometry.blend import corner_distance_blend, max_corner_deviation_blend
from openmotion.geometry.path import Arc, CircMode, Line, PathChoice, as_point

if TYPE_CHECKING:
    from openmotion.coordinated.group import AxesGroup


@dataclass(frozen=True)
class PathData:
    """A prepared path (MC_PathSelect's output)."""

    coord_system: CoordSystem
    first: tuple[Any, ...]  #: the first element's description, built from the start later
    elements: tuple[Any, ...]  #: geometry after the first element, contours inserted
    exits: tuple[float, ...]  #: per element: the speed cap at its end (0: exact stop)
    first_transition: tuple[TransitionMode, float]  #: corner between first and second
    length: float  #: arc length after the first element [mm]
    count: int  #: elements in the description


def select_path(group: AxesGroup, description: Any, coord_system: Any = CoordSystem.MCS,
                mode: Any = TransitionMode.TM_MAX_CORNER_DEVIATION,
                parameter: Any = 0.1) -> PathData:
    """Check and prepare ``description``; ``CommandRejected`` names the bad element."""
    coord = enum_value(CoordSystem, coord_system, "CoordSystem")
    if coord is CoordSystem.ACS:
        raise CommandRejected(ErrorId.INVALID_MODE, "PathData is given in MCS or PCS")
    if not isinstance(description, Sequence) or isinstance(description, str | bytes) \
            or not description:
        raise CommandRejected(ErrorId.INVALID_PATH_GEOMETRY,
                              "PathDescription: a non-empty list of elements")
    default = (transition_mode(mode), 0.0)
    default = (default[0], transition_parameter(default[0], parameter))
    frame = group.spaces.frame(group.runtime.now) if coord is CoordSystem.PCS else None
    parsed = _parse_lines(description, frame, default) or \
        [_parse(i, item, frame, default) for i, item in enumerate(description)]
    elements: list[Any] = []
    exits: list[float] = []
    previous_end = parsed[0][1]
    index = 1
    while index < len(parsed):
        kind, end, aux, circ, choice, transition = parsed[index]
        run = _line_run(parsed, index) if elements and type(elements[-1]) is Line else index
        if run - index >= DENSE_MIN:  # many lines with one transition: in bulk (D-290)
            blend_lines(elements, exits, np.array([p[1] for p in parsed[index:run]]), index,
                        transition, _contour)
            previous_end = parsed[run - 1][1]
            index = run
            continue
        number, index = index, index + 1
        try:
            element = Line(previous_end, end) if kind == "line" else \
                Arc.from_circ_mode(circ, previous_end, aux, end, choice)
        except CommandRejected as rejected:
            raise CommandRejected(rejected.error_id,
                                  f"element {number}: {rejected.message}") from None
        if elements:
            contour = _contour(elements[-1], element, transition)
            if contour is None:
                exits[-1] = 0.0
            else:
                elements[-1] = contour.before
                elements.append(contour.contour)
                exits.append(math.inf)
                element = contour.after
        elements.append(element)
        exits.append(math.inf)
        previous_end = end
    if exits:
        exits[-1] = 0.0
    head = parsed[0]
    second = parsed[1][5] if len(parsed) > 1 else default
    return PathData(coord, head, tuple(elements), tuple(exits), second,
                    float(sum(e.length for e in elements)), len(parsed))


def _line_run(parsed: list[Any], index: int) -> int:
    """The end (exclusive) of the run of lines from ``index`` whose corners all have the
    transition of the first, a blending one; ``index`` itself if there is none."""
    transition = parsed[index][5]
    if not blendable(transition):
        return index
    end = index
    while end < len(parsed) and parsed[end][0] == "line" and parsed[end][5] == transition:
        end += 1
    return end


def _parse_lines(description: Sequence[Any], frame: Any, default: tuple[TransitionMode, float]
                 ) -> list[Any]:
    """``_parse`` of every element at once where all are plain ``{"line": point}`` mappings
    of finite points with 1 to 3 coordinates in the MCS, as a CAM path's are; else [] (and
    ``_parse`` element by element, which names what is wrong)."""
    if frame is not None or not all(type(item) is dict and len(item) == 1 and "line" in item
                                    for item in description):
        return []
    try:
        values = np.array([item["line"] for item in description], dtype=float)
    except (TypeError, ValueError):
        return []
    if values.ndim != 2 or not 1 <= values.shape[1] <= 3 or not np.all(np.isfinite(values)):
        return []
    points = np.zeros((len(values), 3))
    points[:, :values.shape[1]] = values
    return [("line", point, None, None, None, default) for point in points]


def _parse(index: int, item: Any, frame: Any, default: tuple[TransitionMode, float]
           ) -> tuple[str, np.ndarray, Any, Any, Any, tuple[TransitionMode, float]]:
    if not isinstance(item, Mapping) or ("line" in item) == ("arc" in item):
        raise CommandRejected(ErrorId.INVALID_PATH_GEOMETRY,
                              f"element {index}: a mapping with 'line' or 'arc'")
    kind = "line" if "line" in item else "arc"

    def point(value: Any, name: str, offset: bool = False) -> np.ndarray:
        raw = np.zeros(3)
        values = np.asarray(value, dtype=float).ravel()
        if not 1 <= values.size <= 3:
            raise CommandRejected(ErrorId.INVALID_POSITION,
                                  f"element {index}: {name} needs 1 to 3 coordinates")
        raw[: values.size] = values
        p = as_point(raw, f"element {index} {name}")
        if frame is None:
            return p
        return frame.rotate(p) if offset else frame.apply(p)

    end = point(item[kind], kind)
    aux = circ = choice = None
    if kind == "arc":
        circ = enum_value(CircMode, _named(CircMode, item.get("circ_mode", CircMode.BORDER)),
                          "circ_mode")
        choice = enum_value(PathChoice, _named(PathChoice, item.get(
            "path_choice", PathChoice.COUNTERCLOCKWISE)), "path_choice")
        if "aux" not in item:
            raise CommandRejected(ErrorId.INVALID_PATH_GEOMETRY, f"element {index}: arc needs aux")
        aux = point(item["aux"], "aux", offset=circ is CircMode.RADIUS)
    transition = default
    if "transition_mode" in item:
        mode = transition_mode(_named(TransitionMode, item["transition_mode"]))
        transition = (mode, transition_parameter(mode, item.get("transition_parameter")))
    return kind, end, aux, circ, choice, transition


def _named(kind: Any, value: Any) -> Any:
    """Enum members by name too ("BORDER", "TM_NONE"), as scenario files write them."""
    if isinstance(value, str) and value in kind.__members__:
        return kind[value]
    return value


def _contour(before: Any, after: Any, transition: tuple[TransitionMode, float]) -> Any:
    mode, value = transition
    try:
        if mode is TransitionMode.TM_CORNER_DISTANCE:
            return corner_distance_blend(before, after, value)
        if mode is TransitionMode.TM_MAX_CORNER_DEVIATION:
            return max_corner_deviation_blend(before, after, value)
    except CommandRejected:
        return None  # reversal or degenerate corner: stop there
    return None
