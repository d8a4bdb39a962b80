"""The planar plot: the stator field seen from above, with the movers' paths.

Grey squares are the stators (240 mm). With parts (§5) there is one panel per coordinate
system: each part is drawn in every position it can take there, filled where it ended and
dashed where it may move to, and a mover's samples go to the panel of the coordinate system
they were in (its ``coordinate_system`` signal). Each mover's path is a line in its colour,
its footprint (turned by c when c was recorded) drawn dashed where the trace starts and
filled where it ends, and its name just above where it ended, drawn over everything. A
command the planar group refused (or that failed) is a red cross at the mover's position when
it ended, labelled with its id below right of it. A router's obstacles are hatched grey
areas, and every way it planned (``planned_routes``, planar/routing/plans.py) is a thin
dashed line in the mover's colour, under its path.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.trace.plot import (
    NAME_ZORDER,
    RESULT_COLORS,
    distinct_colors,
    event_text,
    mark_refusals,
    new_figure,
    planar_movers,
    value_at,
)
from openmotion.trace.record import Trace

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

MOVER_SIZE = 155.0  #: footprint side [mm] when the layout does not give it (the default)
MARGIN = 40.0  #: around the field and the paths [mm]
NAME_OFFSET = 7.0  #: [points] from where a mover ended up to its name: clear of a cross there
ROUTE_ALPHA = 0.7  #: opacity of a planned way: the path drawn over it stays readable


def planar_figure(trace: Trace, title: str | None = None) -> Figure:
    """Stators or parts, every recorded mover's path and footprints, refused commands."""
    planar = trace.layout.get("planar", {})
    systems: list[int | None] = list(planar.get("coordinate_systems", [])) or [None]
    figure = new_figure(2.6 + 4.6 * len(systems), 6.0, title)
    panels = figure.subplots(1, len(systems), squeeze=False)[0]
    sizes = planar.get("movers", {})
    movers = planar_movers(trace)
    colors = distinct_colors(len(movers))
    for panel, system in zip(panels, systems, strict=True):
        _draw_field(panel, planar, system)
        if system == systems[0]:  # a router plans in the group's frame: the first system
            _draw_routes(panel, planar, dict(zip(movers, colors, strict=True)))
        for mover, color in zip(movers, colors, strict=True):
            _draw_mover(panel, trace, mover, sizes.get(mover, {}), color,
                        _in_system(trace, mover, system))
        _mark_refused(panel, trace, movers, system)
        panel.set_aspect("equal")
        panel.set_xlabel("x [mm]")
        panel.set_ylabel("y [mm]")
        if system is not None:
            panel.set_title(f"coordinate system 16#{system:08X}", fontsize="medium")
        _fit(panel)
    _legend(figure, panels)
    return figure


def _in_system(trace: Trace, mover: str, system: int | None) -> np.ndarray:
    """Which samples of ``mover`` lie in ``system`` (all without parts or without the
    mover's ``coordinate_system`` column)."""
    column = f"{mover}.coordinate_system"
    if system is None or column not in trace:
        return np.ones(len(trace), dtype=bool)
    return trace[column] == system


def _draw_field(panel: Axes, planar: dict[str, Any], system: int | None) -> None:
    from matplotlib.patches import Polygon, Rectangle

    if system is None:
        size = planar.get("stator_size", 240.0)
        for x, y in planar.get("stators", []):
            panel.add_patch(Rectangle((x, y), size, size, facecolor="0.93", edgecolor="0.75",
                                      linewidth=0.8, zorder=0, gid="stator"))
    for part in planar.get("parts", []):
        if system is not None and part["coordinate_system"] != system:
            continue
        outline = np.array(part["outline"])
        active = part.get("active", True)
        panel.add_patch(Polygon(outline, closed=True, facecolor="0.93" if active else "none",
                                edgecolor="tab:purple", linestyle="-" if active else "--",
                                linewidth=1.2, zorder=0 if active else 1, gid=part["name"]))
        low = outline.min(axis=0)
        panel.annotate(part["name"], (low[0], low[1]), xytext=(3, 3),
                       textcoords="offset points", fontsize=7, color="tab:purple", zorder=1)


