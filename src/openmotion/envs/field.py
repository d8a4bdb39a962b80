"""The simulated planar field both environments step: one runtime, one group, N movers.

``PlanarField`` builds a field from a ``Layout`` (the environment, its stators and boundary in
one enabled ``MC_PlanarGroup`` with every mover), gives each mover a goal, and turns one
action row per mover into a TF5430 ``MoveToPosition`` to its set position plus an increment
(D-311). The group decides every command as it would on a controller: a move whose swept area
meets another mover's reservation or leaves the stators is refused with PLANAR_COLLISION,
and the field counts that refusal for the mover. Then it runs ``cycles_per_step`` runtime
cycles and reads every mover's published set position and velocity.

Only the planar package's public API is used (commands, ``position``, ``velocity``, state),
so what a policy learns here is what a PLC program could do.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarGroup,
    MC_PlanarMover,
    MoverVector,
    PlanarCommand,
    PlanarMoverParameters,
    PlanarState,
    PositionXYC,
)
from openmotion.planar.layouts import Layout
from openmotion.planar.stators import STATOR_SIZE
from openmotion.runtime.runtime import Runtime

CYCLE_TIME = 0.001  #: runtime cycle [s], the TF5430 default task cycle
CYCLES_PER_STEP = 10  #: runtime cycles per environment step (10 ms)
REACH = STATOR_SIZE  #: an action of 1 moves the target this far from the set position [mm]
ACTION_DEADBAND = 1e-3  #: a mover whose action is shorter than this gets no new command
ARRIVAL_TOLERANCE = 5.0  #: a mover has arrived when its centre is this close to its goal [mm]
SETUP_CYCLES = 3  #: cycles to enable the movers and join the group


@dataclass(frozen=True)
class StepResult:
    """What one ``PlanarField.step`` did, per mover."""

    commanded: np.ndarray  #: bool: a MoveToPosition was sent
    rejected: np.ndarray  #: bool: the group (or the mover) refused it
    error_ids: np.ndarray  #: int: the refusal's error id, 0 when none


class PlanarField:
    """A planar field of ``layout`` with movers standing on ``starts`` and heading to
    ``goals`` (both [mm], shape (movers, 2))."""

    def __init__(self, layout: Layout, starts: np.ndarray, goals: np.ndarray,
                 cycles_per_step: int = CYCLES_PER_STEP, reach: float = REACH) -> None:
        if starts.shape != goals.shape or starts.ndim != 2 or starts.shape[1] != 2:
            raise ConfigError(f"planar field: starts and goals must both have shape (movers, 2), "
                              f"got {starts.shape} and {goals.shape}")
        if isinstance(cycles_per_step, bool) or not isinstance(cycles_per_step, int) \
                or cycles_per_step < 1:
            raise ConfigError(f"planar field: cycles_per_step must be an int >= 1, got "
                              f"{cycles_per_step!r}")
        if not reach > 0.0:
            raise ConfigError(f"planar field: reach must be > 0 mm, got {reach!r}")
        self.layout = layout
        self.cycles_per_step = cycles_per_step
        self.reach = float(reach)
        self.goals = np.array(goals, dtype=float)
        self.runtime = Runtime(CYCLE_TIME)
        self.environment = MC_PlanarEnvironment(self.runtime)
        for lower_x, lower_y in layout.stators():
            self.environment.add_stator(lower_x, lower_y)
        self.environment.create_boundary()
        self.group = MC_PlanarGroup(self.runtime)
        self.group.enable()
        size = layout.mover_size
        self.movers = [MC_PlanarMover(self.runtime, PlanarMoverParameters(
            initial_position=MoverVector(float(x), float(y)), mover_width=size,
            mover_height=size), name=f"m{i}") for i, (x, y) in enumerate(starts)]
        self._setup()

    def _setup(self) -> None:
        for mover in self.movers:
            mover.enable()
        self.runtime.run(2 * CYCLE_TIME)
        joins = [mover.add_to_group(self.group) for mover in self.movers]
        joins.append(self.environment.add_to_group(self.group))
        self.runtime.run((SETUP_CYCLES - 1) * CYCLE_TIME)
        failed = [command for command in joins if not command.done]
        if failed or any(mover.state is not PlanarState.ENABLED for mover in self.movers):
            raise ConfigError(f"planar field {self.layout.name}: set-up failed: "
                              f"{failed[0].error_id if failed else 'a mover is not Enabled'}")

    @property
    def count(self) -> int:
        return len(self.movers)

    def positions(self) -> np.ndarray:
        """Set positions x, y [mm], shape (movers, 2)."""
        return np.array([mover.pose[:2] for mover in self.movers], dtype=float)

    def velocities(self) -> np.ndarray:
        """Set velocities x, y [mm/s], shape (movers, 2)."""
        return np.array([(v.x, v.y) for v in (mover.velocity for mover in self.movers)],
                        dtype=float)

    def distances(self, positions: np.ndarray) -> np.ndarray:
        """Each mover's distance to its goal [mm]."""
        return np.hypot(*(self.goals - positions).T)

    def failed(self) -> np.ndarray:
        """Movers no longer Enabled (an error took them out): they cannot move any more."""
        return np.array([mover.state is not PlanarState.ENABLED for mover in self.movers])

    def step(self, actions: np.ndarray) -> StepResult:
        """Send one move per mover whose action (shape (movers, 2), each in [-1, 1]) is not
        zero: to its set position plus ``reach`` times the action; then run the cycles."""
        actions = np.clip(np.asarray(actions, dtype=float), -1.0, 1.0)
        positions = self.positions()
        targets = positions + self.reach * actions
        commanded = np.hypot(*actions.T) > ACTION_DEADBAND
        commands: list[PlanarCommand | None] = [None] * self.count
        for i in np.flatnonzero(commanded):
            x, y = targets[i]
            commands[i] = self.movers[i].move_to_position(PositionXYC(float(x), float(y)))
        self.runtime.run(self.cycles_per_step * CYCLE_TIME)
        error_ids = np.array([0 if c is None or not c.error else int(c.error_id)
                              for c in commands], dtype=np.int64)
        return StepResult(commanded, error_ids != 0, error_ids)
