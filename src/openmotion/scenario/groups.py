"""The CA groups of one run: built after the axes, fed by the timeline, their gaps watched.

The run builds each group of ``ca_groups`` after the axes, gives it its parts, tracks,
geometry and templates (scenario/tracks.py), adds the axes in the listed order (IdentInGroup
1..n) and, with ``enable``, powers them (a CA mover needs MC_Power) and enables the group
before the first cycle. CA entries call the group's methods. As an
observer, ``watch`` takes every group's gaps once per cycle (one ``gaps()`` call per group)
and keeps each mover's smallest gap, so the summary's minimum covers every cycle, recorded or
not.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from openmotion.axis.axis import Axis
from openmotion.axis.commands import Command, CommandStatus
from openmotion.core.errors import ConfigError
from openmotion.rail.stations import StationLine, StationRow
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.programs import cycle_of
from openmotion.scenario.queries import Called
from openmotion.scenario.stations import build_line
from openmotion.scenario.tracks import configure
from openmotion.scenario.transport import (
    CaEntry,
    CaGroupSpec,
    GearInPosCa,
    GroupEntry,
    GroupStop,
    SetGap,
)
from openmotion.transport.enums import GroupState
from openmotion.transport.group import UDINT_TO_IDENTINGROUP, CaGroup

#: a mover stands when |set velocity| <= STANDING * max_velocity and |set acceleration| <=
#: STANDING * max_acceleration: float residue of the group's tracking steps does not count
STANDING = 1e-9


@dataclass(frozen=True)
class MoverRow:
    """One mover at the end of a run."""

    group: str
    mover: str  #: the axis name
    order: int  #: position in the CA order, 1 = the first mover (the leader)
    position: float  #: final set position [mm]
    gap: float | None  #: setpoint gap to the predecessor at the end [mm]; None: no predecessor
    minimum_gap: float | None  #: smallest gap in any cycle [mm]; None: never a predecessor
    minimum_at: float | None  #: [s] when the smallest gap was first seen


@dataclass(frozen=True)
class GroupRow:
    """One CA group at the end of a run: its state and its smallest gap."""

    name: str
    state: str  #: GroupState name in lower case
    minimum_gap: float | None  #: [mm]; None when no mover ever had a predecessor
    mover: str  #: whose gap it was ("" with None)
    minimum_at: float | None  #: [s]


class CaGroups:
    """The run's CA groups: building, issuing CA entries, releases, gaps and rest."""

    def __init__(self, rt: Runtime, specs: list[CaGroupSpec]) -> None:
        self.rt = rt
        self.groups: dict[str, CaGroup] = {}
        self.group_of: dict[str, CaGroup] = {}  #: axis name -> its group
        self.lines: list[StationLine] = []  #: the groups' station lines
        for spec in specs:
            group = CaGroup(rt, spec.name, spec.parameters.build())
            problems = list(configure(spec, group))  # parts, tracks, geometry, templates
            if problems:  # the scenario's validation tried the same on a scratch group
                raise ConfigError(f"ca_groups {spec.name}: " + "; ".join(
                    f"{'.'.join(map(str, loc))}: {message}" for loc, message in problems))
            for number, name in enumerate(spec.axes, start=1):
                axis = rt.axes[name]
                if spec.enable:
                    axis.power()
                group.add_axis(axis, UDINT_TO_IDENTINGROUP(number))
                self.group_of[name] = group
            if spec.enable:
                group.enable()
            self.groups[spec.name] = group
            line = build_line(rt, group, spec.stations, spec.routes, list(spec.axes))
            if line is not None:
                self.lines.append(line)
        rows = 1 + max((axis.row for axis in rt.axes.values()), default=0)
        self.minimum = np.full(rows, np.inf)  #: smallest gap of each axis row [mm]
        self.minimum_at = np.full(rows, np.nan)
        self.releases: list[tuple[int, Command]] = []  #: (cycle, group_stop) still held
        self.commands: dict[Command, CaGroup] = {}  #: mover commands -> their group

    # -- the timeline ------------------------------------------------------------------------

    def issue(self, entry: CaEntry | GroupEntry | SetGap, by_id: Mapping[str, Command]) \
            -> Command:
        """Carry out a CA entry now."""
        rt = self.rt
        if isinstance(entry, SetGap):
            return self._set_gap(entry, by_id.get(entry.move))
        if isinstance(entry, Called):  # a block called once (transport.py)
            target = (self.groups[entry.group], rt) if isinstance(entry, GroupEntry) \
                else rt.axes[entry.axis]
            return entry.call(target, rt.now)
        if isinstance(entry, GroupEntry):
            group = self.groups[entry.group]
            command = getattr(group, entry.method)(**entry.arguments())
            if isinstance(entry, GroupStop) and command.busy:
                cycle = cycle_of(entry.release_at, rt.cycle_time) if entry.release_at \
                    is not None else rt.cycle + max(1, cycle_of(entry.hold, rt.cycle_time))
                self.releases.append((cycle, command))
            return command
        member_of = rt.axes[entry.axis].group  # add_axis_to_group may have moved it
        group = member_of if isinstance(member_of, CaGroup) else self.group_of[entry.axis]
        if isinstance(entry, GearInPosCa):  # master first, as MC_GearInPosCA's in/outs
            command = group.gear_in_pos(rt.axes[entry.master], rt.axes[entry.axis],
                                        **entry.arguments())
        else:
            owner = group
            for name in filter(None, entry.owner.split(".")):  # group.tracks, .tracks.geo
                owner = getattr(owner, name)
            command = getattr(owner, entry.method)(rt.axes[entry.axis], **entry.arguments())
        self.commands[command] = group
        return command

    def _set_gap(self, entry: SetGap, move: Command | None) -> Command:
        command = Command(entry.command, self.rt.now)
        if move is None or not move.busy or move not in self.commands:
            command.message = f"ignored: {entry.move} is not running"
        else:
            group = self.commands[move]
            mover = next((m for m in group.movers if m.job is not None
                          and m.job.command is move), None)
            if mover is not None and not mover.job.continuous_update:  # type: ignore[union-attr]
                command.message = f"ignored: {entry.move} has continuous_update false"
            group.set_gap(move, entry.gap)
        command.end(CommandStatus.DONE, self.rt.now, message=command.message)
        return command

    def release_due(self) -> None:
        """Let Execute of every group_stop whose hold is over fall (program phase)."""
        cycle = self.rt.cycle
        for due in [due for due in self.releases if due[0] <= cycle]:
            due[1].release()
            self.releases.remove(due)

    # -- rest --------------------------------------------------------------------------------

    @property
    def busy(self) -> bool:
        """A group_stop still holds its group (Execute TRUE), or a station line has movers on
        their routes: the run goes on."""
        return bool(self.releases) or any(line.busy for line in self.lines)

    def standing(self, group: CaGroup) -> bool:
        """Every mover of ``group`` stands: set velocity and acceleration 0 (see STANDING)."""
        return all(_stands(mover.axis) for mover in group.movers)

    def waiting(self, command: Command) -> bool:
        """A busy CA command whose group stands still: a mover queued behind another, which
        may stay Busy for ever (Done only at the target, TF5410 §9.1.1.1.1)."""
        group = self.commands.get(command)
        return group is not None and command.busy and self.standing(group)

    # -- gaps ------------------------------------------------------------------------------

    def watch(self) -> None:
        """Keep each mover's smallest gap (observer phase, every cycle)."""
        now = self.rt.now
        for group in self.groups.values():
            if group.state is GroupState.DISABLED or not group.movers:
                continue
            gaps, rows = group.gaps(), group.rows
            lower = gaps < self.minimum[rows]
            if lower.any():
                self.minimum[rows[lower]] = gaps[lower]
                self.minimum_at[rows[lower]] = now

    def mover_rows(self) -> list[MoverRow]:
        rows = []
        for name, group in self.groups.items():
            gaps = group.gaps()
            for order, mover in enumerate(group.movers, start=1):
                row = mover.axis.row
                rows.append(MoverRow(name, mover.axis.name, order, mover.axis.set_position,
                                     _finite(gaps[order - 1]), _finite(self.minimum[row]),
                                     _finite(self.minimum_at[row])))
        return rows

    def station_rows(self) -> list[tuple[str, StationRow]]:
        """(line name, station row) of every station line."""
        return [(line.name, row) for line in self.lines for row in line.station_rows()]

    def group_rows(self) -> list[GroupRow]:
        rows = []
        movers = self.mover_rows()
        for name, group in self.groups.items():
            seen = [row for row in movers if row.group == name and row.minimum_gap is not None]
            low = min(seen, key=lambda row: row.minimum_gap, default=None)  # type: ignore
            rows.append(GroupRow(name, group.state.name.lower(),
                                 None if low is None else low.minimum_gap,
                                 "" if low is None else low.mover,
                                 None if low is None else low.minimum_at))
        return rows


def _stands(axis: Axis) -> bool:
    parameters = axis.parameters
    return abs(axis.set_velocity) <= STANDING * parameters.max_velocity and \
        abs(axis.set_acceleration) <= STANDING * parameters.max_acceleration


def _finite(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None
