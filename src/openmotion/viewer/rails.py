"""The CA groups: a rail (a ring or an open line) with its movers, their gaps and parts."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from openmotion.transport.group import CaGroup
from openmotion.viewer.axes import axis_row
from openmotion.viewer.layers import (
    Layer,
    Row,
    error_text,
    finite,
    number,
)

if TYPE_CHECKING:
    from openmotion.runtime.runtime import Runtime


class RailLayer(Layer):
    """One CA group on its rail. Movers come in CA order: the first is the leader."""

    kind = "rail"

    def __init__(self, group: CaGroup) -> None:
        self.name = group.name
        self._group = group

    def panel(self) -> dict[str, Any]:
        group, parameters = self._group, self._group.parameters
        movers = []
        for mover, gap in zip(group.movers, group.gaps().tolist(), strict=True):
            axis = mover.axis
            movers.append({"name": axis.name, "position": finite(axis.set_position),
                           "velocity": finite(axis.set_velocity), "gap": finite(gap),
                           "wanted_gap": finite(mover.gap), "error": axis.error})
        parts = [{"id": part.part_id, "start": part.start, "end": part.end}
                 for part in group.tracks.parts.values()]
        stations = [{**station, "queue": state.queue_length, "occupied": state.occupied,
                     "processed": state.processed}
                    for line in group.station_lines
                    for station, state in zip(line.layout(), line.objects(), strict=True)]
        return {"length": parameters.rail_length, "ring": parameters.rail_is_ring,
                "state": group.state.name, "movers": movers, "parts": parts,
                "stations": stations}

    def rows(self) -> list[Row]:
        group = self._group
        rows = [Row("CA group", group.name, group.state.name.lower(),
                    detail=f"{len(group.movers)} movers",
                    error=error_text(group.error_id, ""))]
        for line in group.station_lines:
            for state in line.objects():
                rows.append(Row("station", state.name, f"{state.occupied} busy",
                                detail=f"queue {state.queue_length}, {state.processed} done, "
                                       f"{60.0 * state.processed / state.elapsed:.1f}/min"
                                       if state.elapsed > 0 else "starting"))
        for mover, gap in zip(group.movers, group.gaps().tolist(), strict=True):
            track = group.tracks.active_track(mover.axis)
            detail = f"gap {number(gap, 1)}" + (f", track {track.track_id}" if track else "")
            rows.append(axis_row(mover.axis, "CA mover", detail))
        return rows


def rail_layers(runtime: Runtime) -> list[Layer]:
    """One layer per CA group on the runtime."""
    return [RailLayer(system) for system in runtime.systems
            if isinstance(system, CaGroup)]
