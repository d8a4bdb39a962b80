"""Properties of path motion over random contours (PLCopen Part 4 §5.20-§5.23, §7; issue 7).

Each example lays out 2-6 MoveLinear / MoveCircular commands (absolute or relative; arcs in
BORDER, CENTER or RADIUS mode) in a random plane and gives them to a group: a Cartesian gantry
of 2 or 3 axes (possibly swapped, mirrored and shifted), a SCARA or the delta robot. The corners
turn by random angles, from a tangent joint through near-straight and ordinary corners to
near-reversals and reversals. Every command after the first is Buffered or one of the Blending
modes with a random TransitionMode and parameter; velocities, accelerations and jerks of the
commands and of the axes span decades. The commands go in through the group's public methods
(the FBs call the same), all in the first cycle or some of them later, while the path runs.
Every cycle we read the axes' setpoints and the TCP, and check:

1. continuity: the TCP moves at most the fastest commanded speed times the cycle time per
   cycle; every axis' position step is the trapezoid of its velocities within j·dt³/12; on a
   gantry the TCP's velocity vector never turns at speed faster than the axes' accelerations
   allow (a corner without a contour is passed at rest, a contour is tangent-continuous);
2. every axis within its own velocity, acceleration and jerk, to 1e-9 relative: the velocity
   setpoint; the acceleration setpoint (exact on a gantry, a difference quotient otherwise) and
   the velocity's difference quotient; the jerk from the difference quotients of both. A
   difference quotient is a mean over a cycle (or two), so it cannot exceed a limit the motion
   keeps;
3. the TCP leaves the programmed lines and arcs only near a blended corner: within the
   requested corner distance (TMCornerDistance), or within half of the neighbouring elements
   (every other mode); with TMMaxCornerDeviation it passes the corner no further than asked;
4. every command ends Done and the TCP rests on the last target within 1e-9 mm;

and, without a group, that inverse ∘ forward is the identity for random gantries, SCARAs and
delta robots (tests/coordinated/test_kinematics.py checks fixed ones).

Between two samples the TCP strays from the chord between them by at most A·dt²/8, A bounding
|d²x/dt²|; that is the tolerance of the corner deviation check (3). Bugs these tests found are
kept as ``@example``s, each with a comment naming what was wrong.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

import openmotion as om
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.inputs import CoordSystem, TransitionMode
from openmotion.coordinated.kinematics import (
    COORDINATES,
    CartesianGantry,
    Configuration,
    DeltaRobot,
    Kinematics,
    Scara,
)
from openmotion.coordinated.limits import path_limits
from openmotion.core.enums import BufferMode
from openmotion.core.errors import CommandRejected
from openmotion.geometry.blend import corner_distance_blend
from openmotion.geometry.path import Arc, CircMode, Line, PathChoice
from openmotion.trajectory.plan import Limits

B, T = BufferMode, TransitionMode
REL = 1e-9  #: relative tolerance on the axis limits
END_TOL = 1e-9  #: [mm] the last target
ON_PATH = 1e-8  #: [mm] a TCP this close to the programmed elements is on them
BLENDING = [B.BLENDING_LOW, B.BLENDING_PREVIOUS, B.BLENDING_NEXT, B.BLENDING_HIGH]
MAX_CYCLES = 100_000


def decades(low: float, high: float) -> st.SearchStrategy[float]:
    return st.floats(math.log10(low), math.log10(high)).map(lambda e: 10.0**e)


# -- the machine ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class AxisLimits:
    velocity: float  #: [mm/s or °/s]
    acceleration: float  #: [mm/s² or °/s²]
    deceleration: float
    jerk: float  #: [mm/s³ or °/s³]

    def parameters(self) -> dict[str, float]:
        return {"max_velocity": self.velocity, "max_acceleration": self.acceleration,
                "max_deceleration": self.deceleration, "max_jerk": self.jerk,
                "acceleration": self.acceleration, "deceleration": self.deceleration,
                "jerk": self.jerk}


@st.composite
def axis_limits(draw: Any, velocity: tuple[float, float] = (100.0, 1000.0)) -> AxisLimits:
    acceleration = draw(decades(500.0, 3e4))
    deceleration = draw(st.one_of(st.just(acceleration), decades(500.0, 3e4)))
    return AxisLimits(draw(decades(*velocity)), acceleration, deceleration,
                      draw(decades(2e4, 3e6)))


GANTRIES = [
    CartesianGantry(("x", "y")),
    CartesianGantry(("x", "y", "z")),
    CartesianGantry(("y", "x", "z"), sign=(1, -1, 1), offset=(5.0, -20.0, 3.0)),
    CartesianGantry(("z", "y", "x"), sign=(-1, -1, 1), offset=(0.0, 40.0, -7.5)),
]
SCARAS = [Scara(300.0, 250.0), Scara(300.0, 250.0, z_axis=True, c_axis=True)]
DELTA = DeltaRobot(base_radius=200.0, effector_radius=50.0, upper_arm=300.0, forearm=800.0)


# -- the contour ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Step:
    """One command: its element relative to the end tangent of the one before, and its inputs."""

    kind: str  #: "line" or "arc"
    turn: float  #: [rad] signed, from the previous end tangent to this start tangent
    size: float  #: [mm] line length, or arc radius
    sweep: float  #: [rad] arcs: signed, positive turns left in the contour's plane
    circ_mode: CircMode
    relative: bool  #: MC_Move*Relative instead of *Absolute
    dynamics: tuple[float, float, float, float]  #: velocity, acceleration, deceleration, jerk
    buffer_mode: BufferMode
    transition_mode: TransitionMode
    parameter: float | None  #: TransitionParameter
    delay: int  #: cycles after the command before it is issued


@dataclass(frozen=True)
class Scene:
    kinematics: Kinematics
    limits: tuple[AxisLimits, ...]
    start: tuple[float, ...]  #: ACS positions at the start
    steps: tuple[Step, ...]
    frame: tuple[float, float, float]  #: rotation angles [rad] of the contour's plane
    cycle_time: float

    @property
    def cartesian(self) -> bool:
        return isinstance(self.kinematics, CartesianGantry)


turns = st.one_of(
    st.just(0.0),  # a tangent joint
    st.floats(1e-5, 0.05),  # nearly straight on
    st.floats(0.05, math.pi - 0.05),
    st.floats(math.pi - 0.05, math.pi - 1e-5),  # nearly back the same way
    st.just(math.pi),  # a reversal
).flatmap(lambda a: st.sampled_from([a, -a]))

transitions = st.one_of(
    st.just((T.TM_NONE, None)),
    st.tuples(st.just(T.TM_START_VELOCITY), st.floats(1.0, 100.0)),
    st.tuples(st.just(T.TM_CONSTANT_VELOCITY), st.floats(1.0, 100.0)),
    st.tuples(st.just(T.TM_CORNER_DISTANCE), decades(0.01, 100.0)),
    st.tuples(st.just(T.TM_MAX_CORNER_DEVIATION), decades(1e-3, 20.0)),
)


@st.composite
def steps(draw: Any, first: bool, radius_mode: bool, late: bool, scale: float) -> Step:
    kind = draw(st.sampled_from(["line", "arc"]))
    if kind == "line":
        size, sweep, circ_mode = draw(decades(0.5, 60.0 * scale)), 0.0, CircMode.BORDER
    else:
        size = draw(decades(0.5, 30.0 * scale))
        sweep = draw(st.floats(0.05, 2 * math.pi - 0.1)) * draw(st.sampled_from([1, -1]))
        modes = [CircMode.BORDER]
        if abs(abs(sweep) - math.pi) > 0.02:  # CENTER cannot take a half circle
            modes.append(CircMode.CENTER)
            if radius_mode:
                modes.append(CircMode.RADIUS)
        circ_mode = draw(st.sampled_from(modes))
    velocity = draw(decades(20.0, 1000.0))
    dynamics = (velocity, draw(decades(500.0, 1e4)), draw(decades(500.0, 1e4)),
                draw(decades(5e3, 1e6)))
    buffer_mode = B.BUFFERED if first else draw(st.sampled_from([B.BUFFERED, *BLENDING]))
    mode, parameter = draw(transitions)
    delay = draw(st.one_of(st.just(0), st.integers(1, 400))) if late and not first else 0
    return Step(kind, draw(turns), size, sweep, circ_mode, draw(st.booleans()), dynamics,
                buffer_mode, mode, parameter, delay)


def contour(draw: Any, kinematics: Kinematics, late: bool, max_steps: int,
            scale: float = 1.0) -> tuple[tuple[Step, ...], tuple[float, float, float]]:
    spatial = "z" in kinematics.coordinates
    count = draw(st.integers(2, max_steps))
    chosen = tuple(draw(steps(k == 0, spatial, late, scale)) for k in range(count))
    assume(crawl_time(chosen) <= 20.0)
    angle = st.floats(-math.pi, math.pi)
    frame = (draw(angle), draw(angle), draw(angle)) if spatial else (0.0, 0.0, draw(angle))
    return chosen, frame


def crawl_time(chosen: tuple[Step, ...]) -> float:
    """A rough time [s] of the slow stretches: each element at its velocity, and the widest
    contour (half of both elements) at the TransitionParameter's share of the slower one.
    TMConstantVelocity 1 % makes the largest contour the curvature allows and runs it at 1 %
    (as Part 4 asks): minutes of simulation, which the examples leave out."""
    total = 0.0
    for before, after in zip((None, *chosen[:-1]), chosen, strict=True):
        total += length_of(after) / after.dynamics[0]
        if before is not None and after.buffer_mode in BLENDING and after.transition_mode in (
                T.TM_START_VELOCITY, T.TM_CONSTANT_VELOCITY):
            share = after.parameter / 100.0 * min(before.dynamics[0], after.dynamics[0])
            total += 0.5 * (length_of(before) + length_of(after)) / share
    return total


def length_of(step: Step) -> float:
    return step.size if step.kind == "line" else step.size * abs(step.sweep)


@st.composite
def gantry_scenes(draw: Any, late: bool = False, max_steps: int = 6) -> Scene:
    gantry = draw(st.sampled_from(GANTRIES))
    limits = tuple(draw(axis_limits()) for _ in range(gantry.n_axes))
    chosen, frame = contour(draw, gantry, late, max_steps)
    return Scene(gantry, limits, (0.0,) * gantry.n_axes, chosen, frame,
                 draw(st.sampled_from([0.001, 0.002])))


def inside(scene: Scene, test: Any) -> bool:
    """Every programmed element, densely sampled, passes ``test`` (points (m, 3))."""
    start = scene.kinematics.forward(np.array(scene.start))
    return all(test(c.element.position(np.linspace(0.0, c.element.length, 65)))
               for c in program(scene, start))


@st.composite
def scara_scenes(draw: Any, late: bool = False, max_steps: int = 6) -> Scene:
    """A SCARA (the ring 50-550 mm) at a random pose; contours kept 30 mm inside the ring."""
    scara = draw(st.sampled_from(SCARAS))
    base = st.one_of(st.floats(-180.0, 180.0), st.floats(150.0, 180.0), st.floats(-180.0, -150.0))
    start = [draw(base), draw(st.floats(40.0, 140.0))]  # often near the wrap at ±180°
    if scara.z_axis:
        start.append(draw(st.floats(-100.0, 0.0)))
    if scara.c_axis:
        start.append(draw(st.floats(-90.0, 90.0)))
    limits = tuple(draw(axis_limits((60.0, 600.0))) for _ in range(scara.n_axes))
    chosen, frame = contour(draw, scara, late, max_steps, scale=0.5)
    if scara.z_axis:  # planes tilted by at most 0.5 rad about x and about y
        frame = (0.5 * frame[0] / math.pi, 0.5 * frame[1] / math.pi, frame[2])
    scene = Scene(scara, limits, tuple(start), chosen, frame, 0.001)

    def in_ring(points: np.ndarray) -> bool:
        r = np.hypot(points[:, 0], points[:, 1])
        return bool(r.min() >= 80.0 and r.max() <= 520.0)

    assume(inside(scene, in_ring))
    return scene


@st.composite
def delta_scenes(draw: Any, late: bool = False, max_steps: int = 6) -> Scene:
    """The delta robot at a random pose, contours in a cylinder well inside its reach."""
    start = tuple(draw(st.floats(5.0, 45.0)) for _ in range(3))
    limits = tuple(draw(axis_limits((60.0, 600.0))) for _ in range(3))
    chosen, frame = contour(draw, DELTA, late, max_steps, scale=0.5)
    scene = Scene(DELTA, limits, start, chosen, frame, 0.001)

    def in_reach(points: np.ndarray) -> bool:
        r = np.hypot(points[:, 0], points[:, 1])
        return bool(r.max() <= 250.0 and points[:, 2].min() >= -1000.0
                    and points[:, 2].max() <= -700.0)

    assume(inside(scene, in_reach))
    return scene


def rotation(angles: tuple[float, ...]) -> np.ndarray:
    """Rz·Ry·Rx: the contour's plane is spanned by the first two columns."""
    (cx, cy, cz), (sx, sy, sz) = np.cos(angles), np.sin(angles)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def xyz_slots(kinematics: Kinematics) -> list[int]:
    return [i for i, name in enumerate(kinematics.coordinates) if name in ("x", "y", "z")]


