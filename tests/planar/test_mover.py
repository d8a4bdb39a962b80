"""MC_PlanarMover on the runtime: status one cycle after the call, group admission in call
order, the environment boundary, C rotation modes (TF5430 §4.2, §6.3, §6.7)."""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest

import openmotion as om
from openmotion.core.errors import ErrorId
from openmotion.planar import (
    MC_PlanarEnvironment,
    MC_PlanarFeedback,
    MC_PlanarGroup,
    MC_PlanarMover,
    MoverCommandMode,
    MoverVector,
    PlanarMoverParameters,
    PlanarObjectType,
    PlanarState,
    PositionXYC,
)
from openmotion.planar import mover as mover_module
from openmotion.planar.motion import sample_path
from openmotion.planar.reservation import swept_area


def field(columns: int = 4, rows: int = 4, *starts: tuple[float, float]):
    """A runtime with an enabled group holding the environment and enabled movers."""
    rt = om.Runtime()
    environment = MC_PlanarEnvironment(rt)
    for i in range(columns):
        for j in range(rows):
            environment.add_stator(240.0 * i, 240.0 * j)
    environment.create_boundary()
    group = MC_PlanarGroup(rt)
    group.enable()
    movers = [MC_PlanarMover(rt, PlanarMoverParameters(initial_position=MoverVector(x, y)))
              for x, y in starts]
    for mover in movers:
        mover.enable()
    rt.run(0.002)
    for mover in movers:
        mover.add_to_group(group)
    environment.add_to_group(group)
    rt.step()
    return rt, environment, group, movers


def test_status_shows_one_cycle_after_the_call():
    rt = om.Runtime()
    mover = MC_PlanarMover(rt)
    feedback = MC_PlanarFeedback()
    mover.enable(feedback)
    assert feedback.busy and not feedback.done and mover.state is PlanarState.DISABLED
    rt.step()
    assert mover.state is PlanarState.ENABLING and feedback.busy
    rt.step()
    assert mover.state is PlanarState.ENABLED and feedback.done
    assert mover.command_mode is MoverCommandMode.FREE_MOVEMENT


def test_two_movers_to_one_target_the_first_caller_wins():
    rt, _, _, (first, second) = field(4, 4, (120.0, 120.0), (600.0, 120.0))
    a, b = MC_PlanarFeedback(), MC_PlanarFeedback()
    first.move_to_position(PositionXYC(600.0, 600.0), feedback=a)
    second.move_to_position(PositionXYC(600.0, 600.0), feedback=b)
    rt.step()
    assert a.active and not a.error
    assert b.error and b.error_id == ErrorId.PLANAR_COLLISION == 33158
    assert b.object_info.object_type is PlanarObjectType.MOVER
    assert b.object_info.id == first.oid
    rt.run_until(lambda: a.done, timeout=5.0)
    assert first.position.x == pytest.approx(600.0, abs=1e-9)
    assert first.position.y == pytest.approx(600.0, abs=1e-9)


def test_each_rejection_by_the_same_blocker_names_it_and_the_mover_goes_on():
    """A collision's message names the motion and the blocker, the same for every refusal
    by that blocker (its object info and message tail are made once, D-328); the refused
    mover's next free move runs."""
    rt, _, _, (first, second) = field(4, 4, (120.0, 120.0), (600.0, 120.0))
    refused = []
    for x in (200.0, 250.0):
        refused.append(second.move_to_position(PositionXYC(x, 120.0)))
        rt.step()
    for command in refused:
        assert command.error and command.error_id == ErrorId.PLANAR_COLLISION
        assert command.message == f"the move meets the area of mover 16#{first.oid:08X} (§6.3)"
        assert command.object_info.object_type is PlanarObjectType.MOVER
        assert command.object_info.id == first.oid
    free = second.move_to_position(PositionXYC(600.0, 600.0))
    rt.run_until(free, timeout=5.0)
    assert free.done and second.position.y == pytest.approx(600.0, abs=1e-9)


