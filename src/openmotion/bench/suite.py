"""``openmotion bench all``: every benchmark in one run, written to one JSON file.

Each benchmark runs in a process of its own (``python -m openmotion.bench.suite NAME``), so
that one cannot slow the next with what it leaves behind (threads of a server, a Ray
cluster, a grown heap) and a crash is one benchmark's error, not the run's (D-295). The file
holds the machine, the date, the commit and, per benchmark, its result dict and verdicts
as ``openmotion bench NAME --json`` prints them, or the error that stopped it.
docs/benchmarks.md's figures are rendered from that file (``bench.report``).
"""

from __future__ import annotations

import argparse
import datetime
import importlib.metadata
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
import traceback
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from openmotion.bench import BENCHMARK_NAMES

FORMAT = 1  #: version of the file's layout; a reader refuses files of another one
#: the distributions whose versions go into the file: ours, the numerics, the peers measured
#: against, and the extras that some benchmarks need
VERSIONS = ("openmotion", "numpy", "numba", "ruckig", "pyplcopen", "shapely", "pydantic",
            "asyncua", "pyads", "ray", "pandas", "pyarrow")
ERROR_LINES = 12  #: lines of a child's stderr kept when it dies without a result

#: one benchmark run: (name, quick, progress) -> run_benchmark's dict without its machine
RunOne = Callable[[str, bool, Callable[[str], None]], dict[str, Any]]


class BenchmarkError(RuntimeError):
    """A benchmark's process reported an error or died; the message says which and why."""


def _version(distribution: str) -> str | None:
    try:
        return importlib.metadata.version(distribution)
    except importlib.metadata.PackageNotFoundError:
        return None


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def machine() -> dict[str, Any]:
    """What the run was measured on: the cpu, the OS, the load and every version that moves a
    figure (the peers' included)."""
    try:
        load: list[float] | None = [round(x, 2) for x in os.getloadavg()]
    except OSError:  # not on this platform
        load = None
    return {
        "cpu": _cpu_model(),
        "cpu_count": os.cpu_count(),
        "os": platform.platform(),
        "python": platform.python_version(),
        "load_average": load,
        "versions": {name: _version(name) for name in VERSIONS},
    }


def git_commit(where: Path | None = None) -> dict[str, Any] | None:
    """The commit of the checkout openmotion runs from and whether tracked files differ from
    it; None for an installed package (no git, or not a checkout)."""
    where = where or Path(__file__).resolve().parent
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=where, capture_output=True,  # noqa: S607
                                text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],  # noqa: S607
                               cwd=where, capture_output=True, text=True, timeout=10,
                               check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return {"commit": commit, "dirty": bool(dirty)}


def select(only: Iterable[str] | None = None, skip: Iterable[str] = ()) -> list[str]:
    """The benchmarks of a run in BENCHMARK_NAMES' order; ValueError names an unknown one."""
    only, skip = list(only or ()), list(skip)
    unknown = [name for name in (*only, *skip) if name not in BENCHMARK_NAMES]
    if unknown:
        raise ValueError(f"unknown benchmark {unknown[0]!r}; choose from: "
                         f"{', '.join(BENCHMARK_NAMES)}")
    return [name for name in BENCHMARK_NAMES if (not only or name in only) and name not in skip]


def child_command(name: str, quick: bool, out: Path) -> list[str]:
    """How one benchmark is started in a process of its own."""
    return [sys.executable, "-m", "openmotion.bench.suite", name, "--out", str(out),
            *(["--quick"] if quick else [])]


def run_in_process(name: str, quick: bool, progress: Callable[[str], None],
                   command: list[str] | None = None) -> dict[str, Any]:
    """Run one benchmark in a child process; its progress lines are passed to ``progress``.
    Raises BenchmarkError with the child's error (or the tail of its stderr if it died)."""
    with tempfile.TemporaryDirectory(prefix="openmotion-bench-") as folder:
        out = Path(folder) / "result.json"
        command = command or child_command(name, quick, out)
        tail: list[str] = []
        with subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,  # noqa: S603
                              text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"}) as child:
            assert child.stderr is not None
            for line in child.stderr:
                line = line.rstrip()
                if line:
                    tail = [*tail[1 - ERROR_LINES:], line]
                    progress(line)
        if out.exists():
            answer = json.loads(out.read_text())
            if "error" in answer:
                raise BenchmarkError(answer["error"])
            return answer
    detail = "\n".join(tail) or "no output"
    raise BenchmarkError(f"the benchmark's process ended with code {child.returncode} and no "
                       f"result:\n{detail}")


