"""The contract a motion system signs to join the cyclic runtime (docs/architecture.md).

A system owns objects (axes, an axes group, a CA group, the planar objects) and has two
duties per cycle: ``advance(now)`` in the motion phase (plan on events, evaluate the
setpoints, correct them) and, optionally, ``monitor(now)`` in the drive phase (actual
values, following error, Done windows). ``objects()`` lists its public objects in creation
order; the machine model describes them.

Ordering, the one rule for determinism: in every phase the runtime calls the systems in the
order they were added. The axes come first (the runtime adds them when it is made), so a CA
group or an axes group corrects setpoints the axis profiles have just produced, and the
planar system, added with its first object, runs after the systems made before it.

Quiet stretches (optional, D-275): a system may also offer ``quiet_until()`` and
``advance_quietly(now, cycles, times)``. ``quiet_until`` is the first instant whose cycle it
must run phase by phase (an event due; -inf for the very next cycle, +inf for none ahead);
``advance_quietly`` runs both its phases of the ``cycles`` cycles up to the one at ``now``,
all before that instant, at once, leaving the state the cycles would have left, bit for bit.
``times`` (None unless an observer wants them) are the cycles' times; it returns its samples of them
for the observers' ``observe_block``. A system offering them promises that in such a stretch
it needs nothing another system does in it. A system without them makes every cycle a step,
so systems written before keep working unchanged.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol, runtime_checkable


@runtime_checkable
class System(Protocol):
    """What ``CyclicRuntime.add_system`` accepts. ``monitor`` is optional."""

    name: str  #: stable within a runtime: it never depends on how many systems exist

    def advance(self, now: float) -> None:
        """The motion phase of cycle ``now``."""

    def objects(self) -> Sequence[object]:
        """The system's public objects, in creation order."""
