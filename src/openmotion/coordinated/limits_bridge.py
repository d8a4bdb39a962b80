"""The caps of a group's path pieces from its member axes' limits (limits.py does the math).

The group knows its members and kinematics; limits.py knows elements and axis limits. This is
the seam: one ``Limits`` per member from its parameters, then the caps of one element, or of
many lines at once (MC_MovePath's dense paths).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.coordinated.dense import DENSE_MIN, derivative_bounds
from openmotion.coordinated.dense_timing import planned_time
from openmotion.coordinated.kinematics import CartesianGantry
from openmotion.coordinated.limits import (
    DENSE_SHARES,
    DirectLine,
    direct_limits,
    line_limits,
    many_limits,
    path_limits,
)
from openmotion.geometry.blend import Contour
from openmotion.geometry.path import Line
from openmotion.trajectory.plan import Limits

if TYPE_CHECKING:
    from openmotion.coordinated.group import AxesGroup

__all__ = ["DirectLine", "axis_limits", "caps_for", "caps_for_many", "dense_path"]


def axis_limits(group: AxesGroup) -> list[Limits]:
    """Each member's own maxima (TcMC parameters), in IdentInGroup order."""
    return [Limits(a.parameters.max_velocity, a.parameters.max_acceleration,
                   a.parameters.max_deceleration, a.parameters.max_jerk) for a in group.axes]


def caps_for(group: AxesGroup, element: Any, space: str,
             dynamics: tuple[float, float, float, float],
             limits: Sequence[Limits] | None = None) -> tuple[float, float, float, float]:
    """Velocity, acceleration, deceleration and jerk caps on the path parameter of
    ``element`` that keep every member within its limits (limits.py)."""
    limits = axis_limits(group) if limits is None else limits
    commanded = Limits(*dynamics)
    if isinstance(element, DirectLine):
        caps = direct_limits(element, limits, commanded)
    else:
        spaces = group.spaces
        caps = path_limits(element, spaces.kinematics, limits, commanded,
                           configuration=spaces.configuration)
    return (caps.velocity, caps.acceleration, caps.deceleration, caps.jerk)


def dense_path(group: AxesGroup, elements: Sequence[Any], space: str) -> bool:
    """Whether ``elements`` are a dense path of a gantry: ``DENSE_MIN`` or more blend contours
    in one command (D-290). Its contours get the dense shares (D-336) and the time law runs
    it by one profile (D-335)."""
    if space == "ACS" or not isinstance(group.spaces.kinematics, CartesianGantry):
        return False
    return sum(type(e) is Contour for e in elements) >= DENSE_MIN


def caps_for_many(group: AxesGroup, elements: Sequence[Any], space: str,
                  dynamics: tuple[float, float, float, float]
                  ) -> list[tuple[float, float, float, float]]:
    """``caps_for`` of every element; the lines of a gantry in one vectorised pass, and the
    contours of a dense path too, with the shares of ``DENSE_SHARES`` under which its
    profile plans fastest (D-336)."""
    limits = axis_limits(group)
    kinematics = group.spaces.kinematics
    gantry = space != "ACS" and isinstance(kinematics, CartesianGantry)
    lines = [i for i, e in enumerate(elements) if type(e) is Line] if gantry else []
    contours = [i for i, e in enumerate(elements) if type(e) is Contour] if gantry else []
    caps = np.full((len(elements), 4), np.nan)
    if len(lines) > 1:
        directions = np.array([elements[i].direction for i in lines])
        caps[lines] = line_limits(directions, kinematics, limits, Limits(*dynamics))
    dense = len(contours) >= DENSE_MIN
    batched = set(contours) if dense else set()
    for i, element in enumerate(elements):
        if np.isnan(caps[i, 0]) and i not in batched:
            caps[i] = caps_for(group, element, space, dynamics, limits)
    if dense:  # a dense path's contours in one pass (D-290, D-336)
        bounds = derivative_bounds([elements[i] for i in contours])
        lengths = np.array([e.length for e in elements], dtype=float)
        best, chosen = np.inf, caps
        for rate, turning in DENSE_SHARES:
            table = many_limits(bounds, kinematics, limits, Limits(*dynamics),
                                rate_share=rate, turning_share=turning)
            trial = caps.copy()
            trial[contours] = table
            duration = planned_time(lengths, trial[:, 0], trial[:, 1], trial[:, 2])
            if duration < best or chosen is caps:
                best, chosen = duration, trial
        caps = chosen
    return [tuple(row) for row in caps.tolist()]