def _children_cpu() -> float | None:
    """CPU seconds of the processes this one has waited for (None where the OS does not
    say): a benchmark's own, next to its wall seconds, shows how much a load on the machine
    stretched the run."""
    try:
        import resource
    except ImportError:
        return None
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    return used.ru_utime + used.ru_stime


def _load() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except OSError:
        return None


def run_suite(names: list[str], quick: bool = False, echo: Callable[[str], None] | None = None,
              run_one: RunOne = run_in_process, command: str = "openmotion bench all"
              ) -> dict[str, Any]:
    """Run ``names`` one after another; a benchmark that raises is recorded with its error
    and the others still run. ``passed``: every benchmark ran and met all its goals."""
    say = echo or (lambda _text: None)
    started = time.monotonic()
    run: dict[str, Any] = {
        "format": FORMAT,
        "command": command,
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "git": git_commit(),
        "quick": quick,
        "machine": machine(),
        "benchmarks": {},
    }
    for number, name in enumerate(names, 1):
        begun = time.monotonic()

        def progress(text: str, name: str = name, begun: float = begun) -> None:
            say(f"  {name} {time.monotonic() - begun:6.1f} s  {text}")

        say(f"[{number}/{len(names)}] {name} (run {time.monotonic() - started:.0f} s so far)")
        entry: dict[str, Any]
        used, load = _children_cpu(), _load()
        try:
            result = run_one(name, quick, progress)
            entry = {"status": "passed" if result["passed"] else "failed", "error": None,
                     "options": result.get("options", {}), "goals": result["goals"],
                     "results": result["results"]}
        except Exception as exc:  # recorded; the next benchmark still runs
            error = str(exc) if isinstance(exc, BenchmarkError) else f"{type(exc).__name__}: {exc}"
            entry = {"status": "error", "error": error, "goals": {}, "results": None}
        entry["seconds"] = round(time.monotonic() - begun, 1)
        now = _children_cpu()
        entry["cpu_seconds"] = None if now is None or used is None else round(now - used, 1)
        entry["load_average"] = load
        run["benchmarks"][name] = entry
        say(f"[{number}/{len(names)}] {name}: {entry['status']} in {entry['seconds']:.1f} s"
            + (f"  ({entry['error'].splitlines()[0]})" if entry["error"] else ""))
    run["seconds"] = round(time.monotonic() - started, 1)
    run["passed"] = bool(names) and all(b["status"] == "passed"
                                        for b in run["benchmarks"].values())
    return run


def summary(run: dict[str, Any]) -> str:
    """Plain-text table of a run: one line per benchmark (docs/benchmarks.md has the figures)."""
    m = run["machine"]
    lines = [f"openmotion bench all{' (quick)' if run['quick'] else ''}: {run['date']}, "
             f"{run['seconds']:.0f} s",
             f"machine: {m['cpu']}, {m['cpu_count']} cpu, {m['os']}, python {m['python']}",
             ""]
    width = max((len(name) for name in run["benchmarks"]), default=4)
    for name, entry in run["benchmarks"].items():
        goals = entry["goals"].values()
        met = sum(g["passed"] is True for g in goals)
        detail = (entry["error"].splitlines()[0] if entry["error"]
                  else f"{met}/{len(goals)} goals met")
        lines.append(f"{name.ljust(width)}  {entry['status']:<6}  {entry['seconds']:7.1f} s  "
                     f"{detail}")
        lines += [f"{'':{width}}    FAIL {g['goal']}" for g in goals if g["passed"] is False]
    lines.append(f"passed: {'yes' if run['passed'] else 'no'}")
    return "\n".join(lines)


def _child(argv: list[str] | None = None) -> int:
    """One benchmark in this process: progress on stderr, the result (or the error) as JSON
    in ``--out``."""
    parser = argparse.ArgumentParser(prog="python -m openmotion.bench.suite")
    parser.add_argument("name", choices=BENCHMARK_NAMES)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    try:
        from openmotion.bench.runner import IN_SUITE, run_benchmark

        result = run_benchmark(args.name, quick=args.quick, in_suite=True,
                               progress=lambda text: print(text, file=sys.stderr, flush=True))
        result.pop("machine", None)  # the run's machine is written once, at the top
        result["options"] = IN_SUITE.get(args.name, {})
        answer: dict[str, Any] = result
        code = 0
    except Exception as exc:
        traceback.print_exc(file=sys.stderr)
        answer, code = {"error": f"{type(exc).__name__}: {exc}"}, 1
    args.out.write_text(json.dumps(answer, default=str))
    return code


if __name__ == "__main__":
    sys.exit(_child())