def xyz(kinematics: Kinematics, mcs: np.ndarray) -> np.ndarray:
    """The TCP point(s) of MCS vector(s), z = 0 where the model has none."""
    slots = xyz_slots(kinematics)
    out = np.zeros(mcs.shape[:-1] + (3,))
    out[..., :len(slots)] = mcs[..., slots]
    return out


@dataclass
class Programmed:
    """A command's geometry and FB inputs."""

    step: Step
    element: Line | Arc  #: in MCS, 3-D
    end: np.ndarray  #: the target, an MCS vector
    inputs: dict[str, Any] = field(default_factory=dict)


def program(scene: Scene, start: np.ndarray) -> list[Programmed]:
    """Lay the steps out in a plane from ``start`` (MCS) and write each command's inputs."""
    slots = xyz_slots(scene.kinematics)
    plane = rotation(scene.frame)[:, :2]
    normal = np.cross(plane[:, 0], plane[:, 1])
    origin = xyz(scene.kinematics, start)
    here, heading = np.zeros(2), 0.0
    result = []

    def point(p2: np.ndarray) -> np.ndarray:
        return origin + plane @ p2

    def mcs(p3: np.ndarray, base: np.ndarray = start) -> np.ndarray:
        out = np.array(base, dtype=float)
        out[slots] = p3[:len(slots)]
        return out

    for step in scene.steps:
        heading += step.turn
        t = np.array([math.cos(heading), math.sin(heading)])
        aux: np.ndarray | None = None
        if step.kind == "line":
            end2 = here + step.size * t
            element: Line | Arc = Line(point(here), point(end2))
        else:
            left = math.copysign(1.0, step.sweep)
            centre2 = here + step.size * left * np.array([-t[1], t[0]])

            def turned(angle: float, c2: np.ndarray = centre2, h: np.ndarray = here
                       ) -> np.ndarray:
                c, s = math.cos(angle), math.sin(angle)
                w = h - c2
                return c2 + np.array([c * w[0] - s * w[1], s * w[0] + c * w[1]])

            end2, mid2 = turned(step.sweep), turned(0.5 * step.sweep)
            element = Arc.from_border(point(here), point(mid2), point(end2))
            aux = {CircMode.BORDER: point(mid2), CircMode.CENTER: point(centre2),
                   CircMode.RADIUS: left * step.size * normal}[step.circ_mode]
            heading += step.sweep
        begin, end = mcs(point(here)), mcs(point(end2))
        inputs: dict[str, Any] = dict(zip(("velocity", "acceleration", "deceleration", "jerk"),
                                          step.dynamics, strict=True))
        inputs.update(buffer_mode=step.buffer_mode, transition_mode=step.transition_mode,
                      transition_parameter=None if step.parameter is None
                      else [step.parameter])
        if aux is not None:
            inputs["circ_mode"] = step.circ_mode
            inputs["path_choice"] = PathChoice.CLOCKWISE if abs(step.sweep) > math.pi \
                else PathChoice.COUNTERCLOCKWISE
            if step.circ_mode is CircMode.RADIUS:  # a vector: the same in both FBs
                inputs["aux_point"] = mcs(aux, np.zeros_like(start))
            else:
                inputs["aux_point"] = mcs(aux) - begin if step.relative else mcs(aux)
            inputs["end_point"] = end - begin if step.relative else end
        elif step.relative:
            inputs["distance"] = end - begin
        else:
            inputs["position"] = end
        result.append(Programmed(step, element, end, inputs))
        here = end2
    return result