def _draw_routes(panel: Axes, planar: dict[str, Any], colors: dict[str, str]) -> None:
    """The routers' obstacles (hatched) and every planned way (thin, dashed)."""
    from matplotlib.patches import Polygon

    for obstacle in planar.get("obstacles", []):
        for ring in obstacle["rings"]:
            panel.add_patch(Polygon(np.array(ring), closed=True, facecolor="0.8",
                                    edgecolor="0.35", hatch="///", linewidth=0.8, zorder=1,
                                    gid=f"obstacle:{obstacle['name']}"))
        low = np.array(obstacle["rings"][0]).min(axis=0)
        panel.annotate(obstacle["name"], (low[0], low[1]), xytext=(3, 3),
                       textcoords="offset points", fontsize=7, color="0.25", zorder=1)
    for k, route in enumerate(planar.get("planned_routes", [])):
        points = np.array(route["points"], dtype=float).reshape(-1, 2)
        panel.plot(points[:, 0], points[:, 1], "--", color=colors.get(route["mover"], "0.5"),
                   linewidth=0.9, alpha=ROUTE_ALPHA, zorder=2,
                   gid=f"route:{route['mover']}:{k}")


def _draw_mover(panel: Axes, trace: Trace, mover: str, size: dict[str, float], color: str,
                inside: np.ndarray) -> None:
    from matplotlib.patches import Polygon

    x, y = trace[f"{mover}.x"], trace[f"{mover}.y"]
    c = trace[f"{mover}.c"] if f"{mover}.c" in trace else np.zeros_like(x)
    if not inside.any():
        return
    width, height = size.get("width", MOVER_SIZE), size.get("height", MOVER_SIZE)
    panel.plot(np.where(inside, x, np.nan), np.where(inside, y, np.nan), "-", color=color,
               linewidth=1.2, zorder=3, label=mover, gid=mover)
    for index, filled in ((0, False), (-1, True)):
        if not inside[index]:
            continue
        corners = footprint(x[index], y[index], c[index], width, height)
        panel.add_patch(Polygon(corners, closed=True, zorder=2, linewidth=1.0,
                                edgecolor=color, facecolor=color if filled else "none",
                                alpha=0.35 if filled else 1.0,
                                linestyle="-" if filled else "--",
                                gid=f"{mover}:{'end' if filled else 'start'}"))
    if inside[-1]:
        panel.annotate(mover, (x[-1], y[-1]), xytext=(0, NAME_OFFSET),
                       textcoords="offset points", ha="center", va="bottom", fontsize=8,
                       zorder=NAME_ZORDER, gid=f"name:{mover}",
                       bbox={"boxstyle": "round,pad=0.15", "facecolor": "white",
                             "edgecolor": "none", "alpha": 0.7})


def footprint(x: float, y: float, c: float, width: float, height: float) -> np.ndarray:
    """The four corners of a width x height rectangle centred on (x, y), turned by c [°]."""
    half = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * (width / 2, height / 2)
    turn = np.radians(c)
    rotation = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    return half @ rotation.T + (x, y)


def _mark_refused(panel: Axes, trace: Trace, movers: list[str], system: int | None) -> None:
    refusals = []
    for event in trace.events:
        if event.object not in movers or event.result != "ERROR":
            continue
        column = f"{event.object}.coordinate_system"
        if system is not None and column in trace and \
                value_at(trace, column, event.time) != system:
            continue
        refusals.append((value_at(trace, f"{event.object}.x", event.time),
                         value_at(trace, f"{event.object}.y", event.time), event_text(event)))
    mark_refusals(panel, refusals)


def _fit(panel: Axes) -> None:
    """Limits around everything drawn, with a margin."""
    panel.autoscale_view()
    (x0, x1), (y0, y1) = panel.get_xlim(), panel.get_ylim()
    panel.set_xlim(x0 - MARGIN, x1 + MARGIN)
    panel.set_ylim(y0 - MARGIN, y1 + MARGIN)


def _legend(figure: Figure, panels: Any) -> None:
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = [Patch(facecolor="none", edgecolor="0.3", linestyle="--", label="start"),
               Patch(facecolor="0.6", edgecolor="0.3", label="end"),
               Line2D([], [], color="0.3", label="path")]
    lines = [str(line.get_gid()) for panel in panels for line in panel.get_lines()]
    if any(gid.startswith("route:") for gid in lines):
        handles.append(Line2D([], [], color="0.3", linestyle="--", linewidth=0.9,
                              label="planned route"))
    if any(str(patch.get_gid()).startswith("obstacle:") for panel in panels
           for patch in panel.patches):
        handles.append(Patch(facecolor="0.8", edgecolor="0.35", hatch="///", label="obstacle"))
    if any(str(line.get_gid()).startswith("refused:")
           for panel in panels for line in panel.get_lines()):
        handles.append(Line2D([], [], color=RESULT_COLORS["ERROR"], marker="X", linestyle="",
                              label="refused command"))
    figure.legend(handles=handles, loc="outside right upper", fontsize="small")
