"""The path figure of axes groups (PLCopen Part 4): the TCP in the XY plane and the axis
profiles beside it.

Per group one row. Left: the TCP's set position in the MCS seen from above, coloured by the
motion command that was active (a command is active from the later of its issue and the end
of the command before it, to its own end), grey where none was. A dot marks where one command
handed over to the next: with blending the next one's contour starts there, so each corner
shows its contour, and a Buffered corner is a sharp one. The path starts at a ring and ends at
a square; a command refused when it was issued is a red cross at the TCP, labelled with its
id. Right: position, velocity and acceleration of every member axis over time (setpoints),
with the path velocity dashed, and each command's time span shaded in its colour.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.trace.plot import (
    axes_groups,
    distinct_colors,
    event_text,
    mark_refusals,
    new_figure,
    value_at,
)
from openmotion.trace.record import Trace

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import SubFigure

#: the commands that move a group along its path (``Command.kind``): they colour the path
MOTION_COMMANDS = frozenset({
    "MC_MoveLinearAbsolute", "MC_MoveLinearRelative", "MC_MoveCircularAbsolute",
    "MC_MoveCircularRelative", "MC_MoveDirectAbsolute", "MC_MoveDirectRelative",
    "MC_MovePath", "group_halt", "group_stop", "group_interrupt"})
IDLE_COLOR = "0.65"  #: the path where no motion command was active
MAX_LEGEND = 16  #: commands named in a group's legend at most
#: (panel title with its unit, the member signal, the group signal drawn dashed in it)
PROFILES = (("position [mm, °]", "set_position", None),
            ("velocity [mm/s, °/s]", "set_velocity", "path_velocity"),
            ("acceleration [mm/s², °/s²]", "set_acceleration", "path_acceleration"))


@dataclass(frozen=True)
class Span:
    """When one motion command was active: ``start < t <= end``."""

    label: str  #: the entry's id (the command's kind without one)
    start: float  #: [s]
    end: float  #: [s]
    result: str  #: how it ended: DONE, ABORTED, ERROR, or BUSY at the end of the trace


def command_spans(trace: Trace, group: str) -> list[Span]:
    """The active spans of ``group``'s motion commands, in time order.

    Ends are taken in time order; a command is active from the later of its issue and the
    previous end. A command that ended where it was issued (refused) has no span.
    """
    issued: dict[tuple[str, str], list[float]] = defaultdict(list)
    ends: list[tuple[float, float, str, str]] = []
    for event in trace.events:
        if event.object != group or event.command not in MOTION_COMMANDS:
            continue
        key = (event.command, event.label)
        if event.result == "ISSUED":
            issued[key].append(event.time)
        elif issued[key]:
            ends.append((event.time, issued[key].pop(0), event_text(event), event.result))
    last = float(trace.time[-1]) if len(trace) else 0.0
    ends += [(last, start, label or command, "BUSY")
             for (command, label), starts in issued.items() for start in starts]
    spans, previous = [], -np.inf
    for end, start, label, result in sorted(ends, key=lambda item: item[0]):
        start = max(start, previous)
        if end > start:
            spans.append(Span(label, start, end, result))
            previous = end
    return spans


def path_figure(trace: Trace, title: str | None = None) -> Any:
    """The XY path and the axis profiles of every axes group the trace holds."""
    groups = axes_groups(trace)
    figure = new_figure(12.0, 5.2 * max(len(groups), 1) + 0.4, title)
    if not groups:
        figure.add_subplot().text(0.5, 0.5, "no axes group TCP recorded", ha="center",
                                  va="center")
        return figure
    rows = figure.subfigures(len(groups), 1, squeeze=False)[:, 0]
    for row, (name, group) in zip(rows, groups.items(), strict=True):
        _draw_group(row, trace, name, group)
    return figure


def _draw_group(row: SubFigure, trace: Trace, name: str, group: dict[str, Any]) -> None:
    grid = row.add_gridspec(len(PROFILES), 2, width_ratios=(1.0, 1.15))
    plane = row.add_subplot(grid[:, 0])
    panels = [row.add_subplot(grid[index, 1]) for index in range(len(PROFILES))]
    for panel in panels[1:]:
        panel.sharex(panels[0])
    spans = command_spans(trace, name)
    labels = list(dict.fromkeys(span.label for span in spans))
    colors = dict(zip(labels, distinct_colors(len(labels)), strict=True))
    _draw_plane(plane, trace, name, spans, colors)
    _draw_profiles(panels, trace, name, group, spans, colors)
    axes = ", ".join(group.get("axes", []))
    coordinates = ", ".join(group.get("coordinates", []))
    row.suptitle(f"{name}: axes {axes}; MCS {coordinates}", fontsize="medium")


def _draw_plane(plane: Axes, trace: Trace, name: str, spans: list[Span],
                colors: dict[str, str]) -> None:
    time, x, y = trace.time, trace[f"{name}.x"], trace[f"{name}.y"]
    plane.plot(x, y, "-", color=IDLE_COLOR, linewidth=1.0, zorder=1, gid=f"{name}:tcp")
    named: set[str] = set()
    for span in spans:
        inside = np.flatnonzero((time > span.start) & (time <= span.end))
        if not inside.size:
            continue
        pieces = np.arange(max(inside[0] - 1, 0), inside[-1] + 1)  # joined to the sample before
        label = span.label if span.label not in named and len(colors) <= MAX_LEGEND else None
        named.add(span.label)
        plane.plot(x[pieces], y[pieces], "-", color=colors[span.label], linewidth=1.8, zorder=2,
                   label=label, gid=f"{name}:{span.label}")
        if span.start > time[0]:
            plane.plot([x[pieces[0]]], [y[pieces[0]]], "o", color="k", markersize=3, zorder=4,
                       gid=f"{name}:handover:{span.label}")
    if len(trace):
        plane.plot([x[0]], [y[0]], "o", markerfacecolor="none", markeredgecolor="k",
                   markersize=8, zorder=5, label="start", gid=f"{name}:start")
        plane.plot([x[-1]], [y[-1]], "s", color="k", markersize=6, zorder=5, label="end",
                   gid=f"{name}:end")
    _mark_refused(plane, trace, name)
    plane.set_aspect("equal", adjustable="datalim")
    plane.set_xlabel("x [mm] (MCS)")
    plane.set_ylabel("y [mm] (MCS)")
    plane.grid(True, alpha=0.3)
    plane.legend(loc="best", fontsize="small")


def _mark_refused(plane: Axes, trace: Trace, name: str) -> None:
    mark_refusals(plane, [(value_at(trace, f"{name}.x", event.time),
                           value_at(trace, f"{name}.y", event.time), event_text(event))
                          for event in trace.events
                          if event.object == name and event.result == "ERROR"])


def _draw_profiles(panels: list[Axes], trace: Trace, name: str, group: dict[str, Any],
                   spans: list[Span], colors: dict[str, str]) -> None:
    axes = [axis for axis in group.get("axes", []) if f"{axis}.set_position" in trace]
    axis_colors = distinct_colors(len(axes))
    for panel, (label, signal, path_signal) in zip(panels, PROFILES, strict=True):
        for axis, color in zip(axes, axis_colors, strict=True):
            column = f"{axis}.{signal}"
            if column in trace:
                panel.plot(trace.time, trace[column], "-", color=color, linewidth=1.0,
                           label=axis, gid=column)
        column = f"{name}.{path_signal}"
        if path_signal is not None and column in trace:
            panel.plot(trace.time, trace[column], "--", color="k", linewidth=1.0,
                       label=f"{name} path", gid=column)
        for span in spans:
            panel.axvspan(span.start, span.end, color=colors[span.label], alpha=0.08,
                          linewidth=0.0, gid=f"span:{span.label}")
        panel.set_ylabel(label, fontsize="small")
        panel.grid(True, alpha=0.3)
        if panel.get_lines():
            panel.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    for panel in panels[:-1]:
        panel.tick_params(labelbottom=False)
    panels[-1].set_xlabel("time [s]")
