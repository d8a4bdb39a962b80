"""The axes' events (a profile that ends, the next of them) from the kernel's bound compiled
passes (axis/kernel.py, D-276, D-323): right for every row, also after the kernel arrays grew
past their first capacity while the runtime ran, and the same in bulk as stepped."""

from __future__ import annotations

import openmotion as om

LIMITS = {"max_velocity": 500.0, "max_acceleration": 5000.0, "max_deceleration": 5000.0,
          "max_jerk": 50000.0}
FIRST = 10  #: axes made before the first run
LATER = 30  #: axes made after it: the kernel grows past its first capacity (16) twice
CYCLES = 1500


def machine(stepped: bool) -> tuple[om.Runtime, list[om.Command], list[om.Axis]]:
    """FIRST axes move, the runtime runs, then LATER axes join and every axis moves again;
    each move has its own length, so the profiles end in different cycles."""
    rt = om.Runtime(cycle_time=0.001)
    axes = [rt.add_axis(f"a{i}", **LIMITS) for i in range(FIRST)]
    commands: list[om.Command] = []

    def advance(cycles: int) -> None:
        if stepped:
            for _ in range(cycles):
                rt.step()
        else:
            rt.run(cycles * rt.cycle_time)

    for index, axis in enumerate(axes):
        axis.power()
        commands.append(axis.move_absolute(10.0 + 7.0 * index, 300.0, 3000.0, 2000.0, 30000.0))
    advance(200)
    for index in range(FIRST, FIRST + LATER):
        axis = rt.add_axis(f"a{index}", **LIMITS)
        axis.power()
        axes.append(axis)
    for index, axis in enumerate(axes):
        commands.append(axis.move_absolute(-5.0 - 3.0 * index, 250.0, 2500.0, 4000.0, 40000.0))
    advance(CYCLES - 200)
    return rt, commands, axes


def test_every_row_ends_its_profile_and_is_done_after_the_kernel_grew():
    rt, commands, axes = machine(stepped=False)
    assert rt.axis_system.kernel.size == FIRST + LATER
    assert all(c.aborted for c in commands[:FIRST] if not c.done)
    assert all(c.done for c in commands[FIRST:])
    assert [axis.set_position for axis in axes] == [-5.0 - 3.0 * i for i in range(len(axes))]
    assert rt.axis_system.kernel.ended(rt.now).size == 0  # every event was handled
    again = axes[-1].move_absolute(0.0, 250.0, 2500.0, 4000.0, 40000.0)  # still usable
    rt.run(1.0)
    assert again.done and axes[-1].set_position == 0.0


def test_bulk_gives_the_stepped_events_and_setpoints_bit_for_bit_after_growth():
    bulk, bulk_commands, _ = machine(stepped=False)
    stepped, stepped_commands, _ = machine(stepped=True)
    assert [(c.status, c.ended_at) for c in bulk_commands] == \
        [(c.status, c.ended_at) for c in stepped_commands]
    n = stepped.axis_system.kernel.size
    assert bulk.axis_system.kernel.fields[:, :n].tobytes() == \
        stepped.axis_system.kernel.fields[:, :n].tobytes()