# -- running it ----------------------------------------------------------------------------------

@dataclass
class Run:
    dt: float
    tcp: np.ndarray  #: (samples, 3) TCP from the set positions
    tcp_velocity: np.ndarray  #: (samples, 3)
    p: np.ndarray  #: (samples, axes) set positions
    v: np.ndarray  #: set velocities
    a: np.ndarray  #: set accelerations
    commands: list[Any]


def group_for(scene: Scene) -> tuple[om.Runtime, AxesGroup, list[om.Axis]]:
    rt = om.Runtime(scene.cycle_time)
    group = AxesGroup(rt, "g")
    axes = []
    for ident, (limits, position) in enumerate(zip(scene.limits, scene.start, strict=True), 1):
        axis = rt.add_axis(f"a{ident}", position=position, **limits.parameters())
        assert axis.power()
        assert group.add_axis(axis, ident).done
        axes.append(axis)
    assert group.set_kinematics(scene.kinematics).done
    assert group.enable().done
    return rt, group, axes


def issue(group: AxesGroup, command: Programmed) -> Any:
    kind, relative = command.step.kind, command.step.relative
    if kind == "line":
        move = group.move_linear_relative if relative else group.move_linear_absolute
    else:
        move = group.move_circular_relative if relative else group.move_circular_absolute
    return move(**command.inputs)


