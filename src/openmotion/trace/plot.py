"""A trace's figures: the scope (scope.py), the rail of a CA group (rail.py), the planar
surface (planar.py), the path of an axes group (path.py), and which of them is a trace's
default.

matplotlib is imported inside the functions, never with the package, and every figure is
drawn on an Agg canvas of its own: no pyplot, no global backend, no GUI and no warnings.
``save_plot`` takes the image format from the file's suffix: PNG, SVG or PDF. Objects and
commands get colours from ``distinct_colors``: as many different ones as there are to tell
apart. Labels are drawn above the marks they name.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.core.errors import ConfigError
from openmotion.trace.record import Trace

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

IMAGE_FORMATS = ("png", "svg", "pdf")  #: by the file's suffix
DPI = 110  #: dots per inch of a PNG (SVG and PDF are vector images)
FIGURES = ("planar", "path", "rail", "scope")  #: in the order ``default_figure`` considers
#: them; what each figure needs of a planar mover, of a CA mover, of an axes group and of
#: each of its members
PLANAR_FIGURE_SIGNALS = ("x", "y", "c")
RAIL_FIGURE_SIGNALS = ("set_position", "gap")
PATH_FIGURE_SIGNALS = ("x", "y", "path_velocity")
PATH_MEMBER_SIGNALS = ("set_position", "set_velocity", "set_acceleration")
#: colour of an event by its result
RESULT_COLORS = {"ISSUED": "0.45", "DONE": "tab:green", "ABORTED": "tab:orange",
                 "ERROR": "tab:red"}
GOLDEN = (5 ** 0.5 - 1) / 2  #: hue step between neighbours beyond twenty colours
LIGHTNESS = (0.38, 0.52, 0.66)  #: taken in turn beyond twenty colours
#: drawing order: a refused command's cross, its label above it, an object's name above all
REFUSAL_ZORDER, REFUSAL_LABEL_ZORDER, NAME_ZORDER = 5.0, 6.0, 7.0
LABEL_STEP = 8.0  #: [points] between the labels of refusals at one point


def distinct_colors(count: int) -> list[str]:
    """``count`` colours, no two alike (hex): tab10 first (matplotlib's default cycle), then
    tab20's light tones, then hues a golden-ratio step apart in three lightnesses, so that
    neighbours in the list differ clearly. A longer list starts as a shorter one: one more
    command does not recolour the others. (Beyond a few thousand, colours repeat.)"""
    import colorsys

    from matplotlib import colormaps
    from matplotlib.colors import to_hex

    tab20 = colormaps["tab20"].colors
    colors = dict.fromkeys(to_hex(color) for color in (*tab20[0::2], *tab20[1::2]))
    for index in range(2 * count):  # twice as many as needed: a clash is skipped
        if len(colors) >= count:
            break
        rgb = colorsys.hls_to_rgb((index * GOLDEN) % 1.0, LIGHTNESS[index % 3], 0.8)
        colors.setdefault(to_hex(rgb))
    unique = list(colors)
    return [unique[index % len(unique)] for index in range(count)]  # repeats: thousands


def image_format(path: str | Path) -> str:
    """The image format of ``path`` by its suffix; ConfigError for any other suffix."""
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in IMAGE_FORMATS:
        raise ConfigError(f"{path}: the image format comes from the suffix: "
                          f"{', '.join('.' + name for name in IMAGE_FORMATS)}")
    return suffix


def new_figure(width: float, height: float, title: str | None = None) -> Figure:
    """An empty figure on an Agg canvas of its own, laid out by matplotlib (constrained)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(figure)
    if title:
        figure.suptitle(title)
    return figure


def planar_movers(trace: Trace) -> list[str]:
    """The planar movers of the layout whose x and y the trace holds."""
    movers = trace.layout.get("planar", {}).get("movers", {})
    return [name for name in movers if f"{name}.x" in trace and f"{name}.y" in trace]


def ca_groups(trace: Trace) -> dict[str, dict[str, Any]]:
    """The CA groups of the layout with at least one mover whose set position is recorded."""
    return {name: group for name, group in trace.layout.get("ca_groups", {}).items()
            if any(f"{mover}.set_position" in trace for mover in group["movers"])}


def axes_groups(trace: Trace) -> dict[str, dict[str, Any]]:
    """The axes groups of the layout whose TCP x and y the trace holds."""
    return {name: group for name, group in trace.layout.get("axes_groups", {}).items()
            if f"{name}.x" in trace and f"{name}.y" in trace}


def default_figure(trace: Trace) -> str:
    """``planar`` when the trace holds planar movers' x and y, ``path`` when it holds axes
    groups' TCP x and y, ``rail`` when it holds CA movers' set positions, else ``scope``."""
    if planar_movers(trace):
        return "planar"
    if axes_groups(trace):
        return "path"
    return "rail" if ca_groups(trace) else "scope"


def figure_signals(layout: dict[str, Any]) -> list[str]:
    """What the default figure of a run with this layout needs recorded: x, y, c of every
    planar mover (and its coordinate system when there are parts); else x, y and path
    velocity of every axes group and set position, velocity and acceleration of its members;
    else set position and gap of every CA mover; else nothing beyond the recorded signals
    (the scope)."""
    planar = layout.get("planar", {})
    movers = planar.get("movers", {})
    if movers:
        props = (*PLANAR_FIGURE_SIGNALS, "coordinate_system") if planar.get("parts") \
            else PLANAR_FIGURE_SIGNALS
        return [f"{name}.{prop}" for name in movers for prop in props]
    groups = layout.get("axes_groups", {})
    if groups:
        return [*(f"{name}.{prop}" for name in groups for prop in PATH_FIGURE_SIGNALS),
                *(f"{axis}.{prop}" for group in groups.values() for axis in group["axes"]
                  for prop in PATH_MEMBER_SIGNALS)]
    return [f"{mover}.{prop}" for group in layout.get("ca_groups", {}).values()
            for mover in group["movers"] for prop in RAIL_FIGURE_SIGNALS]


def plot_trace(trace: Trace, title: str | None = None,
               signals: Sequence[str] | None = None) -> Figure:
    """The trace's default figure (``default_figure``); with ``signals``, the scope figure
    of those signals (or objects: every recorded signal of each). ``title`` defaults to the
    trace's own."""
    from openmotion.trace.path import path_figure
    from openmotion.trace.planar import planar_figure
    from openmotion.trace.rail import rail_figure
    from openmotion.trace.scope import scope_figure

    title = trace.title if title is None else title
    if signals:
        return scope_figure(trace, signals, title)
    kind = default_figure(trace)
    if kind == "planar":
        return planar_figure(trace, title)
    if kind == "path":
        return path_figure(trace, title)
    return rail_figure(trace, title) if kind == "rail" else scope_figure(trace, None, title)


def save_plot(trace: Trace, path: str | Path, title: str | None = None,
              signals: Sequence[str] | None = None, dpi: float = DPI) -> Path:
    """Draw ``plot_trace(trace, title, signals)`` into ``path`` (PNG, SVG or PDF by suffix)."""
    path = Path(path)
    kind = image_format(path)
    plot_trace(trace, title, signals).savefig(path, format=kind, dpi=dpi,
                                              metadata=_METADATA[kind])
    return path


#: no creation date or tool version in the files, so that a figure is reproducible
_METADATA: dict[str, dict[str, Any]] = {
    "png": {"Software": None},
    "svg": {"Date": None, "Creator": None},
    "pdf": {"CreationDate": None, "Creator": None, "Producer": None},
}


def value_at(trace: Trace, name: str, time: float) -> float:
    """The value of column ``name`` at the last sample at or before ``time`` (the first
    sample before the trace starts; NaN for an empty trace)."""
    times = trace.time
    if not times.size:
        return float("nan")
    index = max(int(np.searchsorted(times, time, side="right")) - 1, 0)
    return float(trace[name][index])


def event_text(event: Any) -> str:
    """How a figure labels an event: its label, else its command."""
    return event.label or event.command


def mark_refusals(panel: Axes, refusals: Sequence[tuple[float, float, str]]) -> None:
    """A red cross at each (x, y, label) with the label below right of it; the labels of
    several refusals at one point go one under the other."""
    at_point: dict[tuple[float, float], int] = {}
    for x, y, text in refusals:
        count = at_point.get((x, y), 0)
        at_point[(x, y)] = count + 1
        panel.plot([x], [y], "X", color=RESULT_COLORS["ERROR"], markersize=9,
                   markeredgecolor="white", zorder=REFUSAL_ZORDER, gid=f"refused:{text}")
        panel.annotate(text, (x, y), xytext=(6, -10 - LABEL_STEP * count),
                       textcoords="offset points", fontsize=7, color=RESULT_COLORS["ERROR"],
                       zorder=REFUSAL_LABEL_ZORDER, gid=f"refused-label:{text}")
