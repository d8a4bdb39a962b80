"""Track management (TF5410 §8.3, §9.1.1.1.5-6; digest D1.12, D3.1.5-6, D5 T17; D-074).

The ring of 3000 mm is cut into three parts of 1000 mm: 11 [0, 1000), 12 [1000, 2000),
13 [2000, 3000). Track 21 = 11 + 12 is open; track 22 = 12 + 13 + 11 is closed and starts at
1000; track 23 = 13 alone.
"""

from __future__ import annotations

from typing import Any

import pytest

import openmotion as om
from openmotion.transport import (
    UDINT_TO_IDENTINGROUP,
    CaGroup,
    MC_ActivateTrack,
    MC_AddAxisToGroup,
    MC_GroupEnable,
    MC_MoveAbsoluteCA,
    MC_MoveRelativeCA,
    MC_ReadTrackPositions,
    ModuloDirection,
)

ErrorId = om.ErrorId
AXIS = {"max_velocity": 1000.0, "max_deceleration": 20000.0, "max_jerk": 1.0e6}


def ring(*positions: float, ring_rail: bool = True) -> tuple[om.Runtime, CaGroup, list[om.Axis]]:
    """An enabled CA group on 3000 mm with the parts and tracks of the module docstring."""
    rt = om.Runtime()
    group = CaGroup(rt, "ca", rail_length=3000.0, rail_is_ring=ring_rail)
    axes = []
    for ident, position in enumerate(positions, 1):
        axis = rt.add_axis(f"m{ident}", position=position, **AXIS)
        assert axis.power()
        MC_AddAxisToGroup(group)(execute=True, axis=axis,
                                 ident_in_group=UDINT_TO_IDENTINGROUP(ident))
        axes.append(axis)
    MC_GroupEnable(group)(execute=True)
    tracks = group.tracks
    tracks.add_part(11, 0.0, 1000.0)
    tracks.add_part(12, 1000.0, 2000.0)
    tracks.add_part(13, 2000.0, 3000.0)
    tracks.add_track(21, [11, 12])
    if ring_rail:
        tracks.add_track(22, [12, 13, 11])
    tracks.add_track(23, [13])
    return rt, group, axes


def move(rt: om.Runtime, axis: om.Axis, **inputs: Any) -> MC_MoveAbsoluteCA:
    """MC_MoveAbsoluteCA to the end; the block afterwards."""
    fb = MC_MoveAbsoluteCA(axis)
    for _ in range(20000):
        fb(execute=True, velocity=500.0, **inputs)
        if not fb.busy:
            return fb
        rt.step()
    raise AssertionError("the move did not end")


def read(axis: om.Axis) -> MC_ReadTrackPositions:
    fb = MC_ReadTrackPositions(axis)
    fb(enable=True)
    return fb


def activate(axis: om.Axis, track_id: Any) -> MC_ActivateTrack:
    fb = MC_ActivateTrack(axis)
    fb(execute=True, track_id=track_id)
    return fb


# -- configuration -------------------------------------------------------------------------------


def test_tracks_know_their_parts_lengths_and_whether_they_are_closed():
    _, group, _ = ring(500.0)
    open_, closed = group.tracks.tracks[21], group.tracks.tracks[22]
    assert (open_.length, open_.closed, open_.start, open_.offsets) == (2000.0, False, 0.0,
                                                                       (0.0, 1000.0))
    assert (closed.length, closed.closed, closed.start, closed.offsets) == (
        3000.0, True, 1000.0, (0.0, 1000.0, 2000.0))
    assert group.tracks.parts[13].length == 1000.0
    assert group.tracks.part_at(3500.0).part_id == 11  # a ring position after one lap


def test_a_part_may_wrap_over_the_ring_end_and_one_part_may_be_the_whole_ring():
    rt = om.Runtime()
    tracks = CaGroup(rt, "ca", rail_length=3000.0).tracks
    assert tracks.add_part(1, 2500.0, 500.0).length == 1000.0
    assert tracks.part_at(2999.0).part_id == tracks.part_at(0.0).part_id == 1
    whole = CaGroup(rt, "ca2", rail_length=3000.0).tracks
    assert whole.add_part(1, 700.0, 700.0).length == 3000.0
    assert whole.add_track(2, [1]).closed