def drive(scene: Scene) -> tuple[Run, list[Programmed]]:
    rt, group, axes = group_for(scene)
    model = scene.kinematics
    commands = program(scene, group.position(CoordSystem.MCS, actual=False))
    due = np.cumsum([c.step.delay for c in commands])
    issued: list[Any] = []
    samples: list[tuple[np.ndarray, ...]] = []

    def sample() -> None:
        p = np.array([x.set_position for x in axes])
        v = np.array([x.set_velocity for x in axes])
        a = np.array([x.set_acceleration for x in axes])
        samples.append((xyz(model, model.forward(p)), xyz(model, model.forward_velocity(p, v)),
                        p, v, a))

    sample()
    for cycle in range(MAX_CYCLES):
        while len(issued) < len(commands) and due[len(issued)] <= cycle:
            issued.append(issue(group, commands[len(issued)]))
        if len(issued) == len(commands) and all(c.finished for c in issued) \
                and group.all_axes_standing:
            break
        rt.step()
        sample()
    else:
        pytest.fail(f"the contour did not end within {MAX_CYCLES} cycles: "
                    f"{[c.status.name for c in issued]}")
    columns = [np.array(column) for column in zip(*samples, strict=True)]
    return Run(scene.cycle_time, *columns, commands=issued), commands


# -- distances to the programmed path ------------------------------------------------------------

def to_line(points: np.ndarray, line: Line) -> np.ndarray:
    along = np.clip((points - line.start) @ line.direction, 0.0, line.length)
    return np.linalg.norm(points - (line.start + along[:, None] * line.direction), axis=1)


def to_arc(points: np.ndarray, arc: Arc) -> np.ndarray:
    w = points - arc.center
    height = w @ arc.normal
    flat = w - height[:, None] * arc.normal
    u = (arc.start - arc.center) / arc.radius
    v = np.cross(arc.normal, u)
    angle = np.arctan2(flat @ v, flat @ u) % (2 * math.pi)
    inside = np.hypot(height, np.linalg.norm(flat, axis=1) - arc.radius)
    ends = np.minimum(np.linalg.norm(points - arc.start, axis=1),
                      np.linalg.norm(points - arc.end, axis=1))
    return np.where(angle <= arc.sweep, inside, ends)


def off_path(points: np.ndarray, commands: list[Programmed]) -> np.ndarray:
    return np.min([to_line(points, c.element) if isinstance(c.element, Line)
                   else to_arc(points, c.element) for c in commands], axis=0)


def to_polyline(point: np.ndarray, polyline: np.ndarray) -> float:
    a, b = polyline[:-1], polyline[1:]
    ab = b - a
    squared = np.einsum("ij,ij->i", ab, ab)
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.where(squared > 0, squared, 1.0),
                0.0, 1.0)
    return float(np.linalg.norm(a + t[:, None] * ab - point, axis=1).min())


def half_reach(before: Line | Arc, after: Line | Arc) -> float:
    """How far from their corner two elements let a contour start: the nearer midpoint."""
    corner = before.end
    return min(float(np.linalg.norm(before.position(0.5 * before.length) - corner)),
               float(np.linalg.norm(after.position(0.5 * after.length) - corner)))


# -- the properties ------------------------------------------------------------------------------

EPS = 8 * np.finfo(float).eps  #: round-off of a difference of two setpoints, relative


def check_commands(run: Run, commands: list[Programmed]) -> None:
    """4: every command Done, the TCP on the last target, the axes at rest."""
    for index, command in enumerate(run.commands):
        assert command.done, (index, command.status.name, command.error_id, command.message)
    target = commands[-1].element.end
    assert np.abs(run.tcp[-1] - target).max() <= END_TOL, (run.tcp[-1], target)
    assert np.all(run.v[-1] == 0.0) and np.all(run.a[-1] == 0.0)


def limit_arrays(scene: Scene) -> tuple[np.ndarray, ...]:
    return tuple(np.array([getattr(x, name) for x in scene.limits])
                 for name in ("velocity", "acceleration", "deceleration", "jerk"))


def check_axis_limits(run: Run, scene: Scene) -> None:
    """2: every axis within its velocity, acceleration and jerk, and its setpoints one motion.

    A difference quotient of the velocity is the mean acceleration over a cycle, a second one
    a mean jerk: neither can exceed a limit the motion keeps. By the trapezoidal rule with its
    error bound, Δp = dt·(v0 + v1)/2 within j·dt³/12 (a position jump shows), and on a gantry,
    whose acceleration setpoint is exact, Δv = dt·(a0 + a1)/2 within j·dt²/4.
    """
    dt, (v_max, acc, dec, jerk) = run.dt, limit_arrays(scene)
    p, v, a = run.p, run.v, run.a
    # a position carries the round-off of the arc length s along the whole path and of the
    # MCS coordinates it is computed from (a gantry's offset makes them larger than the
    # axis' own), times |dq/ds| = |q'|/|x'|
    speed = np.linalg.norm(run.tcp_velocity, axis=1)
    moving = speed > 1e-6 * speed.max()
    gain = (np.abs(v[moving]) / speed[moving, None]).max(axis=0)
    length = np.linalg.norm(np.diff(run.tcp, axis=0), axis=1).sum()
    p_noise = EPS * (np.abs(p).max(axis=0) + gain * (length + np.abs(run.tcp).max()))
    v_noise = EPS * np.abs(v).max(axis=0)
    a_noise = EPS * np.abs(a).max(axis=0)
    assert np.all(np.abs(v) <= v_max * (1 + REL)), np.abs(v).max(axis=0) / v_max
    mean_a = np.abs(np.diff(v, axis=0)) / dt
    assert np.all(mean_a <= np.maximum(acc, dec) * (1 + REL) + v_noise / dt), \
        mean_a.max(axis=0) / np.maximum(acc, dec)
    mean_j = np.abs(np.diff(v, 2, axis=0)) / dt**2
    assert np.all(mean_j <= jerk * (1 + REL) + 2 * v_noise / dt**2), mean_j.max(axis=0) / jerk
    trapezoid = np.abs(np.diff(p, axis=0) - 0.5 * dt * (v[1:] + v[:-1]))
    worst = trapezoid.max(axis=0)
    assert np.all(trapezoid <= jerk * dt**3 / 12 * (1 + REL) + p_noise + dt * v_noise), \
        (worst, np.argmax(trapezoid, axis=0))
    if scene.cartesian:
        allowed = np.where(v * a > 0.0, acc, dec)  # speeding up, or slowing down
        assert np.all(np.abs(a) <= allowed * (1 + REL)), (np.abs(a) / allowed).max(axis=0)
        trapezoid = np.abs(np.diff(v, axis=0) - 0.5 * dt * (a[1:] + a[:-1]))
        assert np.all(trapezoid <= jerk * dt**2 / 4 * (1 + REL) + v_noise + dt * a_noise), \
            trapezoid.max(axis=0) / (jerk * dt**2 / 4)
        mean_j = np.abs(np.diff(a, axis=0)) / dt
        assert np.all(mean_j <= jerk * (1 + REL) + a_noise / dt), mean_j.max(axis=0) / jerk
    else:  # the published acceleration is the velocity's difference quotient, 0 at rest
        quotient = np.diff(v, axis=0) / dt
        resting = (v[1:] == 0.0) & (a[1:] == 0.0)
        wrong = ~resting & (np.abs(a[1:] - quotient) > EPS * np.abs(v).max(axis=0) / dt)
        assert not np.any(wrong), np.argwhere(wrong)[:5]


