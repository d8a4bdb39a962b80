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
from openmotion.coordinated.kinematics import CartesianGantry
from openmotion.coordinated.limits import (
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

__all__ = ["DirectLine", "axis_limits", "caps_for", "caps_for_many"]


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


def caps_for_many(group: AxesGroup, elements: Sequence[Any], space: str,
                  dynamics: tuple[float, float, float, float]
                  ) -> list[tuple[float, float, float, float]]:
    """``caps_for`` of every element; the lines of a gantry in one vectorised pass."""
    limits = axis_limits(group)
    kinematics = group.spaces.kinematics
    lines = [i for i, e in enumerate(elements) if type(e) is Line] \
        if space != "ACS" and isinstance(kinematics, CartesianGantry) else []
    caps: list[Any] = [None] * len(elements)
    contours = [i for i, e in enumerate(elements) if type(e) is Contour] \
        if space != "ACS" and isinstance(kinematics, CartesianGantry) else []
    if len(contours) >= DENSE_MIN:  # a dense path's contours in one pass (D-290)
        bounds = derivative_bounds([elements[i] for i in contours])
        table = many_limits(bounds, kinematics, limits, Limits(*dynamics))
        for i, row in zip(contours, table.tolist(), strict=True):
            caps[i] = tuple(row)
    if len(lines) > 1:
        directions = np.array([elements[i].direction for i in lines])
        table = line_limits(directions, kinematics, limits, Limits(*dynamics))
        for i, row in zip(lines, table.tolist(), strict=True):
            caps[i] = tuple(row)
    for i, element in enumerate(elements):
        if caps[i] is None:
            caps[i] = caps_for(group, element, space, dynamics, limits)
    return caps
