"""The viewer's planar panel draws tracks, switches and collision ranges (issue 8, point 6)."""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.planar import MC_PlanarTrack, PlanarState, PositionXYC
from openmotion.planar.system import PlanarSystem
from openmotion.viewer.planar import TRACK_STEP, PlanarLayer


def _merge() -> tuple[om.Runtime, list[MC_PlanarTrack]]:
    rt = om.Runtime(0.001)
    out = MC_PlanarTrack(rt, "out")
    out.append_line(PositionXYC(720.0, 240.0), PositionXYC(1680.0, 240.0))
    ins = []
    for name, y in (("in1", 240.0), ("in2", 720.0)):
        track = MC_PlanarTrack(rt, name)
        track.append_line(PositionXYC(0.0, y), PositionXYC(480.0, y))
        track.end_at_track(out)
        ins.append(track)
    for track in (out, *ins):
        track.enable()
    rt.run_until(lambda: all(t.state is PlanarState.ENABLED for t in (out, *ins)), timeout=1.0)
    return rt, [out, *ins]


def test_the_panel_holds_tracks_switches_and_collision_ranges():
    rt, tracks = _merge()
    panel = PlanarLayer(PlanarSystem.of(rt)).panel()
    drawn = {t["name"]: t for t in panel["tracks"]}
    assert set(drawn) == {"out", "in1", "in2"}
    for track in tracks:
        points = drawn[track.name]["points"]
        assert len(points) >= track.get_length() / TRACK_STEP
        end = track.get_position_at(track.get_length())
        assert points[-1] == pytest.approx([end.x, end.y], abs=0.1)
        assert drawn[track.name]["mode"] == "STANDING"
    assert panel["switches"] == [pytest.approx([720.0, 240.0], abs=0.1)]
    # the two incoming tracks run close before the merge: a range at their ends, none on out
    assert len(drawn["in1"]["ranges"]) == 1 and len(drawn["in2"]["ranges"]) == 1
    assert drawn["out"]["ranges"] == []


def test_the_objects_table_lists_the_tracks():
    rt, _ = _merge()
    rows = [row for row in PlanarLayer(PlanarSystem.of(rt)).rows() if row.kind == "planar track"]
    assert [row.name for row in rows] == ["out", "in1", "in2"]
    assert all("standing" in row.detail for row in rows)
