"""Fill numba's cache of compiled loops ahead of the first run (D-157).

A run compiles each compiled loop it uses the first time it calls it (from a fraction of a
second to about a second per loop); numba keeps the machine code next to the loop's module
(``__pycache__``) and later runs load it in milliseconds. ``python -m openmotion.warm [PATH
...]`` runs each scenario file given (every ``*.yaml`` of a folder; by default the shipped
examples) once, writing nothing, and loads every loop of the planar traffic: that compiles
each loop with the argument types those runs pass. Building the wheel runs it (setup.py), so
an installed package starts with the loops of every shipped example compiled.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Sequence
from pathlib import Path


def scenario_files(paths: Iterable[str | Path]) -> list[Path]:
    """The scenario files named by ``paths``: files as given, folders' ``*.yaml`` sorted."""
    files: list[Path] = []
    for path in map(Path, paths):
        files.extend(sorted(path.glob("*.yaml")) if path.is_dir() else [path])
    return files


def warm(paths: Iterable[str | Path]) -> list[tuple[Path, float, str | None]]:
    """Run every scenario of ``paths`` once and load the traffic's loops: per scenario its
    file, the seconds it took and the error that stopped it (None: it ran)."""
    from openmotion.planar.traffic_kernels import warm as warm_traffic
    from openmotion.scenario import run_scenario

    report: list[tuple[Path, float, str | None]] = []
    for file in scenario_files(paths):
        start = time.perf_counter()
        try:
            run_scenario(file)
            error = None
        except Exception as exc:  # noqa: BLE001 - a scenario that fails warms what it reached
            error = f"{type(exc).__name__}: {exc}"
        report.append((file, time.perf_counter() - start, error))
    warm_traffic()
    return report


def _shipped_examples() -> Path:
    from openmotion.scenario import default_scenario

    return default_scenario().parent


def main(argv: Sequence[str] | None = None) -> int:
    """Warm the cache for the scenario files or folders in ``argv`` (default: the shipped
    examples); one line per scenario on stdout. Exit 1 if a scenario failed to run."""
    paths = list(sys.argv[1:] if argv is None else argv) or [_shipped_examples()]
    start = time.perf_counter()
    report = warm(paths)
    for file, seconds, error in report:
        print(f"{file.name}: {seconds:.1f} s" + (f" ({error})" if error else ""))
    print(f"compiled loops cached in {time.perf_counter() - start:.1f} s")
    return 1 if any(error for _, _, error in report) else 0


if __name__ == "__main__":
    sys.exit(main())
