"""Planar frames: 2-D rigid transforms between a part frame and its coordinate system.

TF5430 §5.1 places every part in a coordinate system by the position of the part's own frame
(origin at the part's lower-left corner). A ``Pose`` (x, y, c) is both a position of a mover
and such a placement: composing the placement of a part with a pose given on the part gives
the pose in the coordinate system. Rotations by multiples of 90° are exact, so that stator
corners stay on the 240 mm grid after any number of round trips.
"""

from __future__ import annotations

from typing import NamedTuple

from openmotion.core.angles import cos_sin as cos_sin  # the planar frames' trigonometry


class Pose(NamedTuple):
    """A planar pose, or the placement of a child frame in its parent frame.

    ``c`` is not wrapped: composing adds angles, so a round trip gives back the same c.
    """

    x: float = 0.0  #: [mm]
    y: float = 0.0  #: [mm]
    c: float = 0.0  #: rotation about the vertical axis, counter-clockwise [°]

    def compose(self, inner: Pose) -> Pose:
        """``inner``, given in the frame this pose places, expressed in the parent frame."""
        cos, sin = cos_sin(self.c)
        return Pose(
            self.x + cos * inner.x - sin * inner.y,
            self.y + sin * inner.x + cos * inner.y,
            self.c + inner.c,
        )

    def inverse(self) -> Pose:
        """The parent frame placed in the child frame, so that ``p.inverse().compose(p)`` is 0."""
        cos, sin = cos_sin(self.c)
        return Pose(-(cos * self.x + sin * self.y), sin * self.x - cos * self.y, -self.c)

    def affine(self) -> list[float]:
        """This placement as the matrix ``shapely.affinity.affine_transform`` takes."""
        cos, sin = cos_sin(self.c)
        return [cos, -sin, sin, cos, self.x, self.y]
