"""Fault injection for testing executors: a point hook that leaves a marker file for every
run of a point and can make the worker process die the first time a given point runs.

Marker files, not counters in memory, because the runs happen in other processes (pool
workers, Ray workers) that may die.
"""

from __future__ import annotations

import os
import uuid
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from openmotion.sweep.points import Point

EXIT_CODE = 77  #: the exit code of a worker the hook kills
RUN_SUFFIX = ".run"


@dataclass(frozen=True)
class FaultHook:
    """``on_point`` hook: marks each run in ``folder``; the first run of point ``exit_at``
    (an index) ends its process at once, before the point runs."""

    folder: Path
    exit_at: int | None = None

    def __call__(self, point: Point) -> None:
        (self.folder / f"{point.point_id}.{uuid.uuid4().hex}{RUN_SUFFIX}").touch()
        if point.index == self.exit_at and self._first_exit():
            os._exit(EXIT_CODE)

    def _first_exit(self) -> bool:
        try:
            os.close(os.open(self.folder / "exited", os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            return False
        return True


def runs(folder: str | Path) -> Counter[str]:
    """How often each point (by id) started running, from a ``FaultHook``'s markers."""
    return Counter(path.name.split(".", 1)[0] for path in Path(folder).glob(f"*{RUN_SUFFIX}"))
