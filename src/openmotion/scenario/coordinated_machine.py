"""The axes groups of one run: built after the CA groups, fed by the timeline, read by checks.

The run builds each group of ``axes_groups``, adds its axes in the listed order (IdentInGroup
1..n), gives it its kinematics and first Cartesian transform and, with ``enable``, powers the
members and enables it before the first cycle. Entries call the ``AxesGroup`` methods; a
``move_path`` entry calls ``select_path`` first (MC_PathSelect) and hands its PathData to
``move_path``; a ``move_path_table`` entry fills a path table with the TF5410 preparation
blocks and runs it with MC_MovePath. A ``group_stop`` keeps the group Stopping until its
``hold`` is over, as for CA groups.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from openmotion.axis.commands import Command, CommandStatus
from openmotion.coordinated.group import AxesGroup
from openmotion.coordinated.kind import AXES_GROUP
from openmotion.coordinated.path_table import (
    MC_PATH_DATA_REF,
    MC_BlockerPreparation,
    MC_DwellTimePreparation,
    MC_MoveCircularAbsolutePreparation,
    MC_MoveLinearAbsolutePreparation,
    MC_SetCoordinateTransformPreparation,
)
from openmotion.coordinated.paths import select_path
from openmotion.coordinated.states import AxesGroupState
from openmotion.core.errors import CommandRejected, ConfigError
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.coordinated import (
    BACKGROUND,
    AxesGroupEntry,
    AxesGroupSpec,
    MovePath,
    MovePathTable,
    SyncGroupToAxis,
    frame_of,
)
from openmotion.scenario.programs import cycle_of
from openmotion.scenario.queries import Called
from openmotion.scenario.transport import GroupEntry, GroupStop

if TYPE_CHECKING:
    from rich.table import Table


@dataclass(frozen=True)
class AxesGroupRow:
    """One axes group at the end of a run."""

    group: str
    state: str  #: AxesGroupState name in lower case
    x: float  #: the TCP's set position in the MCS [mm]
    y: float
    z: float
    axes: tuple[tuple[str, float], ...]  #: (member, set position [mm or °]) in ident order


class AxesGroups:
    """The run's axes groups: building, issuing their entries, releases, signals, rows."""

    def __init__(self, rt: Runtime, specs: list[AxesGroupSpec]) -> None:
        self.rt = rt
        self.groups: dict[str, AxesGroup] = {}
        for spec in specs:
            self.groups[spec.name] = self._build(spec)
        self.releases: list[tuple[int, Command]] = []  #: (cycle, group_stop) still held
        self.background: set[Command] = set()  #: tracking and syncing commands

    def _build(self, spec: AxesGroupSpec) -> AxesGroup:
        rt = self.rt
        group = AxesGroup(rt, spec.name, spec.dynamics.build())
        for number, name in enumerate(spec.axes, start=1):
            _set_up(spec, group.add_axis(rt.axes[name], number))
        if spec.kinematics is not None:
            _set_up(spec, group.set_kinematics(spec.kinematics.build()))
        if spec.cartesian_transform is not None:
            _set_up(spec, group.set_cartesian_transform(frame_of(spec.cartesian_transform)))
        if spec.enable:
            for name in spec.axes:
                rt.axes[name].power()
            _set_up(spec, group.enable())
        return group

    def owns(self, entry: object) -> bool:
        """An entry for one of these groups (its own kind, or a shared group command)."""
        return isinstance(entry, AxesGroupEntry) or \
            isinstance(entry, GroupEntry) and entry.group in self.groups

    # -- the timeline ------------------------------------------------------------------------

    def issue(self, entry: AxesGroupEntry | GroupEntry) -> Command:
        """Carry out an entry on an axes group now."""
        rt, group = self.rt, self.groups[entry.group]
        arguments = entry.arguments()
        if isinstance(entry, GroupStop):
            command = group.stop(**arguments)
            if command.busy:
                cycle = cycle_of(entry.release_at, rt.cycle_time) if entry.release_at \
                    is not None else rt.cycle + max(1, cycle_of(entry.hold, rt.cycle_time))
                self.releases.append((cycle, command))
            return command
        if isinstance(entry, Called):  # a block called once (queries.py)
            return entry.call((group, rt), rt.now)
        if isinstance(entry, GroupEntry):
            return getattr(group, entry.method)(**arguments)
        for name in entry.axis_fields:
            arguments[name] = rt.axes[arguments[name]]
        for name in entry.group_fields:
            arguments[name] = self.groups[arguments[name]]
        if isinstance(entry, MovePathTable):
            return _move_path_table(group, entry)
        if isinstance(entry, MovePath | SyncGroupToAxis):
            select = entry.select
            try:
                arguments["path"] = select_path(group, entry.description(), select.coord_system,
                                                select.transition_mode,
                                                select.transition_parameter)
            except CommandRejected as rejected:
                command = Command("MC_PathSelect", rt.now)
                command.end(CommandStatus.ERROR, rt.now, rejected.error_id, rejected.message)
                return command
        command = getattr(group, entry.method)(**arguments)
        if isinstance(entry, BACKGROUND):
            self.background.add(command)
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
        """A group_stop still holds its group, or a group homes: the run goes on."""
        return bool(self.releases) or any(
            group.state is AxesGroupState.HOMING for group in self.groups.values())

    def waiting(self, command: Command) -> bool:
        """A tracking or syncing command, Busy while it works in the background: it does
        not keep the run going (the group's and the axes' motion do)."""
        return command in self.background

    def rows(self) -> list[AxesGroupRow]:
        return [AxesGroupRow(name, group.state.name.lower(),
                             *(AXES_GROUP.signal(prop).read(group) for prop in "xyz"),
                             tuple((axis.name, axis.set_position) for axis in group.axes))
                for name, group in self.groups.items()]


