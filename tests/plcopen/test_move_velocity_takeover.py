"""How MC_MoveVelocity ends: never silently (issue 19 point 5).

A velocity command never completes by itself (TcMC §3.3). When a command buffered behind it
takes over at InVelocity (PLCopen Part 1 buffer modes, D-008), it was replaced by another
travel command: CommandAborted (TcMC §3.1's meaning, digest §1.3; D-178). When MC_NewPos
turned it into a positioning, it ends Done at the new target (D-015). In every case Busy
falls together with exactly one of Done, CommandAborted and Error (§1.3).
"""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.plcopen import MC_MoveAbsolute, MC_MoveVelocity, MC_NewPos

B = om.BufferMode


def powered_axis() -> tuple[om.Runtime, om.Axis]:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    assert axis.power()
    return rt, axis


@pytest.mark.parametrize("mode", [B.BUFFERED, B.BLENDING_LOW, B.BLENDING_PREVIOUS,
                                  B.BLENDING_NEXT, B.BLENDING_HIGH], ids=lambda m: m.name)
def test_buffered_take_over_shows_command_aborted_while_execute_stays(mode: B) -> None:
    """Issue 19 point 5, D-178: Busy and Active fell with no Done, CommandAborted or Error;
    now CommandAborted rises with the take-over and stays while Execute stays TRUE."""
    rt, axis = powered_axis()
    velocity, buffered = MC_MoveVelocity(axis), MC_MoveAbsolute(axis)
    velocity(execute=True, velocity=100.0)
    buffered(execute=True, position=500.0, velocity=200.0, buffer_mode=mode)
    while velocity.busy:
        rt.step()
        velocity(execute=True)
        buffered(execute=True)
        assert velocity.busy or velocity.command_aborted  # never a silent end
    assert buffered.active and axis.set_velocity == pytest.approx(100.0, rel=1e-3)
    assert (velocity.done, velocity.command_aborted, velocity.error) == (False, True, False)
    assert not velocity.active and not velocity.in_velocity
    assert "buffered" in velocity.message
    for _ in range(3):
        rt.step()
        velocity(execute=True)
        assert velocity.command_aborted
    while not buffered.done:
        rt.step()
        buffered(execute=True)
    assert axis.set_position == 500.0


def test_take_over_after_a_short_execute_pulses_command_aborted() -> None:
    """D-178 with §1.3's persistence rule: Execute already FALSE, CommandAborted shows for
    exactly one call; a new edge then starts a new velocity command."""
    rt, axis = powered_axis()
    velocity, buffered = MC_MoveVelocity(axis), MC_MoveAbsolute(axis)
    velocity(execute=True, velocity=100.0)
    velocity(execute=False)
    buffered(execute=True, position=500.0, velocity=200.0, buffer_mode=B.BUFFERED)
    pulses = 0
    for _ in range(200):
        rt.step()
        velocity(execute=False)
        buffered(execute=True)
        pulses += velocity.command_aborted
    assert pulses == 1 and not velocity.busy
    velocity(execute=True, velocity=50.0)
    assert velocity.busy and velocity.active


def test_python_command_of_a_taken_over_move_velocity_is_aborted() -> None:
    """D-178 in the Python layer: the handle says aborted, with the reason."""
    rt, axis = powered_axis()
    cruise = axis.move_velocity(100.0)
    follow = axis.move_relative(20.0, velocity=100.0, buffer_mode=B.BUFFERED)
    rt.run_until(follow, timeout=5.0)
    assert cruise.aborted and not cruise.done and follow.done
    assert cruise.message == "taken over by the buffered move_relative"


def test_move_velocity_turned_into_a_positioning_shows_done() -> None:
    """D-015: MC_NewPos on a velocity move makes it a positioning; its block reports Done
    at the new target (the block forced Done FALSE and ended silently)."""
    rt, axis = powered_axis()
    velocity, new_pos = MC_MoveVelocity(axis), MC_NewPos(axis)
    velocity(execute=True, velocity=100.0)
    rt.run(0.2)
    velocity(execute=True)
    new_pos(execute=True, new_pos=60.0)
    assert new_pos.done
    while velocity.busy:
        rt.step()
        velocity(execute=True)
    assert (velocity.done, velocity.command_aborted, velocity.error) == (True, False, False)
    assert axis.set_position == 60.0
