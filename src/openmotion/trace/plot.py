"""The scope figure: position, velocity, acceleration, jerk (and following error) per axis.

matplotlib is imported inside the functions, never with the package, and the figure is drawn
on an Agg canvas of its own: no pyplot, no global backend, no GUI and no warnings.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from openmotion.trace.record import Trace

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: One panel per quantity: (title, [(signal, line style, label)]).
PANELS = (
    ("position [mm]", (("set_position", "-", "set"), ("position", "--", "actual"))),
    ("velocity [mm/s]", (("set_velocity", "-", "set"), ("velocity", "--", "actual"))),
    ("acceleration [mm/s²]", (("set_acceleration", "-", "set"),)),
    ("jerk [mm/s³]", (("set_jerk", "-", "set"),)),
    ("following error [mm]", (("following_error", "-", "set - actual"),)),
)


def plot_trace(trace: Trace, title: str | None = None) -> Figure:
    """A figure with one column per axis and one row per recorded quantity."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    axes = trace.axes
    rows = [(name, lines) for name, lines in PANELS
            if any(f"{axis}.{signal}" in trace for axis in axes for signal, _, _ in lines)]
    figure = Figure(figsize=(4.5 * max(len(axes), 1) + 1.5, 1.9 * max(len(rows), 1) + 0.8),
                    layout="constrained")
    FigureCanvasAgg(figure)
    if title:
        figure.suptitle(title)
    if not rows:
        figure.add_subplot().text(0.5, 0.5, "no position, velocity, acceleration or jerk "
                                  "signals recorded", ha="center", va="center")
        return figure
    grid = figure.subplots(len(rows), len(axes), sharex=True, squeeze=False)
    for column, axis in enumerate(axes):
        for row, (name, lines) in enumerate(rows):
            panel = grid[row][column]
            for signal, style, label in lines:
                key = f"{axis}.{signal}"
                if key in trace:
                    panel.plot(trace.time, trace[key], style, linewidth=1.0, label=label)
            panel.grid(True, alpha=0.3)
            if column == 0:
                panel.set_ylabel(name)
            if row == 0:
                panel.set_title(axis)
            if len(panel.get_lines()) > 1:
                panel.legend(loc="best", fontsize="small")
        grid[-1][column].set_xlabel("time [s]")
    return figure


def save_plot(trace: Trace, path: str | Path, title: str | None = None) -> Path:
    """Draw the scope figure of ``trace`` into ``path`` (the suffix picks the format)."""
    path = Path(path)
    plot_trace(trace, title).savefig(path, dpi=110)
    return path
