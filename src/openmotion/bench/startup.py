"""``openmotion bench startup``: what a new user waits for, measured as whole processes.

Each figure is the wall time of a fresh ``python`` process, as a user starts it:

- floors (the peers of this benchmark): ``python -c pass`` and a process that imports
  numpy and numba, the least any numba-based simulator pays;
- warm: ``import openmotion``, ``from openmotion import Runtime``, ``openmotion check`` and
  ``openmotion run`` of the default example, and ``openmotion check`` of a generated 1 MB
  scenario (``large_scenario``), after a priming run has written the bytecode
  and the compiled kernels (so a warm start reads caches only);
- first run: every shipped example once (quick: the default one) with the kernel cache the
  package has, as a user meets it after installing (the build compiles the examples'
  loops into the package, D-158);
- cold: ``openmotion run`` with a fresh, empty kernel cache (``NUMBA_CACHE_DIR`` pointing at
  an empty directory), so every kernel the run uses is compiled first: the default example,
  and in the full run every shipped example once (what a machine pays that cannot use the
  package's cache).

Minimum, median and maximum over the repeats; the goals judge medians and the slowest first
run. Ratios to the floors show what is openmotion's own.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from openmotion.examples import DEFAULT_EXAMPLE, list_examples

Progress = Callable[[str], None] | None
KERNEL_CACHE_VARIABLE = "NUMBA_CACHE_DIR"  #: where numba keeps compiled kernels
BYTECODE_VARIABLE = "PYTHONDONTWRITEBYTECODE"
PROCESS_TIMEOUT = 600.0  #: [s] one process; a cold run of the largest example takes ~20 s
LARGE_SCENARIO_BYTES = 1_000_000  #: the size of the generated scenario `check` reads


def large_scenario(target_bytes: int, axes: int = 100) -> str:
    """A valid scenario of about ``target_bytes``: many axes and a long chained timeline (the
    size a generated production scenario reaches; issue 18 asks 1 MB to load in <= 2 s)."""
    lines = ["name: big legit", "axes:"]
    for a in range(axes):
        lines += [f"  - name: a{a}", "    parameters: {max_velocity: 500.0, jerk: 20000.0}",
                  "    drive: {model: lag, time_constant: 0.004, dead_time: 0.002}"]
    lines += ["timeline:"] + [f"  - {{id: p{a}, at: 0.0, axis: a{a}, command: power}}"
                              for a in range(axes)]
    size, n = sum(len(line) + 1 for line in lines), 0
    while size < target_bytes:
        after = f"p{n}" if n < axes else f"m{n - axes}"
        entry = [f"  - id: m{n}", f"    when: {after}.done", f"    axis: a{n % axes}",
                 "    command: move_absolute", f"    position: {(n % 7) * 10.0}",
                 "    velocity: 250.0"]
        lines += entry
        size += sum(len(line) + 1 for line in entry)
        n += 1
    return "\n".join(lines + ["checks:", "  - {command: m0, result: done}"]) + "\n"


def _command(*arguments: str) -> list[str]:
    return [sys.executable, *arguments]


def _openmotion(*arguments: str) -> list[str]:
    return _command("-m", "openmotion", *arguments)


def _environment(kernel_cache: str | None = None, write_bytecode: bool = False) -> dict[str, str]:
    env = dict(os.environ)
    if kernel_cache is not None:
        env[KERNEL_CACHE_VARIABLE] = kernel_cache
    if write_bytecode:
        env.pop(BYTECODE_VARIABLE, None)
    return env


def time_process(command: Sequence[str], env: dict[str, str], cwd: str) -> float:
    """Wall seconds of one process; a failing process is an error, not a figure."""
    start = time.perf_counter()
    done = subprocess.run(command, env=env, cwd=cwd, capture_output=True, text=True,
                          timeout=PROCESS_TIMEOUT, check=False)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command[1:])} exited with {done.returncode}: "
                           f"{done.stderr.strip()[-400:]}")
    return seconds


def _stats(samples: list[float]) -> dict[str, Any]:
    return {"min_s": min(samples), "median_s": statistics.median(samples),
            "max_s": max(samples), "runs": len(samples)}


def run_startup(repeats: int = 5, cold_repeats: int = 3, every_example: bool = True,
                progress: Progress = None, cold_examples: bool = True) -> dict[str, Any]:
    """Time the start-up figures of the module docstring; ``cold_examples`` False leaves out
    the empty-cache run of every example (minutes of compiling: ``bench all`` does, D-295)."""
    say = progress or (lambda _text: None)
    examples = {example.name: example.path for example in list_examples()}
    default = examples[DEFAULT_EXAMPLE]
    with tempfile.TemporaryDirectory(prefix="openmotion-startup-") as work:
        trace = str(Path(work) / "trace.csv")
        run = _openmotion("run", str(default), "--trace", trace, "--quiet")
        large = Path(work) / "large.yaml"
        large.write_text(large_scenario(LARGE_SCENARIO_BYTES), encoding="utf-8")
        warm_commands = {
            "import": _command("-c", "import openmotion"),
            "import_runtime": _command("-c", "from openmotion import Runtime"),
            "check": _openmotion("check", str(default)),
            "check_1mb": _openmotion("check", str(large)),
            "run": run,
        }
        floors = {
            "python": _command("-c", "pass"),
            "numpy_numba": _command("-c", "import numpy, numba"),
        }
        say("startup: priming the bytecode and kernel caches")
        time_process(run, _environment(write_bytecode=True), work)
        rounds: dict[str, list[float]] = {name: [] for name in [*floors, *warm_commands]}
        for round_ in range(repeats):  # interleaved, so drift hits every figure alike
            say(f"startup: warm round {round_ + 1}/{repeats}")
            for name, command in [*floors.items(), *warm_commands.items()]:
                rounds[name].append(time_process(command, _environment(), work))
        cold_default = []
        for round_ in range(cold_repeats):
            say(f"startup: cold run {round_ + 1}/{cold_repeats} ({DEFAULT_EXAMPLE})")
            with tempfile.TemporaryDirectory(dir=work) as cache:
                cold_default.append(time_process(run, _environment(cache), work))
        first: dict[str, float] = {}
        for name, path in examples.items() if every_example else [(DEFAULT_EXAMPLE, default)]:
            say(f"startup: first run of {name}")
            first[name] = time_process(
                _openmotion("run", str(path), "--trace", trace, "--quiet"), _environment(), work)
        cold: dict[str, float] = {}
        for name, path in examples.items() if every_example and cold_examples else ():
            say(f"startup: cold first run of {name}")
            with tempfile.TemporaryDirectory(dir=work) as cache:
                cold[name] = time_process(
                    _openmotion("run", str(path), "--trace", trace, "--quiet"),
                    _environment(cache), work)
    warm = {name: _stats(rounds[name]) for name in warm_commands}
    floor = {name: _stats(rounds[name]) for name in floors}
    python = floor["python"]["median_s"]
    return {
        "scenario": DEFAULT_EXAMPLE,
        "repeats": repeats,
        "floors": floor,
        "warm": warm,
        "over_python": {name: row["median_s"] / python for name, row in warm.items()},
        "first": first,
        "cold": {"run": _stats(cold_default), "examples": cold},
    }