@pytest.mark.parametrize(("call", "match"), [
    (lambda t: t.add_part(0, 0.0, 10.0), "OTCID"),
    (lambda t: t.add_part(11, 0.0, 10.0), "OTCID"),  # taken
    (lambda t: t.add_part(21, 0.0, 10.0), "OTCID"),  # a track has it
    (lambda t: t.add_part(5, -1.0, 10.0), "start"),
    (lambda t: t.add_part(5, 3000.0, 10.0), "start"),
    (lambda t: t.add_part(5, 0.0, 3000.5), "end"),
    (lambda t: t.add_track(24, [11, 13]), "does not start where"),
    (lambda t: t.add_track(24, []), "distinct existing parts"),
    (lambda t: t.add_track(24, [11, 99]), "unknown: \\[99\\]"),
    (lambda t: t.add_track(24, [11, 11]), "distinct"),
    (lambda t: t.add_track(True, [11]), "OTCID"),
], ids=["id-0", "id-taken", "id-of-a-track", "start<0", "start=L", "end>L", "not-adjacent",
        "empty", "unknown-part", "twice", "bool-id"])
def test_bad_configuration_is_a_config_error(call, match):
    _, group, _ = ring(500.0)
    with pytest.raises(om.ConfigError, match=match):
        call(group.tracks)


def test_overlapping_parts_are_a_config_error():
    rt = om.Runtime()
    tracks = CaGroup(rt, "ca", rail_length=3000.0).tracks
    tracks.add_part(1, 2500.0, 500.0)
    with pytest.raises(om.ConfigError, match="overlaps part 1"):
        tracks.add_part(2, 400.0, 600.0)
    with pytest.raises(om.ConfigError, match="overlaps part 1"):
        tracks.add_part(3, 2000.0, 2600.0)
    assert tracks.add_part(4, 500.0, 2500.0).length == 2000.0


def test_on_an_open_rail_parts_do_not_wrap_and_tracks_are_open():
    rt = om.Runtime()
    tracks = CaGroup(rt, "ca", rail_length=3000.0, rail_is_ring=False).tracks
    with pytest.raises(om.ConfigError, match="open rail"):
        tracks.add_part(1, 2500.0, 500.0)
    tracks.add_part(1, 0.0, 1500.0)
    tracks.add_part(2, 1500.0, 3000.0)
    track = tracks.add_track(3, [1, 2])
    assert (track.length, track.closed) == (3000.0, False)
    assert tracks.part_at(3000.0).part_id == 2  # the rail end belongs to the last part


# -- T17: MC_ReadTrackPositions and MC_ActivateTrack ---------------------------------------------


def test_read_without_an_active_track_gives_the_absolute_set_position_and_ids_0():
    """T17: TrackId = PartId = 0 and TrackPosition = the absolute setpoint."""
    _, _, (axis,) = ring(3500.0)  # after one lap: not reduced
    fb = read(axis)
    assert (fb.valid, fb.busy, fb.error) == (True, True, False)
    assert (fb.track_position, fb.track_id, fb.part_position, fb.part_id) == (
        3500.0, 0, 3500.0, 0)


def test_activate_a_track_whose_parts_the_mover_is_not_on_is_an_error():
    """T17: ActivateTrack with the mover on a foreign part."""
    _, group, (axis,) = ring(500.0)  # on part 11; track 23 is part 13 only
    fb = activate(axis, 23)
    assert fb.error and fb.error_id is ErrorId.NOT_ON_TRACK
    assert group.tracks.active_track(axis) is None
    assert read(axis).track_id == 0


@pytest.mark.parametrize("track_id", [99, -1, True, 1.5, 11], ids=["unknown", "negative",
                                                                   "bool", "float", "a-part"])
def test_activate_an_unknown_track_is_an_error(track_id):
    _, _, (axis,) = ring(500.0)
    fb = activate(axis, track_id)
    assert fb.error and fb.error_id is ErrorId.UNKNOWN_TRACK


def test_activate_then_read_then_activate_0_gives_the_absolute_frame_again():
    """T17: ActivateTrack(0) -> absolute frame."""
    _, _, (axis,) = ring(3500.0)  # 500 on the ring: part 11
    fb = activate(axis, 22)
    assert fb.done and not fb.busy
    positions = read(axis)
    # track 22 starts at 1000: 12 (1000) + 13 (1000) + 500 on part 11
    assert (positions.track_position, positions.track_id, positions.part_position,
            positions.part_id) == (2500.0, 22, 500.0, 11)
    assert activate(axis, 21).done
    positions = read(axis)
    assert (positions.track_position, positions.track_id, positions.part_id) == (500.0, 21, 11)
    assert activate(axis, 0).done
    positions = read(axis)
    assert (positions.track_position, positions.track_id, positions.part_position,
            positions.part_id) == (3500.0, 0, 3500.0, 0)