def tcp_acceleration_bound(run: Run, scene: Scene) -> float:
    """A bound of |d²x/dt²| of the TCP: on a gantry the axes' accelerations; else twice the
    largest mean over a cycle (the tolerance of check 3 only)."""
    if scene.cartesian:
        _, acc, dec, _ = limit_arrays(scene)
        return float(np.linalg.norm(np.maximum(acc, dec)))
    return 2.0 * float(np.linalg.norm(np.diff(run.tcp_velocity, axis=0), axis=1).max()) / run.dt


def check_continuity(run: Run, scene: Scene) -> None:
    """1: the TCP's position and, on a gantry, its direction of motion continuous."""
    dt = run.dt
    top = max(min(s.dynamics[0], 1000.0) for s in scene.steps)  # PathDynamics.max_velocity
    step = np.linalg.norm(np.diff(run.tcp, axis=0), axis=1)
    assert step.max() <= top * dt * (1 + REL) + 1e-12, step.max() / dt
    speed = np.linalg.norm(run.tcp_velocity, axis=1)
    assert speed.max() <= top * (1 + REL), speed.max()
    if not scene.cartesian:
        return  # the axes' velocities are continuous (check 2), so is J(q)·q'
    # at speed the velocity vector turns only as fast as the axes' accelerations allow:
    # |v1 - v0| >= 2·min(|v0|, |v1|)·sin(angle / 2), and |v1 - v0| <= A·dt
    v0, v1 = run.tcp_velocity[:-1], run.tcp_velocity[1:]
    cos = np.einsum("ij,ij->i", v0, v1) / np.maximum(speed[:-1] * speed[1:], 1e-300)
    turned = 2.0 * np.minimum(speed[:-1], speed[1:]) * np.sqrt(np.clip((1 - cos) / 2, 0, 1))
    allowed = tcp_acceleration_bound(run, scene) * dt * (1 + REL) + 1e-9
    worst = int(np.argmax(turned - allowed))
    assert np.all(turned <= allowed), (worst, turned[worst], allowed, speed[worst])


def check_corners(run: Run, scene: Scene, commands: list[Programmed]) -> None:
    """3: off the programmed elements only near a blended corner; corner deviation kept."""
    chord_error = tcp_acceleration_bound(run, scene) * run.dt**2 / 8.0
    away = off_path(run.tcp, commands)
    near_corner = np.zeros(len(run.tcp), dtype=bool)
    for before, after in zip(commands[:-1], commands[1:], strict=True):
        step = after.step
        if step.buffer_mode not in BLENDING or step.transition_mode is T.TM_NONE:
            continue
        corner = before.element.end
        reach = half_reach(before.element, after.element)
        if step.transition_mode is T.TM_CORNER_DISTANCE:
            reach = min(reach, step.parameter)
        distance = np.linalg.norm(run.tcp - corner, axis=1)
        near_corner |= distance <= reach * (1 + REL) + 1e-9
        if step.transition_mode is T.TM_MAX_CORNER_DEVIATION:
            nearest = to_polyline(corner, run.tcp)
            assert nearest <= step.parameter + chord_error + 1e-9, (nearest, step.parameter)
    stray = (away > ON_PATH) & ~near_corner
    assert not np.any(stray), (np.flatnonzero(stray)[:5], away[stray].max())


def check_all(scene: Scene) -> Run:
    run, commands = drive(scene)
    check_commands(run, commands)
    check_axis_limits(run, scene)
    check_continuity(run, scene)
    check_corners(run, scene, commands)
    return run


def step(size: float, turn: float = 0.0, velocity: float = 100.0, jerk: float = 1e5,
         buffer_mode: BufferMode = B.BUFFERED, transition: tuple[TransitionMode, Any] = (
             T.TM_NONE, None)) -> Step:
    """A line for the examples below."""
    return Step("line", turn, size, 0.0, CircMode.BORDER, False, (velocity, 1000.0, 1000.0, jerk),
                buffer_mode, *transition, 0)


SLOW = AxisLimits(100.0, 1000.0, 1000.0, 1e5)

#: moves.py: the contour's setpoints ran up to 5e-6 faster than the time law (its per-cycle
#: arc-length inversion, evaluate.py, was a cubic Hermite; now quintic)
COLLINEAR_BLEND = Scene(GANTRIES[1], (SLOW,) * 3, (0.0,) * 3, (
    step(1.0, velocity=10**1.375), step(1.0, velocity=10**1.375, jerk=1e4,
                                         buffer_mode=B.BLENDING_LOW,
                                         transition=(T.TM_CORNER_DISTANCE, 1.0))),
    (0.0, 0.0, 0.0), 0.001)
