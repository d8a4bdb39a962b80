"""From a motion FB's inputs to a ``PathCommand``: checks, coordinate systems, geometry.

Positions are vectors in the FB's CoordSystem (§2.1): one value per member axis in ACS, one per
kinematics coordinate in MCS and PCS (``group.kinematics.coordinates``). A static PCS is
turned into MCS geometry when the command is built; in a moving PCS (tracking, §2.2) the
geometry stays in the PCS and the cycle places it every sample. Path moves keep the
orientation coordinates (a, b, c) where they are; an orientation change needs MC_MoveDirect*
(decisions D-111).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.axis.commands import Command
from openmotion.coordinated.inputs import (
    CoordSystem,
    PathMoveOptions,
    enum_value,
    path_dynamics,
    transition_mode,
    transition_parameter,
    vector,
)
from openmotion.coordinated.limits_bridge import DirectLine
from openmotion.coordinated.moves import ACS, MCS, PCS, PathCommand
from openmotion.coordinated.paths import PathData, _contour
from openmotion.coordinated.tolerances import ORIENTATION_TOLERANCE
from openmotion.core.enums import BufferMode
from openmotion.core.errors import CommandRejected, ErrorId
from openmotion.geometry.path import TOLERANCE, Arc, CircMode, Line, PathChoice

if TYPE_CHECKING:
    from openmotion.coordinated.group import AxesGroup



def build_request(group: AxesGroup, command: Command, kind: str, target: Any, circle: Any,
                  options: PathMoveOptions, buffer_mode: BufferMode,
                  relative: bool) -> PathCommand:
    """The checked request of one path move; ``buffer_mode`` is the checked
    ``options.buffer_mode``."""
    coord = enum_value(CoordSystem, options.coord_system, "CoordSystem")
    mode = transition_mode(options.transition_mode)
    if buffer_mode is BufferMode.ABORTING and mode in (
            mode.TM_CORNER_DISTANCE, mode.TM_MAX_CORNER_DEVIATION):
        raise CommandRejected(ErrorId.INVALID_MODE,
                              f"BufferMode Aborting with {mode.name} is not defined (§2.4.4)")
    joins = buffer_mode is BufferMode.ABORTING and mode in (
        mode.TM_START_VELOCITY, mode.TM_CONSTANT_VELOCITY)  # at speed (moves.py, D-195)
    value = transition_parameter(mode, options.transition_parameter) \
        if buffer_mode is not BufferMode.BUFFERED and (
            buffer_mode is not BufferMode.ABORTING or joins) else 0.0
    if buffer_mode is BufferMode.BUFFERED:
        mode = mode.TM_NONE  # §7.3.2: TransitionMode is not evaluated
    dynamics = path_dynamics(group.dynamics, command.warnings, options.velocity,
                             options.acceleration, options.deceleration, options.jerk)
    spaces = group.spaces
    if kind == "direct" or (kind == "linear" and coord is CoordSystem.ACS):
        size = len(group.members) if coord is CoordSystem.ACS else spaces.size
        values = vector(target, size, "Distance" if relative else "Position")
        build = _direct(group, coord, values, relative)
        space = ACS
    elif kind == "path":
        if not isinstance(target, PathData):
            raise CommandRejected(ErrorId.INVALID_PATH_GEOMETRY,
                                  "MC_MovePath needs the PathData of a Done MC_PathSelect "
                                  "(§5.26)")
        space = MCS
        request = PathCommand(command, target.coord_system, lambda s, r: [], dynamics,
                              buffer_mode, mode, value, space)
        request.build = _path(group, target, request)
        return request
    else:
        if coord is CoordSystem.ACS:
            raise CommandRejected(ErrorId.INVALID_MODE,
                                  "a circle is defined in MCS or PCS, not in ACS (§5.22)")
        values = vector(target, spaces.size, "Distance" if relative else "EndPoint"
                        if kind == "circular" else "Position")
        space = PCS if coord is CoordSystem.PCS and spaces.dynamic is not None else MCS
        build = _cartesian(group, coord, space, kind, values, circle, relative)
    return PathCommand(command, coord, build, dynamics, buffer_mode, mode, value, space)


def _direct(group: AxesGroup, coord: CoordSystem, values: np.ndarray, relative: bool) -> Any:
    spaces = group.spaces

    def build(start: np.ndarray, reference: np.ndarray) -> list[Any]:
        if coord is CoordSystem.ACS:
            goal = reference + values if relative else values
        else:
            now = group.runtime.now
            mcs = spaces.to_mcs(reference)
            if coord is CoordSystem.PCS:
                base = spaces.pcs_of(mcs, now)
                pcs = base + values if relative else values
                mcs_goal = spaces.mcs_of(pcs, now)
            else:
                mcs_goal = mcs + values if relative else values
            goal = spaces.to_acs(mcs_goal)
        if float(np.linalg.norm(goal - start)) <= TOLERANCE:
            return []
        return [DirectLine(start, goal)]
    return build


def _cartesian(group: AxesGroup, coord: CoordSystem, space: str, kind: str,
               values: np.ndarray, circle: Any, relative: bool) -> Any:
    spaces = group.spaces
    if circle is not None:
        aux_raw, circ_mode, path_choice = circle
        circ_mode = enum_value(CircMode, circ_mode, "CircMode")
        path_choice = enum_value(PathChoice, path_choice, "PathChoice")
        aux = vector(aux_raw, spaces.size, "AuxPoint")

    def placed(point: np.ndarray, offset: bool = False) -> np.ndarray:
        """A PCS point (or offset) of the FB in the build space."""
        if coord is CoordSystem.PCS and space == MCS:
            frame = spaces.frame(group.runtime.now)
            return frame.rotate(point) if offset else frame.apply(point)
        return point

    def build(start: np.ndarray, reference: np.ndarray) -> list[Any]:
        start_xyz, reference_xyz = spaces.xyz(start), spaces.xyz(reference)
        goal = placed(spaces.xyz(values), offset=relative)
        end = reference_xyz + goal if relative else goal
        orientation = values if not relative else reference + values
        _check_orientation(spaces, start, orientation, relative, values)
        if kind == "linear":
            if float(np.linalg.norm(end - start_xyz)) <= TOLERANCE:
                return []
            return [Line(start_xyz, end)]
        aux_xyz = spaces.xyz(aux)
        if circ_mode is CircMode.RADIUS:
            aux_point = placed(aux_xyz, offset=True)
        else:
            aux_point = placed(aux_xyz, offset=relative)
            if relative:
                aux_point = reference_xyz + aux_point
        return [Arc.from_circ_mode(circ_mode, start_xyz, aux_point, end, path_choice)]
    return build


def _check_orientation(spaces: Any, start: np.ndarray, goal: np.ndarray, relative: bool,
                       values: np.ndarray) -> None:
    mask = np.ones(spaces.size, dtype=bool)
    mask[spaces.slots] = False
    if not mask.any():
        return
    change = values[mask] if relative else goal[mask] - start[mask]
    if np.any(np.abs(change) > ORIENTATION_TOLERANCE):
        raise CommandRejected(ErrorId.INVALID_POSITION,
                              "path moves keep the orientation (a, b, c); change it with "
                              "MC_MoveDirect* (decisions D-111)")


def _path(group: AxesGroup, data: PathData, request: PathCommand) -> Any:
    """MC_MovePath: the first element from the start, its corner, then the prepared rest."""
    spaces = group.spaces

    def build(start: np.ndarray, reference: np.ndarray) -> list[Any]:
        kind, end, aux, circ, choice, _ = data.first
        start_xyz = spaces.xyz(start)
        first: list[Any] = []
        if float(np.linalg.norm(end - start_xyz)) > TOLERANCE:
            first = [Line(start_xyz, end) if kind == "line"
                     else Arc.from_circ_mode(circ, start_xyz, aux, end, choice)]
        rest = list(data.elements)
        exits = list(data.exits)
        head_exit = 0.0
        if first and rest:
            contour = _contour(first[0], rest[0], data.first_transition)
            if contour is not None:
                first = [contour.before, contour.contour]
                rest[0] = contour.after
                head_exit = math.inf
        geometry = first + rest
        caps = [math.inf] * (len(first) - 1) + [head_exit] * bool(first) + exits
        request.extra["exits"] = {i: c for i, c in enumerate(caps) if c != math.inf}
        return geometry
    return build