def test_read_and_activate_on_an_axis_in_no_ca_group_are_errors():
    rt = om.Runtime()
    axis = rt.add_axis("alone", **AXIS)
    axis.power()
    fb = read(axis)
    assert (fb.valid, fb.busy, fb.error, fb.error_id) == (False, False, True,
                                                          ErrorId.AXIS_NOT_IN_GROUP)
    assert activate(axis, 21).error_id is ErrorId.AXIS_NOT_IN_GROUP


def test_read_outputs_clear_when_enable_falls():
    _, _, (axis,) = ring(500.0)
    activate(axis, 21)
    fb = read(axis)
    assert fb.valid and fb.track_id == 21
    fb(enable=False)
    assert (fb.valid, fb.busy, fb.track_id, fb.track_position) == (False, False, 0, 0.0)


def test_a_mover_that_left_its_open_track_reads_an_error():
    rt, _, (axis,) = ring(1900.0)
    activate(axis, 21)  # [0, 2000)
    rel = MC_MoveRelativeCA(axis)
    for _ in range(20000):
        rel(execute=True, distance=300.0, velocity=500.0)
        if rel.done:
            break
        rt.step()
    fb = read(axis)
    assert (fb.valid, fb.error, fb.error_id) == (False, True, ErrorId.NOT_ON_TRACK)


# -- T17: MoveAbsoluteCA in track coordinates ----------------------------------------------------


def test_move_absolute_ca_in_closed_track_coordinates_ends_at_the_absolute_position():
    """T17: a MoveAbsoluteCA in track coordinates; track 22 starts at 1000."""
    rt, _, (axis,) = ring(3500.0)  # track position 2500
    assert activate(axis, 22).done
    assert move(rt, axis, position=2800.0).done  # NonModulo: by +300 from the read value
    assert axis.set_position == pytest.approx(3800.0, abs=1e-9)
    fb = move(rt, axis, position=100.0, direction=ModuloDirection.POSITIVE)
    assert fb.done  # modulo on the closed track: 2800 -> 100 forwards, over the track's zero
    assert axis.set_position == pytest.approx(4100.0, abs=1e-9)
    positions = read(axis)
    assert (positions.track_id, positions.part_id) == (22, 12)
    assert positions.track_position == pytest.approx(100.0, abs=1e-9)
    assert activate(axis, 0).done
    assert move(rt, axis, position=4000.0).done  # the absolute frame again
    assert axis.set_position == pytest.approx(4000.0, abs=1e-9)


def test_move_absolute_ca_in_open_track_coordinates():
    rt, group, (axis,) = ring(2500.0)
    assert activate(axis, 23).done  # part 13 only: [2000, 3000)
    assert move(rt, axis, position=900.0).done
    assert axis.set_position == pytest.approx(2900.0, abs=1e-9)
    assert group.tracks.to_absolute(axis, 0.0) == pytest.approx(2000.0, abs=1e-9)


@pytest.mark.parametrize(("inputs", "error_id"), [
    ({"position": 1000.5}, ErrorId.TARGET_OFF_TRACK),
    ({"position": -0.5}, ErrorId.TARGET_OFF_TRACK),
    ({"position": 10.0, "direction": ModuloDirection.POSITIVE}, ErrorId.INVALID_DIRECTION),
    ({"position": 10.0, "direction": ModuloDirection.SHORTEST_WAY}, ErrorId.INVALID_DIRECTION),
], ids=["beyond-the-end", "before-the-start", "positive", "shortest-way"])
def test_open_track_targets_outside_it_or_modulo_are_errors(inputs, error_id):
    """§9.4.1.3: open tracks take NonModulo only."""
    rt, _, (axis,) = ring(2500.0)
    activate(axis, 23)
    fb = MC_MoveAbsoluteCA(axis)
    fb(execute=True, velocity=500.0, **inputs)
    assert fb.error and fb.error_id is error_id
    assert axis.set_position == 2500.0


def test_closed_track_modulo_target_outside_its_period_is_an_error():
    _, _, (axis,) = ring(500.0)
    activate(axis, 22)
    fb = MC_MoveAbsoluteCA(axis)
    fb(execute=True, velocity=500.0, position=3000.5, direction=ModuloDirection.POSITIVE)
    assert fb.error and fb.error_id is ErrorId.INVALID_TARGET_POSITION


def test_tracks_on_an_open_rail():
    rt, group, (axis,) = ring(1500.0, ring_rail=False)
    assert activate(axis, 21).done
    assert read(axis).track_position == 1500.0
    assert move(rt, axis, position=1900.0).done
    assert axis.set_position == pytest.approx(1900.0, abs=1e-9)