#: moves.py: in the first cycle from rest the published acceleration of a SCARA's axes was 0,
#: not the difference quotient of their velocities (which then read as 1.2x the jerk limit)
SCARA_FROM_REST = Scene(SCARAS[1], (SLOW, SLOW, SLOW, AxisLimits(100.0, 1000.0, 1000.0,
                                                                 10**4.5)),
                        (0.0, 50.0, 0.0, 0.0), (step(1.0, jerk=1e4), step(1.0)), (0.0,) * 3,
                        0.001)
#: kinematics.py, moves.py: the SCARA's base axis past 180° jumped a whole turn in one cycle
#: (each cycle took the principal angle of the inverse)
SCARA_PAST_180 = Scene(SCARAS[0], (AxisLimits(300.0, 3000.0, 3000.0, 1e5),) * 2, (165.0, 60.0),
                       (step(60.0), step(60.0), step(40.0)), (0.0, 0.0, -math.pi / 2), 0.001)

#: timing_kernels.py: a 20 mm line after a contour capped at 0.02 mm/s took that cap (the
#: bump rule flattened it as too short to ramp from 800 to 1000 mm/s) and crawled for 15 min
CRAWL = Scene(SCARAS[1], (
    AxisLimits(289.47390936053824, 1138.0102429624917, 1138.0102429624917, 1e6),
    AxisLimits(220.61030389752236, 3332.263578719018, 3332.263578719018, 157687.8743314322),
    AxisLimits(464.58567594521065, 1091.6485386672496, 1091.6485386672496, 441347.89272612054),
    AxisLimits(10**1.9, 28177.3647014462, 28177.3647014462, 439683.9471745703)),
    (-49.46237146211109, 85.58664542965617, -79.51585111134406, 33.131482208996815), (
    Step("arc", 0.0, 10.0, -4.200000833249662, CircMode.RADIUS, True,
         (20.121146965442154, 1120.2278646013333, 2225.937354595473, 79092.65789442779),
         B.BUFFERED, T.TM_CONSTANT_VELOCITY, 79.7953871339663, 0),
    Step("line", -3.1296507006406724, 20.854689615831454, 0.0, CircMode.BORDER, True,
         (1000.0, 1749.344987974538, 1094.5914767151003, 32876.863864942316),
         B.BLENDING_LOW, T.TM_MAX_CORNER_DEVIATION, 0.00250457159143835, 42),
    Step("line", 0.0, 1.0, 0.0, CircMode.BORDER, True,
         (198.73562826383107, 1628.3799482373627, 4086.5875672416523, 5405.236801958428),
         B.BLENDING_PREVIOUS, T.TM_CONSTANT_VELOCITY, 62.789838626426935, 0),
    Step("line", -0.04043488744992034, 29.999999999999982, 0.0, CircMode.BORDER, True,
         (131.71779705924308, 10000.0, 8690.037072995001, 289332.93785666255),
         B.BLENDING_HIGH, T.TM_START_VELOCITY, 86.80733753619899, 146)),
    (0.2115654506904209, -0.15915494309189535, 2.077640967678179), 0.001)

#: timing.py: commands appended while the TCP sped up on line 3; the re-planned leg from
#: a != 0 missed its junction (a = 100 mm/s² there), the legs after it missed theirs by far,
#: and the TCP passed a Buffered corner at 9.5 mm/s (with a contour instead: entered it at
#: 22 times its speed cap)
LATE_APPEND = Scene(SCARAS[1], (AxisLimits(60.0, 500.0, 500.0, 2e4),) * 2 + (
    AxisLimits(100.0, 500.0, 500.0, 2e4), AxisLimits(60.0, 500.0, 500.0, 2e4)),
    (0.0, 113.07058151229077, 0.0, 0.0), (
    step(1.0, velocity=20.0, jerk=198979.34391844203),
    Step("arc", 0.0, 10**0.8, 1.5479691537700544, CircMode.BORDER, False,
         (161.04812946697325, 500.0, 10000.0, 1e6), B.BUFFERED, T.TM_NONE, None, 0),
    Step("line", 0.0, 1.5222697030755565, 0.0, CircMode.BORDER, False,
         (124.12525531865553, 500.0, 500.0, 10000.0), B.BUFFERED, T.TM_NONE, None, 158),
    Step("line", 0.0, 1.0, 0.0, CircMode.BORDER, False, (20.0, 500.0, 500.0, 718757.5715971437),
         B.BLENDING_NEXT, T.TM_START_VELOCITY, 21.722788548118828, 0),
    Step("arc", 2.6526141247449924, 1.0, 4.812874207322297, CircMode.BORDER, False,
         (20.0, 500.0, 500.0, 10000.0), B.BLENDING_NEXT, T.TM_START_VELOCITY, 1.0, 286)),
    (0.0, 0.0, 0.0), 0.001)

#: the test: on the gantry shifted by 40 mm in y, the y axis at its jerk limit on the line
#: (a cubic, so the trapezoid rule's error is exactly j·dt³/12) missed the bound by 6e-15 mm:
#: the round-off of the MCS coordinate y = 40.1 mm, which the noise allowance left out
OFFSET_GANTRY = Scene(GANTRIES[3], (SLOW, AxisLimits(100.0, 1000.0, 1000.0, 10**4.5), SLOW),
                      (0.0,) * 3, (
    Step("arc", 0.0, 1.0, 0.5, CircMode.BORDER, False, (100.0, 1000.0, 1000.0, 1e4),
         B.BUFFERED, T.TM_NONE, None, 0),
    step(1.0)), (0.0, 0.0, 0.0), 0.001)

