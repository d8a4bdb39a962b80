"""The rail plot of CA groups: mover positions over time with the gap band, and the gaps.

Per group, two panels sharing the time axis. Top: each mover's set position; below it a band
as deep as the group's default gap, the stretch its follower must keep out of (TF5410: the
gap is measured from a mover back to its follower). On a ring a line breaks where the mover
passes the rail end, and the band wraps with it. Bottom: each mover's setpoint gap to its
predecessor, the default gap dashed; the panel shows four default gaps, or more when most
movers keep more (the ring's wrap pair, with a gap of nearly a lap, may then leave it). A
mover's own command events sit on its line (issued: a dot; aborted or failed: a cross); a
group command's are dotted lines.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from openmotion.trace.plot import (
    RESULT_COLORS,
    ca_groups,
    distinct_colors,
    event_text,
    new_figure,
    value_at,
)
from openmotion.trace.record import Trace

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

BAND_ALPHA = 0.15
GAP_SPAN = 4.0  #: the gap panel shows at least 0 to this many default gaps


def rail_figure(trace: Trace, title: str | None = None) -> Figure:
    """Positions with gap bands, and gaps, for every CA group the trace holds."""
    groups = ca_groups(trace)
    figure = new_figure(9.0, 4.6 * max(len(groups), 1) + 0.6, title)
    if not groups:
        figure.add_subplot().text(0.5, 0.5, "no CA mover positions recorded", ha="center",
                                  va="center")
        return figure
    grid = figure.subplots(2 * len(groups), 1, sharex=True, squeeze=False,
                           height_ratios=[3, 1] * len(groups))[:, 0]
    for number, (name, group) in enumerate(groups.items()):
        _draw_group(grid[2 * number], grid[2 * number + 1], trace, name, group)
    grid[-1].set_xlabel("time [s]")
    return figure


def _draw_group(rail: Axes, gaps: Axes, trace: Trace, name: str, group: dict[str, Any]) -> None:
    length, ring, gap = group["rail_length"], group["rail_is_ring"], group["default_gap"]
    movers = [mover for mover in group["movers"] if f"{mover}.set_position" in trace]
    time = trace.time
    for mover, color in zip(movers, distinct_colors(len(movers)), strict=True):
        position = trace[f"{mover}.set_position"]
        times, line = _broken(time, position, length) if ring else (time, position)
        rail.plot(times, line, "-", color=color, linewidth=1.0, label=mover, gid=mover)
        for shift in (0.0, length) if ring else (0.0,):
            rail.fill_between(times, line - gap + shift, line + shift, color=color,
                              alpha=BAND_ALPHA, linewidth=0.0)
        if f"{mover}.gap" in trace:
            values = trace[f"{mover}.gap"]
            gaps.plot(time, np.where(np.isfinite(values), values, np.nan), "-", color=color,
                      linewidth=1.0, gid=f"{mover}.gap")
        _mark_mover_events(rail, trace, mover, color, length if ring else None)
    for event in trace.events:
        if event.object == name and event.result == "ISSUED":
            for panel in (rail, gaps):
                panel.axvline(event.time, color=RESULT_COLORS["ISSUED"], linestyle=":",
                              linewidth=0.8, gid=f"event:{event_text(event)}")
    for station in group.get("stations", ()):
        for slot, position in enumerate(station["slots"]):
            rail.axhline(position, color="0.35", linestyle="--", linewidth=0.7,
                         gid=f"station:{station['name']}:{slot}")
        rail.annotate(station["name"], (1.0, station["slots"][0]),
                      xycoords=("axes fraction", "data"), xytext=(-4, 2),
                      textcoords="offset points", ha="right", fontsize="small", color="0.35")
    gaps.axhline(gap, color="tab:red", linestyle="--", linewidth=0.8,
                 label=f"default gap {gap:g} mm")
    largest = [float(np.max(values[np.isfinite(values)])) for values in
               (trace[f"{mover}.gap"] for mover in movers if f"{mover}.gap" in trace)
               if np.isfinite(values).any()]
    if gap > 0 and largest:  # the ring's wrap pair would hide the close gaps of the others
        gaps.set_ylim(0.0, max(GAP_SPAN * gap, 1.1 * float(np.median(largest))))
    kind = "ring" if ring else "open rail"
    rail.set_title(f"{name}: {kind} of {length:g} mm, gap band {gap:g} mm", fontsize="medium")
    rail.set_ylabel("set position [mm]")
    if ring:
        rail.set_ylim(0.0, length)
    rail.grid(True, alpha=0.3)
    rail.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small",
                ncols=1 + len(movers) // 16)
    gaps.set_ylabel("gap [mm]")
    gaps.grid(True, alpha=0.3)
    gaps.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")


def _broken(time: np.ndarray, position: np.ndarray,
            length: float) -> tuple[np.ndarray, np.ndarray]:
    """Positions modulo the rail length, with a NaN point put in where the mover passes the
    rail end, so that no line crosses the panel."""
    wrapped = np.mod(position, length)
    jumps = np.flatnonzero(np.abs(np.diff(wrapped)) > length / 2) + 1
    return np.insert(time, jumps, np.nan), np.insert(wrapped, jumps, np.nan)


def _mark_mover_events(rail: Axes, trace: Trace, mover: str, color: str,
                       length: float | None) -> None:
    for event in trace.events:
        if event.object != mover or event.result == "DONE":
            continue
        position = value_at(trace, f"{mover}.set_position", event.time)
        if length is not None:
            position %= length
        issued = event.result == "ISSUED"
        rail.plot([event.time], [position], "o" if issued else "x",
                  markersize=3.5 if issued else 6,
                  color=color if issued else RESULT_COLORS.get(event.result, "k"),
                  gid=f"event:{event_text(event)}")
