"""The scope figure: stacked panels sharing the time axis, one per quantity, with units.

Each recorded signal goes to the panel of its quantity (positions, velocities, ...), one
colour per object, setpoints solid and actual values dashed. Command events are marked on
every panel: a dotted line where a command was issued (labelled with its id in the top
panel; commands issued too close together to be told apart share one label, their ids joined)
and, at the top edge, a triangle where it ended, coloured by its result.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from openmotion.coordinated.states import AxesGroupState
from openmotion.core.enums import AxisState
from openmotion.core.errors import ConfigError
from openmotion.planar import PlanarState
from openmotion.trace.plot import RESULT_COLORS, distinct_colors, event_text, new_figure
from openmotion.trace.record import Trace

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: (panel title with its unit, the signals drawn in it), top to bottom
QUANTITIES = (
    ("position [mm]", ("set_position", "position", "track_position", "tcp_position", "x",
                       "y")),
    ("velocity [mm/s]", ("set_velocity", "velocity", "path_velocity")),
    ("acceleration [mm/s²]", ("set_acceleration", "path_acceleration")),
    ("jerk [mm/s³]", ("set_jerk",)),
    ("following error [mm]", ("following_error",)),
    ("gap [mm]", ("gap",)),
    ("height [mm]", ("z",)),
    ("angle [°]", ("a", "b", "c")),
    ("override [%]", ("override",)),
    ("state", ("state",)),
    ("coordinate system", ("coordinate_system",)),
    ("homed", ("homed",)),
    ("error id", ("axis_error_id",)),
)
_STYLES = {"position": "--", "velocity": "--", "path_velocity": "--", "y": "-.", "b": "--",
           "c": "-.", "tcp_position": ":", "track_position": "-."}
_STEPS = frozenset({"state", "homed", "axis_error_id", "coordinate_system"})
_STATES = {"axis": AxisState, "planar_mover": PlanarState, "planar_group": PlanarState,
           "axes_group": AxesGroupState}
MAX_LABELS = 40  #: issue labels at most; more are only marked
LABEL_SPACING = 0.015  #: issue labels closer than this share of the time axis are one label


def selected(trace: Trace, signals: Sequence[str] | None) -> list[str]:
    """The columns to draw: ``signals`` by column name, or an object's name for all of its
    columns; all of them for None. ConfigError names what the trace lacks."""
    if signals is None:
        return list(trace.signals)
    chosen: list[str] = []
    for name in signals:
        columns = [name] if name in trace and name != "time" else \
            [column for column in trace.signals if _split(column)[0] == name]
        if not columns:
            raise ConfigError(f"signals: {name!r} is neither a column nor an object of the "
                              f"trace; columns: {', '.join(trace.signals)}")
        chosen += [column for column in columns if column not in chosen]
    return chosen


def panels_for(columns: Sequence[str]) -> list[tuple[str, list[str]]]:
    """(title, columns) per panel in QUANTITIES order; a signal of no quantity gets a panel
    of its own, after them."""
    panels = []
    for title, props in QUANTITIES:
        members = [name for name in columns if _split(name)[1] in props]
        if members:
            panels.append((title, members))
    known = {prop for _, props in QUANTITIES for prop in props}
    panels += [(_split(name)[1], [name]) for name in columns if _split(name)[1] not in known]
    return panels


def _split(column: str) -> tuple[str, str]:
    """(object, signal) of a column; a column without a dot is both (a CSV of any kind)."""
    subject, _, prop = column.partition(".")
    return subject, prop or column


def scope_figure(trace: Trace, signals: Sequence[str] | None = None,
                 title: str | None = None) -> Figure:
    """Stacked panels of ``signals`` (default: every column) over time, events marked."""
    columns = selected(trace, signals)
    panels = panels_for(columns)
    figure = new_figure(8.0, 1.7 * max(len(panels), 1) + 1.2, title)
    if not panels:
        figure.add_subplot().text(0.5, 0.5, "no signals recorded", ha="center", va="center")
        return figure
    grid = figure.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    objects = list(dict.fromkeys(_split(name)[0] for name in columns))
    colors = dict(zip(objects, distinct_colors(len(objects)), strict=True))
    for panel, (name, members) in zip(grid, panels, strict=True):
        for column in members:
            subject, prop = _split(column)
            panel.plot(trace.time, trace[column], _STYLES.get(prop, "-"), color=colors[subject],
                       linewidth=1.0, label=column, gid=column,
                       drawstyle="steps-post" if prop in _STEPS else "default")
        panel.set_ylabel(name)
        panel.grid(True, alpha=0.3)
        if name == "state":
            _state_ticks(panel, trace, members)
        elif name == "homed":
            panel.set_yticks([0.0, 1.0], ["no", "yes"])
        if len(members) > 1:
            panel.legend(loc="best", fontsize="small")
    grid[-1].set_xlabel("time [s]")
    _mark_events(figure, list(grid), trace, set(objects))
    return figure


def _state_ticks(panel: Axes, trace: Trace, members: list[str]) -> None:
    """Name the states on the y axis when all objects in the panel share one state enum."""
    kinds = {trace.layout.get("objects", {}).get(_split(name)[0]) for name in members}
    enums = {_STATES.get(kind) for kind in kinds}  # type: ignore[arg-type]
    if len(enums) != 1 or None in enums:
        return
    enum = enums.pop()
    values = sorted({int(v) for name in members for v in trace[name] if v == v})
    panel.set_yticks(values, [enum(v).name.lower() for v in values], fontsize="small")


def issue_labels(issued: Sequence[Any], duration: float) -> list[tuple[float, str]]:
    """(time, text) of the issue labels: events in time order, each issued less than
    ``LABEL_SPACING`` of ``duration`` after the first of a label (or with it) joins it."""
    labels: list[tuple[float, list[str]]] = []
    for event in issued:
        if labels and event.time - labels[-1][0] <= LABEL_SPACING * duration:
            labels[-1][1].append(event_text(event))
        else:
            labels.append((event.time, [event_text(event)]))
    return [(time, ", ".join(dict.fromkeys(texts))) for time, texts in labels]


def _mark_events(figure: Figure, panels: list[Axes], trace: Trace, objects: set[str]) -> None:
    from matplotlib.lines import Line2D

    events = [event for event in trace.events if event.object in objects]
    if not events:
        return
    top = panels[0]
    issued = [event for event in events if event.result == "ISSUED"]
    for event in issued:
        for panel in panels:
            panel.axvline(event.time, color=RESULT_COLORS["ISSUED"], linestyle=":",
                          linewidth=0.8, gid=f"event:{event_text(event)}")
    labels = issue_labels(issued, float(trace.time[-1] - trace.time[0]) if len(trace) else 0.0)
    for time, text in labels if len(labels) <= MAX_LABELS else ():
        top.annotate(text, (time, 1.0), xycoords=top.get_xaxis_transform(), xytext=(2, -6),
                     textcoords="offset points", rotation=90, va="top", ha="left",
                     fontsize=6, color="0.3", gid=f"label:{text}")  # below the end marks
    ended = [event for event in events if event.result != "ISSUED"]
    for result in dict.fromkeys(event.result for event in ended):
        times = [event.time for event in ended if event.result == result]
        top.plot(times, [1.0] * len(times), "v", color=RESULT_COLORS.get(result, "k"),
                 markersize=6, clip_on=False, transform=top.get_xaxis_transform(),
                 gid=f"events:{result}")
    results = ["ISSUED", *dict.fromkeys(event.result for event in ended)] if issued else \
        list(dict.fromkeys(event.result for event in ended))
    handles: list[Any] = [
        Line2D([], [], color=RESULT_COLORS["ISSUED"], linestyle=":", label="issued")
        if result == "ISSUED" else
        Line2D([], [], color=RESULT_COLORS.get(result, "k"), marker="v", linestyle="",
               label=result.lower()) for result in results]
    figure.legend(handles=handles, loc="outside lower center", ncols=len(handles),
                  fontsize="small", frameon=False)
