"""docs/benchmarks.md's figures, rendered from the JSON file of one ``openmotion bench all``.

The page keeps its hand-written parts (the overview, what each benchmark does) outside
marker comments; between them go tables made here from the file, so that the published
figures are always those of a real run (D-296). A block looks like::

    <!-- generated figures: NAME -->
    ...
    <!-- end of generated figures -->

with NAME ``summary`` (machine, date, versions, one line per benchmark) or a benchmark's
name. Each benchmark's tables come from its own renderer in ``bench.runner``; keys the
renderer does not read (a mode added later) and benchmarks without a renderer get generic
tables, so that new figures appear without a change here.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from openmotion.bench import runner, suite
from openmotion.core.errors import ConfigError

BEGIN = "<!-- generated figures: {name} -->"
END = "<!-- end of generated figures -->"
_BLOCK = re.compile(r"^<!-- generated figures: (\S+) -->\n(.*?)^<!-- end of generated figures -->$",
                    re.DOTALL | re.MULTILINE)
SUMMARY = "summary"
#: what a renderer leaves out on purpose (details behind its figures, or figures it shows in
#: another form): not repeated in the generic tables; ``*`` stands for any one key
UNSHOWN = {
    "axes": ("counts", "by_n.*.axes", "by_n.*.ours", "by_n.*.check", "by_n.*.pyplcopen",
             "by_n.*.ruckig", "by_n.*.ours_all_us", "by_n.*.ours_trace_all_us",
             "by_n.*.pyplcopen_all_us", "by_n.*.ruckig_all_us"),
    "otg": ("failures", "acc_ne_dec", "reversals", "cycle_time"),
    "ca": ("by_n.*.*.movers",),
    "planar": ("by_n.*.movers", "translation.*.movers"),
    "tracks": ("by_n.*.movers",),
    "trace": ("goal",),
}
GENERIC_COLUMNS = 16  #: widest generic table; the rest of the columns go in another table
ERROR_CHARS = 120  #: of an error's first line in the summary (its block has all of it)


class _Tracked(dict):  # type: ignore[type-arg]
    """A results dict that remembers which keys a renderer read (``items``/``values`` read
    them all), so that the keys it did not read can be shown apart."""

    def __init__(self, data: dict[str, Any]) -> None:
        super().__init__(data)
        self.read: set[str] = set()
        self._wrapped: dict[str, Any] = {}

    def _child(self, key: str) -> Any:
        value = dict.__getitem__(self, key)
        if isinstance(value, dict) and not isinstance(value, _Tracked):
            value = self._wrapped.setdefault(key, _Tracked(value))
        return value

    def __getitem__(self, key: str) -> Any:
        self.read.add(key)
        return self._child(key)

    def get(self, key: str, default: Any = None) -> Any:
        self.read.add(key)
        return self._child(key) if key in self else default

    def items(self) -> Iterator[tuple[str, Any]]:  # type: ignore[override]
        self.read.update(self.keys())
        return ((key, self._child(key)) for key in list(self.keys()))

    def values(self) -> Iterator[Any]:  # type: ignore[override]
        self.read.update(self.keys())
        return (self._child(key) for key in list(self.keys()))

    def unread(self, unshown: tuple[str, ...] = (), path: str = "") -> dict[str, Any]:
        """The parts of the data no renderer read and ``unshown`` does not name."""
        out: dict[str, Any] = {}
        for key in self.keys():
            here = f"{path}{key}"
            if any(_matches(pattern, here) for pattern in unshown):
                continue
            if key not in self.read:
                out[key] = dict.__getitem__(self, key)
            elif key in self._wrapped:
                rest = self._wrapped[key].unread(unshown, here + ".")
                if rest:
                    out[key] = rest
        return out


def _matches(pattern: str, path: str) -> bool:
    want, have = pattern.split("."), path.split(".")
    return len(want) == len(have) and all(w in ("*", h) for w, h in zip(want, have, strict=True))


# -- generic tables --------------------------------------------------------------------------


def _scalar(value: Any) -> bool:
    return value is None or isinstance(value, str | int | float | bool) or (
        isinstance(value, list) and all(_scalar(v) and not isinstance(v, list) for v in value))


def _cell(value: Any) -> Any:
    if isinstance(value, list):
        return ", ".join(runner.format_value(v) for v in value)
    return value


def _flat(data: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """Scalar leaves under dotted names; lists of dicts are left out (they get a table)."""
    out: dict[str, Any] = {}
    for key, value in data.items():
        if isinstance(value, dict):
            out.update(_flat(value, f"{prefix}{key}."))
        elif _scalar(value):
            out[f"{prefix}{key}"] = _cell(value)
    return out


def _rows_table(title: str, rows: dict[str, dict[str, Any]]) -> list[str]:
    flat = {label: _flat(row) for label, row in rows.items()}
    columns = list(dict.fromkeys(c for row in flat.values() for c in row))
    lines: list[str] = []
    for start in range(0, len(columns), GENERIC_COLUMNS):
        part = columns[start:start + GENERIC_COLUMNS]
        lines += [f"`{title}`", *runner.markdown_table(
            ["", *part], [[label, *(row.get(c) for c in part)] for label, row in flat.items()])]
    return lines


def _walk(data: dict[str, Any], prefix: str, scalars: dict[str, Any],
          tables: list[str]) -> None:
    for key, value in data.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict) and value and all(isinstance(v, dict) for v in value.values()):
            tables += _rows_table(name, value)
        elif isinstance(value, dict):
            _walk(value, f"{name}.", scalars, tables)
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            tables += _rows_table(name, {str(i): v for i, v in enumerate(value)})
        elif _scalar(value):
            scalars[name] = _cell(value)


def generic(results: dict[str, Any]) -> list[str]:
    """Tables for any results dict: its scalars as figure/value rows (dotted names), each map
    of rows (like ``by_n``) and each list of rows as a table of its own."""
    scalars: dict[str, Any] = {}
    tables: list[str] = []
    _walk(results, "", scalars, tables)
    lines = runner.markdown_table(["figure", "value"], [[k, v] for k, v in scalars.items()]) \
        if scalars else []
    return [*lines, *tables]


# -- one benchmark, the summary, the page -----------------------------------------------------


def _markdown(lines: list[str]) -> list[str]:
    """Every text line a paragraph of its own, one blank line between blocks."""
    out: list[str] = []
    for line in lines:
        table = line.startswith("|")
        if out and out[-1] != "" and not (table and out[-1].startswith("|")):
            out.append("")
        if line or (out and out[-1] != ""):
            out.append(line)
    while out and out[-1] == "":
        out.pop()
    return out


def figures(name: str, results: dict[str, Any]) -> list[str]:
    """The figure tables of one benchmark: its renderer's, then generic tables of what it did
    not show; a renderer that fails on these results (an older or newer file) gives way to
    generic tables of everything."""
    tracked = _Tracked(results)
    try:
        lines = runner.render_figures(name, tracked, markdown=True)
    except (KeyError, TypeError, ValueError, AttributeError, IndexError):
        return ["All figures (generic tables):", *generic(results)]
    rest = tracked.unread(UNSHOWN.get(name, ()))
    if rest:
        lines += ["", "Further figures in the file:", *generic(rest)]
    return lines


def _verdict(passed: bool | None) -> str:
    return {True: "met", False: "**missed**", None: "not judged"}[passed]


def benchmark_block(name: str, run: dict[str, Any]) -> list[str]:
    entry = run["benchmarks"].get(name)
    if entry is None:
        return [f"`{name}` was not part of the run of {run['date'][:10]}."]
    if entry["status"] == "error":
        lines = entry["error"].splitlines()  # a traceback: its first and last line
        shown = "\n".join(lines if len(lines) <= 2 else [lines[0], "...", lines[-1]])
        return [f"`{name}` did not run ({run['date'][:10]}, {entry['seconds']:g} s; the file "
                "has the whole error):", f"```\n{shown}\n```"]
    lines = [f"`openmotion bench {name}` in the run of {run['date'][:10]} "
             f"([summary](#current-figures)), {entry['seconds']:g} s:",
             *figures(name, entry["results"])]
    if entry["goals"]:
        lines += ["", "Goals:", *runner.markdown_table(
            ["goal", "value", "verdict"],
            [[g["goal"], g["value"], _verdict(g["passed"])] for g in entry["goals"].values()])]
    return lines


def summary_block(run: dict[str, Any], elsewhere: set[str]) -> list[str]:
    """Machine, date, versions and one row per benchmark; the figures of benchmarks without a
    block of their own on the page follow."""
    m, git = run["machine"], run["git"]
    versions = ", ".join(f"{k} {v}" for k, v in m["versions"].items() if v is not None)
    missing = [k for k, v in m["versions"].items() if v is None]
    load = m["load_average"]
    commit = "" if git is None else (f", commit {git['commit'][:10]}"
                                     f"{' with local changes' if git['dirty'] else ''}")
    lines = [
        f"`{run['command']}`{' (--quick: smoke sizes, not a measurement)' if run['quick'] else ''}"
        f", {run['date'].replace('T', ' ').replace('+00:00', ' UTC')}{commit}; "
        f"{run['seconds']:g} s in all.",
        f"Machine: {m['cpu']}, {m['cpu_count']} cores, {m['os']}, Python {m['python']}"
        + (f", load average {' / '.join(runner.format_value(x, 2) for x in load)} at the start"
           if load else "") + ".",
        f"Versions: {versions}" + (f"; not installed: {', '.join(missing)}" if missing else "")
        + ".",
    ]
    rows = []
    for name, entry in run["benchmarks"].items():
        goals = entry["goals"].values()
        missed = [g["goal"] for g in goals if g["passed"] is False]
        rows.append([f"[{name}](#{name})" if name in elsewhere else name, entry["status"],
                     f"{sum(g['passed'] is True for g in goals)} / {len(goals)}",
                     "; ".join(missed) or ("-" if entry["error"] is None
                                           else entry["error"].splitlines()[0][:ERROR_CHARS]),
                     f"{entry['seconds']:.1f}", entry.get("cpu_seconds"),
                     entry.get("load_average")])
    lines += runner.markdown_table(["benchmark", "result", "goals met", "missed", "wall s",
                                    "cpu s", "load"], rows)
    lines.append("cpu s: CPU seconds of the benchmark's processes; load: the machine's load "
                 "average (1 min) as it started. A load near the core count or above stretches "
                 "wall times and their p99 most.")
    for name in run["benchmarks"]:
        if name not in elsewhere:
            lines += ["", f"### {name}", "", *benchmark_block(name, run)]
    return lines


def load_run(path: Path) -> dict[str, Any]:
    """A file written by ``openmotion bench all``; ConfigError if it is not one."""
    try:
        run = json.loads(Path(path).read_text())
    except (OSError, ValueError) as exc:
        raise ConfigError(f"{path}: cannot read a bench all file ({exc})") from None
    if not isinstance(run, dict) or run.get("format") != suite.FORMAT \
            or not isinstance(run.get("benchmarks"), dict):
        raise ConfigError(f"{path}: not a file of `openmotion bench all` (format "
                          f"{suite.FORMAT})")
    return run


def fill(page: str, run: dict[str, Any]) -> str:
    """``page`` with every generated block rendered anew from ``run``; ConfigError if the
    page has no summary block."""
    names = _BLOCK.findall(page)
    blocks = {name for name, _ in names}
    if SUMMARY not in blocks:
        raise ConfigError(f"the page has no {BEGIN.format(name=SUMMARY)} block")
    unknown = blocks - {SUMMARY} - set(runner.BENCHMARKS)
    if unknown:
        raise ConfigError(f"generated block of an unknown benchmark: {sorted(unknown)[0]}")
    elsewhere = blocks - {SUMMARY}

    def block(match: re.Match[str]) -> str:
        name = match.group(1)
        lines = summary_block(run, elsewhere) if name == SUMMARY else benchmark_block(name, run)
        return "\n".join([BEGIN.format(name=name), *_markdown(lines), END])

    return _BLOCK.sub(block, page)


def markdown(run: dict[str, Any]) -> str:
    """The figures of a run as one markdown page (``openmotion bench report FILE``)."""
    return "\n".join(_markdown(["# Current figures", "", *summary_block(run, set())])) + "\n"
