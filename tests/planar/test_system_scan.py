"""A planar system with many movers finds the movers due and the objects awake with numpy
(D-286): the same calls in the same order as visiting every one, so the same motion."""

from __future__ import annotations

import numpy as np
import pytest

from openmotion.bench import planar
from openmotion.planar import PositionXYC
from openmotion.planar import system as planar_system

MOVERS = 70  #: above the system's scan threshold


def _run(cycles: int) -> list[tuple]:
    """Every mover sent to a jittered neighbouring stator in turn; per cycle the published
    poses and the phases of the commands."""
    fleet = planar.build(MOVERS, seed=3)
    rng = np.random.default_rng(4)
    commands: list = [None] * MOVERS
    seen = []
    for cycle in range(cycles):
        for i, mover in enumerate(fleet.movers):
            if (commands[i] is None or not commands[i].busy) and (cycle + i) % 40 == 0:
                x, y = planar._centre(fleet.cells[i], fleet.side)
                dx, dy = rng.uniform(-240.0, 240.0, 2)
                commands[i] = mover.move_to_position(PositionXYC(x + dx, y + dy))
        fleet.runtime.step()
        seen.append((tuple((m.position.x, m.position.y) for m in fleet.movers),
                     tuple(None if c is None else c.phase for c in commands)))
    assert any(c is not None and c.done for c in commands)
    assert any(c is not None and c.error for c in commands)  # some meet another mover
    return seen


def test_the_numpy_scan_moves_the_movers_as_the_plain_loops(monkeypatch: pytest.MonkeyPatch
                                                            ) -> None:
    assert MOVERS >= planar_system._SCAN_BELOW
    scanned = _run(400)
    monkeypatch.setattr(planar_system, "_SCAN_BELOW", 10**9)
    assert _run(400) == scanned


def test_flags_follow_the_objects() -> None:
    fleet = planar.build(MOVERS, seed=5)
    system = planar_system.PlanarSystem.of(fleet.runtime)
    objects = system.objects()
    assert system.awake_flags[:len(objects)].tolist() == [o.awake for o in objects]
    assert system.next_events[:MOVERS].tolist() == [m.next_event for m in fleet.movers]
    move = fleet.movers[0].move_to_position(PositionXYC(*planar._centre(fleet.cells[0],
                                                                        fleet.side)))
    fleet.runtime.step()
    assert move.busy or move.done
    assert system.next_events[:MOVERS].tolist() == [m.next_event for m in fleet.movers]
    assert system.awake_flags[:len(objects)].tolist() == [o.awake for o in objects]