#: geometry/blend.py: a TMConstantVelocity contour from a line into a 0.63 mm arc turning
#: 2.1 rad bent on a radius of 0.15 µm (its handles came from the turn between the trimmed
#: tangents, 179.6°, not from the 0.31 mm between its ends); the delta robot's sampled caps
#: could not resolve it and refused the arc as KINEMATICS_SINGULAR (D-138)
NEAR_CUSP_DELTA = Scene(DELTA, (AxisLimits(60.0, 500.0, 500.0, 1e6),) + (
    AxisLimits(60.0, 500.0, 500.0, 2e4),) * 2, (29.746868292083605, 5.0, 5.0), (
    Step("line", 0.0, 1.821707851320244, 0.0, CircMode.BORDER, False,
         (20.0, 1000.0, 500.0, 5000.0), B.BUFFERED, T.TM_NONE, None, 0),
    Step("arc", -2.1283412444764425, 0.6285882143214888, -2.0390809508037564, CircMode.BORDER,
         False, (20.0, 500.0, 500.0, 5000.0), B.BLENDING_NEXT, T.TM_CONSTANT_VELOCITY, 1.0, 0),
    Step("line", 0.0, 1.0, 0.0, CircMode.BORDER, False, (20.0, 10000.0, 500.0, 5000.0),
         B.BUFFERED, T.TM_NONE, None, 0),
    Step("line", 0.0, 1.0, 0.0, CircMode.BORDER, False, (20.0, 500.0, 500.0, 5000.0),
         B.BUFFERED, T.TM_NONE, None, 0)),
    (0.0, 0.0, 0.0), 0.001)


@settings(max_examples=40, deadline=None)
@given(scene=gantry_scenes())
@example(scene=COLLINEAR_BLEND)
@example(scene=OFFSET_GANTRY)
def test_gantry_contours_issued_at_once(scene):
    check_all(scene)


@settings(max_examples=20, deadline=None)
@given(scene=gantry_scenes(late=True, max_steps=4))
def test_gantry_contours_issued_while_the_path_runs(scene):
    check_all(scene)


@settings(max_examples=15, deadline=None)
@given(scene=st.one_of(scara_scenes(late=True, max_steps=4), delta_scenes(max_steps=4)))
@example(scene=SCARA_FROM_REST)
@example(scene=SCARA_PAST_180)
@example(scene=CRAWL)
@example(scene=LATE_APPEND)
@example(scene=NEAR_CUSP_DELTA)
def test_scara_and_delta_contours(scene):
    check_all(scene)


def test_a_contour_into_a_nearly_reversing_arc_bends_on_a_sane_radius():
    """NEAR_CUSP_DELTA's corner (D-138): the path the contour replaces turned 180.4° (122° at
    the corner, 58° of arc); the contour bent on 0.15 µm over its 0.31 mm and the delta
    robot's caps refused it as a singular pose. Now the arc gives up at most 3/4 of what the
    corner leaves to a half turn, the contour bends on no less than an eighth of its length,
    and its caps let it run at the 1 % of 20 mm/s that TMConstantVelocity asks (§7.4.3)."""
    line, arc = (c.element for c in program(NEAR_CUSP_DELTA, DELTA.forward(
        np.array(NEAR_CUSP_DELTA.start)))[:2])
    blend = corner_distance_blend(line, arc, 1e12)  # TMConstantVelocity's widest contour
    contour = blend.contour
    assert blend.clamped and contour.max_curvature * contour.length <= 8.0
    assert 1.0 / contour.max_curvature >= 0.05  # [mm]: the arc's own radius is 0.63
    axes = [Limits(x.velocity, x.acceleration, x.deceleration, x.jerk)
            for x in NEAR_CUSP_DELTA.limits]
    caps = path_limits(contour, DELTA, axes, Limits(0.2, 500.0, 500.0, 5000.0))
    assert caps.velocity == 0.2


@pytest.mark.slow
@settings(max_examples=max(500, settings.default.max_examples), deadline=None)
@given(scene=st.one_of(gantry_scenes(late=True), scara_scenes(late=True), delta_scenes()))
def test_random_contours_many(scene):
    check_all(scene)


def test_a_direct_move_after_a_path_past_180_starts_on_the_turn_the_path_left():
    """The ACS move buffered after SCARA_PAST_180 starts where the path leaves the base axis,
    at 196.3°, not at the principal -163.7° (moves.py, ``_axes_at_end``)."""
    rt, group, axes = group_for(SCARA_PAST_180)
    tcp = group.position(CoordSystem.MCS)
    group.move_linear_absolute([tcp[0], tcp[1] - 160.0], velocity=200.0)
    direct = group.move_direct_absolute([200.0, 30.0], coord_system=CoordSystem.ACS,
                                        buffer_mode=B.BUFFERED)
    positions = [group.acs_set()]
    while not direct.finished:
        rt.step()
        positions.append(group.acs_set())
    assert direct.done
    steps_ = np.abs(np.diff(positions, axis=0)).max(axis=0)
    assert np.all(steps_ <= 300.0 * 0.001 * (1 + REL)), steps_
    assert np.array_equal(positions[-1], [200.0, 30.0])


# -- kinematics: inverse ∘ forward over the workspace, for random machines ------------------------
# test_kinematics.py checks one SCARA, one delta and one gantry; these draw the machine too.

RT = 1e-9  #: [mm] and [°]


@st.composite
def gantries(draw: Any) -> CartesianGantry:
    mapping = draw(st.permutations(COORDINATES).flatmap(
        lambda names: st.integers(1, 6).map(lambda n: tuple(names[:n]))))
    n = len(mapping)
    sign = draw(st.lists(st.sampled_from([1.0, -1.0]), min_size=n, max_size=n))
    offset = draw(st.lists(st.floats(-1e3, 1e3), min_size=n, max_size=n))
    return CartesianGantry(mapping, sign=sign, offset=offset)


@given(gantry=gantries(), data=st.data())
def test_any_gantry_round_trips(gantry, data):
    q = np.array(data.draw(st.lists(st.floats(-1e4, 1e4), min_size=gantry.n_axes,
                                    max_size=gantry.n_axes)))
    assert np.abs(gantry.inverse(gantry.forward(q)) - q).max() <= RT
    x = np.array(data.draw(st.lists(st.floats(-1e4, 1e4), min_size=gantry.n_axes,
                                    max_size=gantry.n_axes)))
    assert np.abs(gantry.forward(gantry.inverse(x)) - x).max() <= RT


