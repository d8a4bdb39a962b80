"""One command handle (D-238): a planar command is the kernel's ``Command`` with what a TF5430
feedback shows besides, and the planar objects cooperate through public members (D-239)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from openmotion.core.errors import ErrorId
from openmotion.kernel.command import Command, CommandStatus
from openmotion.planar import MC_PlanarFeedback, MC_PlanarMover, PositionXYC
from openmotion.planar.feedback import CommandPhase, PlanarCommand
from openmotion.runtime.runtime import Runtime
from openmotion.scenario.planar_machine import follow

ROOT = Path(__file__).resolve().parents[2]


def test_a_planar_command_is_a_command_timed_by_the_runtime():
    rt = Runtime()
    mover = MC_PlanarMover(rt)
    rt.step()
    enable = mover.enable(MC_PlanarFeedback())
    assert isinstance(enable, Command)
    assert (enable.status, enable.phase, enable.issued_at) == (
        CommandStatus.BUFFERED, CommandPhase.SENT, rt.now)
    ended = rt.run_until(enable, timeout=1.0)  # run_until takes any Command
    assert enable.done and enable.ended_at == ended
    move = mover.move_to_position(PositionXYC(x=300.0, y=240.0))
    rt.step()
    assert move.active and move.phase is CommandPhase.ACTIVE
    rt.run_until(move, timeout=5.0)
    assert move.done and move.ended_at == rt.now and move.error_id is ErrorId.NO_ERROR


def test_a_refused_planar_command_ends_once_with_its_time_and_reason():
    rt = Runtime()
    mover = MC_PlanarMover(rt)
    rt.step()
    refused = mover.move_to_position(PositionXYC(x=300.0, y=240.0))  # still Disabled
    rt.step()
    assert refused.error and refused.ended_at == rt.now and refused.message
    refused.finish()  # a later report changes nothing: the first end wins
    assert refused.error and refused.phase is CommandPhase.ERROR
    rt.run_until(mover.enable(), timeout=1.0)  # the mover stays usable
    move = mover.move_to_position(PositionXYC(x=300.0, y=240.0))
    rt.run_until(move, timeout=5.0)
    assert move.done


def test_a_scenario_row_follows_a_planar_command_as_any_command():
    planar = PlanarCommand("MoveToPosition")
    row = Command("move_to_position", 0.0)
    follow(row, planar, 0.1)
    assert row.status is CommandStatus.BUFFERED
    planar.start()
    follow(row, planar, 0.2)
    assert row.active
    planar.reject(ErrorId.PLANAR_COLLISION, "reserved")
    follow(row, planar, 0.3, "rejected (33158): reserved")
    assert (row.status, row.error_id, row.message, row.ended_at) == (
        CommandStatus.ERROR, ErrorId.PLANAR_COLLISION, "rejected (33158): reserved", 0.3)


@pytest.mark.skipif(shutil.which("ruff") is None, reason="ruff is in the [test] extra")
def test_planar_objects_reach_no_private_member_of_another():
    result = subprocess.run(["ruff", "check", "--select", "SLF001", "src/openmotion/planar"],
                            cwd=ROOT, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stdout