#: the TF5410 §9.3 block that appends each kind of path-table row
_PREPARATIONS: dict[str, type] = {
    "linear": MC_MoveLinearAbsolutePreparation, "circular": MC_MoveCircularAbsolutePreparation,
    "blocker": MC_BlockerPreparation, "dwell": MC_DwellTimePreparation,
    "coord_transform": MC_SetCoordinateTransformPreparation}


def _move_path_table(group: AxesGroup, entry: MovePathTable) -> Command:
    """The preparation blocks fill a fresh table, MC_MovePath runs it (TF5410 §9.3)."""
    table = MC_PATH_DATA_REF()
    for number, row in enumerate(entry.rows, start=1):
        block = _PREPARATIONS[row.kind]()
        block(table, **row.inputs())
        if block.error:
            command = Command(type(block).__name__, group.runtime.now)
            command.end(CommandStatus.ERROR, group.runtime.now, block.error_id,
                         f"row {number}: {block.message}")
            return command
    return group.move_path_table(table)


def _set_up(spec: AxesGroupSpec, command: Command) -> None:
    """A setup step the scenario's validation should have made sure of."""
    if command.error:
        raise ConfigError(f"axes_groups {spec.name}: {command.kind}: {command.error_id.name}: "
                          f"{command.message}")


def axes_group_table(rows: list[AxesGroupRow], number: Callable[[float], str]) -> Table:
    """The summary's ``Axes groups`` table: state, TCP and member set positions at the end."""
    from rich import box
    from rich.table import Table
    from rich.text import Text

    table = Table(box=box.SIMPLE, title_justify="left", title="Axes groups")
    for name in ("group", "state", "x [mm]", "y [mm]", "z [mm]", "axes (set position)"):
        table.add_column(Text(name), justify="left" if name in ("group", "state",
                                                                "axes (set position)")
                         else "right", no_wrap=name != "axes (set position)", overflow="fold")
    for row in rows:
        table.add_row(row.group, row.state, *(number(value) for value in (row.x, row.y, row.z)),
                      ", ".join(f"{axis} {number(value)}" for axis, value in row.axes))
    return table