@st.composite
def scaras(draw: Any) -> Scara:
    l1 = draw(decades(50.0, 1000.0))
    l2 = l1 * draw(decades(0.2, 5.0))
    window = None
    if draw(st.booleans()):  # the base axis within a window less than a turn wide
        low = draw(st.floats(-360.0, 0.0))
        window = [(low, low + draw(st.floats(200.0, 359.0))), None]
    z_axis, c_axis = draw(st.booleans()), draw(st.booleans())
    if window is not None:
        window += [None] * (z_axis + c_axis)
    return Scara(l1, l2, z_axis=z_axis, c_axis=c_axis, limits=window)


def scara_axes(draw: Any, scara: Scara, configuration: Configuration) -> np.ndarray:
    """ACS positions of one configuration, 1° clear of the stretched and folded poses, the base
    axis inside its limits."""
    low, high = scara.limits[0]
    base = draw(st.floats(max(low, -180.0), min(high, 180.0))) if math.isfinite(low) \
        else draw(st.floats(-180.0, 180.0, exclude_min=True))
    elbow = draw(st.floats(1.0, 179.0))
    q = [base, elbow if configuration is Configuration.ELBOW_DOWN else -elbow]
    if scara.z_axis:
        q.append(draw(st.floats(-500.0, 500.0)))
    if scara.c_axis:
        q.append(draw(st.floats(-400.0, 400.0)))
    return np.array(q)


@pytest.mark.parametrize("configuration", list(Configuration), ids=lambda c: c.name)
@given(scara=scaras(), data=st.data())
def test_any_scara_round_trips(configuration, scara, data):
    q = scara_axes(data.draw, scara, configuration)
    assume(np.all((q >= scara.limits[:, 0]) & (q <= scara.limits[:, 1])))
    x = scara.forward(q)
    assert np.abs(scara.inverse(x, configuration, near=q) - q).max() <= RT
    # without ``near`` the base axis is the principal angle (or the turn inside its limits):
    # the same up to whole turns, which the tool axis takes back
    error = scara.inverse(x, configuration) - q
    turns = 360.0 * np.round(error[0] / 360.0)
    error[0] -= turns
    if scara.c_axis:
        error[-1] += turns
    assert np.abs(error).max() <= RT
    # anywhere in the ring, its borders included
    inner, outer = abs(scara.l1 - scara.l2), scara.l1 + scara.l2
    r = data.draw(st.floats(inner, outer))
    angle = data.draw(st.floats(-math.pi, math.pi))
    x = np.array([r * math.cos(angle), r * math.sin(angle), *x[2:]])
    try:
        back = scara.forward(scara.inverse(x, configuration))
    except CommandRejected as rejected:  # the base axis' window leaves out this angle
        assert math.isfinite(scara.limits[0, 0]) and "outside its limits" in rejected.message
        return
    assert np.abs(back - x).max() <= RT


@given(scara=scaras(), data=st.data(), turns=st.integers(-3, 3))
def test_scara_inverse_near_keeps_the_turn_of_the_base_axis(scara, data, turns):
    """``near`` (a path's last setpoints) picks the base angle whole turns away from the
    principal one, the tool axis turning back as many: the TCP is the same."""
    q = scara_axes(data.draw, scara, Configuration.ELBOW_DOWN)
    wound = q.copy()
    wound[0] += 360.0 * turns
    if scara.c_axis:
        wound[-1] -= 360.0 * turns
    free = Scara(scara.l1, scara.l2, z_axis=scara.z_axis, c_axis=scara.c_axis)
    assert np.abs(free.forward(wound) - free.forward(q)).max() <= RT
    near = wound + data.draw(st.floats(-170.0, 170.0)) * np.eye(free.n_axes)[0]
    assert np.abs(free.inverse(free.forward(q), near=near) - wound).max() <= RT


@st.composite
def deltas(draw: Any) -> DeltaRobot:
    base = draw(st.floats(100.0, 300.0))
    upper = draw(st.floats(150.0, 400.0))
    return DeltaRobot(base, draw(st.floats(20.0, 0.5 * base)), upper,
                      upper * draw(st.floats(2.0, 3.5)))


def knees_out(delta: DeltaRobot, q: np.ndarray) -> bool:
    """Every elbow 1 mm or more outside the line from its shoulder to its wrist."""
    u = np.array([[math.cos(a), math.sin(a), 0.0] for a in np.radians([0.0, 120.0, 240.0])])
    wrist = delta.forward(q) + (delta.effector_radius - delta.base_radius) * u
    t = np.radians(q)
    side = -(wrist @ u.T).diagonal() * np.sin(t) - wrist[:, 2] * np.cos(t)
    return bool(np.all(side > 1.0))


@given(delta=deltas(), q=st.tuples(*[st.floats(-30.0, 70.0)] * 3).map(np.array))
def test_any_delta_round_trips(delta, q):
    try:
        x = delta.forward(q)
    except CommandRejected:  # the elbows too far apart to assemble
        assume(False)
    assume(knees_out(delta, q))
    assert np.abs(delta.inverse(x) - q).max() <= RT
    assert np.abs(delta.forward(delta.inverse(x)) - x).max() <= RT


def test_a_target_on_an_axis_limit_is_reachable():
    """kinematics.py: a pose with the base axis on its limit came back a rounding beyond it
    (about -4e-13° for the limit 0°) and was refused as out of the limits."""
    scara = Scara(50.0, 25.0, limits=[(0.0, 200.0), None])
    q = np.array([0.0, 1.0])
    assert np.abs(scara.inverse(scara.forward(q)) - q).max() <= RT
    # and on the turn's edge: the principal angle came back as 180° - 3e-14, whose turn down
    # lies a rounding below the limit -180°
    scara = Scara(50.0, 250.0, limits=[(-180.0, 20.0), None])
    q = np.array([-180.0, -30.0])
    assert np.abs(scara.inverse(scara.forward(q), Configuration.ELBOW_UP) - q).max() <= RT