def test_a_move_off_the_surface_is_blocked_by_the_environment():
    rt, environment, _, (mover,) = field(2, 2, (120.0, 120.0))
    feedback = MC_PlanarFeedback()
    mover.move_to_position(PositionXYC(600.0, 120.0), feedback=feedback)
    rt.step()
    assert feedback.error and feedback.error_id == ErrorId.PLANAR_COLLISION
    assert feedback.object_info.object_type is PlanarObjectType.ENVIRONMENT
    assert feedback.object_info.id == environment.oid == 0x05120010


def test_move_c_out_of_the_windows_locks_x_and_y():
    rt, _, _, (mover,) = field(4, 4, (360.0, 360.0))
    turn = mover.move_c(20.0)
    rt.run_until(lambda: turn.done, timeout=5.0)
    rt.step()
    assert mover.command_mode is MoverCommandMode.C_ROTATION_FREE_MOVEMENT
    move = mover.move_to_position(PositionXYC(600.0, 600.0))
    rt.step()
    assert move.error and move.error_id == ErrorId.PLANAR_WRONG_MODE
    back = mover.move_c(90.0)
    rt.run_until(lambda: back.done, timeout=5.0)
    rt.step()
    assert mover.command_mode is MoverCommandMode.FREE_MOVEMENT


def test_a_moves_area_is_the_swept_area_of_its_sampled_path():
    """Equivalence: the area a mover asks for is ``swept_area`` of its sampled future path,
    piece for piece, with the same samples, whether it was built from the run ends of a
    straight move (``PlanarMotion.s``), by the planner's own compiled pass (a turning move
    from rest, ``PlanarMotion.swept``) or from the samples (a move started while moving)."""
    rt, _, _, movers = field(6, 6, (120.0, 120.0), (840.0, 360.0), (360.0, 1080.0))
    original, original_begin = MC_PlanarMover._future_area, MC_PlanarMover._begin
    original_pieces = mover_module.straight_run_pieces
    seen = {"straight": 0, "other": 0, "planner": 0}
    begun = {}

    def check(samples, area, kind):  # noqa: ANN001, ANN202
        mover, profiles, start = begun["call"]
        step = mover.system.cycle_time * 10
        expected_samples, path = sample_path(mover._future_plans(profiles, start), start, step)
        expected = swept_area(path)
        assert np.array_equal(samples, expected_samples)
        assert np.array_equal(area.until, expected.until)
        assert np.array_equal(area.bounds, expected.bounds)
        assert all(a.equals_exact(b, 0.0)
                   for a, b in zip(area.pieces, expected.pieces, strict=True))
        seen[kind] += 1

    def begin_spy(mover, command, profiles, what, **options):  # noqa: ANN001, ANN003, ANN202
        begun["call"] = (mover, profiles, mover.system.previous)
        return original_begin(mover, command, profiles, what, **options)

    def spy(mover, profiles, start, straight):  # noqa: ANN001, ANN202
        samples, area = original(mover, profiles, start, straight)
        check(samples, area, "straight" if straight is not None else "other")
        return samples, area

    def pieces_spy(numbers, hx, hy):  # noqa: ANN001, ANN202
        found = original_pieces(numbers, hx, hy)
        if found is not None:
            check(*found, "planner")
        return found

    rng = np.random.default_rng(4)
    with mock.patch.object(MC_PlanarMover, "_future_area", spy), \
            mock.patch.object(MC_PlanarMover, "_begin", begin_spy), \
            mock.patch.object(mover_module, "straight_run_pieces", pieces_spy):
        for _ in range(40):
            mover = movers[int(rng.integers(len(movers)))]
            x, y = rng.uniform(100.0, 1340.0, 2)
            c = rng.choice([0.0, rng.uniform(-14.0, 14.0)])
            mover.move_to_position(PositionXYC(float(x), float(y), float(c)))
            rt.run(float(rng.choice([0.001, 0.05, 0.3])))
    assert seen["planner"] > 5 and seen["straight"] + seen["planner"] > 10 and seen["other"] > 0
