"""The ``openmotion`` command: thin functions over the public API (style §6).

stdout carries the result (the summary table, or one JSON object with ``--json``); stderr
carries the progress bar, notes on written files and errors. Exit codes: 0 ok, 1 a scenario
check failed, 2 a usage or configuration error.
"""

from __future__ import annotations

import gc
import json
import sys
import time
from pathlib import Path
from typing import Annotated, Any

import typer
from typer.core import TyperCommand

from openmotion.core.errors import ConfigError

app = typer.Typer(name="openmotion", no_args_is_help=True, add_completion=False,
                  pretty_exceptions_enable=False, rich_markup_mode=None,
                  help="Deterministic PLCopen motion-control simulator.")

JsonFlag = Annotated[bool, typer.Option("--json", help="Print one JSON object: no colour, "
                                                        "no progress bar.")]
WALL_DELAY = 1.0  #: seconds of wall time before a progress bar appears
SHOWN_FAILURES = 10  #: failed points listed in the sweep summary
ScenarioArgument = Annotated[str | None, typer.Argument(
    metavar="SCENARIO", show_default=False,
    help="A scenario file, or the name of a shipped example (see 'openmotion examples'). "
         "Default: the shipped single_move example.")]


def _started() -> None:
    """The command's modules are loaded: collect garbage again, never looking at them.

    ``main`` holds the collector off while a command imports (thousands of classes and
    functions, no garbage: collecting during them cost ~8 % of a start); freezing what is
    loaded keeps every later collection of a long run from walking it again."""
    if not gc.isenabled():
        gc.freeze()
        gc.enable()


def _fail(message: str, code: int = 2) -> typer.Exit:
    typer.echo(message, err=True)
    return typer.Exit(code)


class _ProgressBar:
    """A rich bar on stderr that appears only once a run has taken ``WALL_DELAY`` seconds."""

    def __init__(self, enabled: bool) -> None:
        from rich.console import Console

        self.console = Console(stderr=True)
        self.enabled = enabled and self.console.is_terminal
        self.started = time.monotonic()
        self.bar: Any = None
        self.task: Any = None

    def __call__(self, done: float, total: float | None, label: str = "simulated") -> None:
        if not self.enabled:
            return
        if self.bar is None:
            if time.monotonic() - self.started < WALL_DELAY:
                return
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

            self.bar = Progress(BarColumn(), TextColumn(f"{{task.completed:.2f}} s {label}"),
                                TimeElapsedColumn(), console=self.console, transient=True)
            self.bar.start()
            self.task = self.bar.add_task(label, total=total)
        self.bar.update(self.task, completed=done, total=total)

    def message(self, text: str) -> None:
        if self.enabled:
            self.console.print(text, style="dim", highlight=False, markup=False)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


@app.command()
def run(
    scenario: ScenarioArgument = None,
    trace: Annotated[Path | None, typer.Option(
        help="Where to write the trace: .csv (the command events and the layout go to a "
             ".events.json beside it) or .npz (all in one file). Default: trace.csv, none "
             "when the trace is streamed.", show_default=False)] = None,
    trace_keep: Annotated[int | None, typer.Option(
        min=1, metavar="ROWS", help="Keep only the last ROWS rows of the trace in memory "
        "(replaces the scenario's record keep/stream).", show_default=False)] = None,
    trace_stream: Annotated[Path | None, typer.Option(
        metavar="DIRECTORY", help="Stream the trace to this directory in NPZ chunks as the "
        "run goes (replaces the scenario's record keep/stream); 'openmotion plot DIRECTORY' "
        "reads it.", show_default=False)] = None,
    trace_chunk: Annotated[int | None, typer.Option(
        min=1, metavar="ROWS", help="Rows per chunk of a streamed trace. Default: about a "
        "million values per chunk.", show_default=False)] = None,
    plot: Annotated[Path | None, typer.Option(help="Also draw the scenario's figure into this "
                                                    "image file (.png, .svg, .pdf): the planar "
                                                    "plot with planar movers, the path plot "
                                                    "with axes groups, the rail plot with CA "
                                                    "groups, else the scope. The run records "
                                                    "what it needs.")] = None,
    json_output: JsonFlag = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="Print nothing but errors; the "
                                                              "exit code tells the result.")]
    = False,
) -> None:
    """Run a scenario in virtual time: summary table on stdout, trace to a CSV or NPZ file
    (or streamed to a directory)."""
    from openmotion.scenario import run_scenario
    from openmotion.trace import (
        StreamedTrace,
        image_format,
        save_plot,
        trace_format,
        write_trace,
    )

    _started()

    path = _scenario_path(scenario)
    bar = _ProgressBar(enabled=not (json_output or quiet))
    try:
        if trace is not None:
            trace_format(trace)  # before the run, not after it
        if plot is not None:
            image_format(plot)
        result = run_scenario(path, progress=bar, figure=plot is not None, keep=trace_keep,
                              stream=trace_stream, chunk=trace_chunk)
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    except OSError as exc:  # a streamed trace's chunk could not be written
        raise _fail(f"error: cannot write {exc.filename}: {exc.strerror}") from None
    finally:
        bar.close()
    streamed = isinstance(result.trace, StreamedTrace)
    if trace is None and not streamed:
        trace = Path("trace.csv")
    try:
        if trace is not None:  # a streamed trace is read back only when asked for
            write_trace(result.trace, trace)
        if plot is not None:
            save_plot(result.trace, plot, title=result.scenario.name)
    except OSError as exc:
        raise _fail(f"error: cannot write {exc.filename}: {exc.strerror}") from None
    where = trace if trace is not None else result.trace.directory  # type: ignore[attr-defined]
    if json_output:
        data = result.to_dict()
        data["file"] = str(path)
        data["trace"]["path"] = str(where)
        data["plot"] = None if plot is None else str(plot)
        typer.echo(json.dumps(data, indent=2))
    elif not quiet:
        _print_summary(result)
        rows, columns = len(result.trace), len(result.trace.columns)
        verb = "written to" if trace is not None else "streamed to"
        typer.echo(f"trace: {rows} rows x {columns} columns {verb} {where}", err=True)
        if plot is not None:
            typer.echo(f"plot: written to {plot}", err=True)
    if not result.passed:
        raise typer.Exit(1)


def _print_summary(result: Any) -> None:
    from rich.console import Console

    console = Console(highlight=False)
    if console.is_terminal:
        console.print(result.renderable())
    else:  # pipes and files get exactly the golden text of examples/*.out
        sys.stdout.write(result.summary())


@app.command()
def check(
    scenario: Annotated[str, typer.Argument(
        metavar="SCENARIO", help="A scenario file, or the name of a shipped example.")],
) -> None:
    """Validate a scenario file without running it; list every problem."""
    from openmotion.scenario import ScenarioError, load_scenario

    path = _scenario_path(scenario)
    try:
        model = load_scenario(path)
    except ScenarioError as exc:
        for problem in exc.problems:
            typer.echo(f"ConfigError: {problem}", err=True)
        raise typer.Exit(2) from None
    typer.echo(f"{path}: ok ({len(model.axes)} axes, {len(model.timeline)} timeline "
               f"entries, {len(model.checks)} checks)")


@app.command()
def examples(json_output: JsonFlag = False) -> None:
    """List the shipped example scenarios: 'openmotion run NAME' runs one."""
    from openmotion.examples import list_examples

    found = list_examples()
    if json_output:
        typer.echo(json.dumps([{"name": e.name, "path": str(e.path), "summary": e.summary}
                               for e in found], indent=2))
        return
    if not found:
        raise _fail("error: no shipped examples found (is the installation complete?)")
    width = max(len(e.name) for e in found)
    for example in found:
        typer.echo(f"{example.name.ljust(width)}  {example.summary}".rstrip())
    typer.echo(f"{len(found)} examples in {found[0].path.parent}; run one with "
               "'openmotion run NAME'", err=True)


@app.command()
def plot(
    trace: Annotated[Path, typer.Argument(help="Trace written by 'openmotion run': .csv (with "
                                               "its .events.json beside it) or .npz.")],
    signals: Annotated[list[str] | None, typer.Option(
        "--signals", "-s", help="Draw the scope of these signals (x.set_position) or objects "
        "(x: all its signals), comma-separated or repeated. Default: the trace's own figure.",
        show_default=False)] = None,
    output: Annotated[Path | None, typer.Option(
        "--output", "-o", help="Image file to write, .png, .svg or .pdf. Default: the trace's "
        "name with .png.", show_default=False)] = None,
) -> None:
    """Draw a trace: the planar plot with planar movers, the path plot with axes groups, the
    rail plot with CA groups, else the scope (stacked panels over time, command events
    marked)."""
    import warnings

    from openmotion.trace import image_format, read_trace, save_plot

    _started()

    target = output or trace.with_suffix(".png")
    names = [name.strip() for value in signals or () for name in value.split(",")]
    try:
        image_format(target)
        with warnings.catch_warnings(record=True) as notes:
            warnings.simplefilter("always")
            data = read_trace(trace)
        for note in notes:  # a CSV without its sidecar: the scope, and why
            typer.echo(f"note: {note.message}", err=True)
        save_plot(data, target, title=data.title or trace.stem,
                  signals=[name for name in names if name] or None)
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    except OSError as exc:
        raise _fail(f"error: cannot write {exc.filename}: {exc.strerror}") from None
    typer.echo(f"plot: written to {target}", err=True)


def _bench_help() -> str:
    from openmotion.bench import BENCHMARK_NAMES

    return (f"Benchmark to run: {', '.join(BENCHMARK_NAMES)}; 'all' runs every one and writes "
            "one file; 'report FILE' renders such a file as markdown.")


@app.command()
def bench(
    name: Annotated[str, typer.Argument(metavar="NAME", help=_bench_help())],
    file: Annotated[Path | None, typer.Argument(
        metavar="[FILE]", show_default=False,
        help="report: the JSON file of a 'bench all' run.")] = None,
    json_output: JsonFlag = False,
    quick: Annotated[bool, typer.Option("--quick", help="Small sizes: a smoke run, not a "
                                                        "measurement.")] = False,
    cycles: Annotated[int | None, typer.Option(
        min=1, help="Length of the long run (trace: samples of the memory part; default "
        "1000000, 20000 with --quick).", show_default=False)] = None,
    only: Annotated[str | None, typer.Option(
        help="all: run only these benchmarks (comma-separated).", show_default=False)] = None,
    skip: Annotated[str | None, typer.Option(
        help="all: leave these benchmarks out (comma-separated).", show_default=False)] = None,
    output: Annotated[Path | None, typer.Option(
        "--output", "-o", help="all: write the run (JSON) to this file.",
        show_default=False)] = None,
    write_docs: Annotated[Path | None, typer.Option(
        "--write-docs", metavar="PAGE", show_default=False,
        help="all, report: render the figures into the generated blocks of this page "
             "(docs/benchmarks.md).")] = None,
) -> None:
    """Run one benchmark and print its figures and goals (docs/benchmarks.md); or every
    benchmark ('all'), or render the file of such a run ('report')."""
    from openmotion.bench import BENCHMARK_NAMES

    if name not in (*BENCHMARK_NAMES, "all", "report"):
        raise _fail(f"error: unknown benchmark {name!r}; choose one of: "
                    f"{', '.join(BENCHMARK_NAMES)}, all, report")
    given = {"FILE": file is not None and name != "report",
             "--only": only is not None and name != "all",
             "--skip": skip is not None and name != "all",
             "--output": output is not None and name != "all",
             "--write-docs": write_docs is not None and name not in ("all", "report"),
             "--cycles": cycles is not None and name in ("all", "report")}
    misplaced = [option for option, wrong in given.items() if wrong]
    if misplaced:
        raise _fail(f"error: {misplaced[0]} does not go with 'bench {name}'")
    if name == "report":
        _bench_report(file, write_docs)
        return
    try:
        from openmotion.bench import runner
    except ImportError as exc:
        raise _fail(f"error: the benchmarks are not available ({exc})") from None
    if name == "all":
        _bench_all(json_output, quick, only, skip, output, write_docs)
        return
    if cycles is not None and name not in runner.LONG_RUNS:
        raise _fail(f"error: --cycles: only for {', '.join(runner.LONG_RUNS)}, not {name}")
    _started()
    bar = _ProgressBar(enabled=not json_output)
    try:
        result = runner.run_benchmark(name, quick=quick, progress=bar.message, cycles=cycles)
    except ImportError as exc:  # an optional extra (the sweep benchmark's) is missing
        raise _fail(f"error: {exc}") from None
    finally:
        bar.close()
    typer.echo(json.dumps(result, indent=2, default=str) if json_output
               else runner.render(result))


def _names(value: str | None) -> list[str] | None:
    return None if value is None else [n.strip() for n in value.split(",") if n.strip()]


def _bench_all(json_output: bool, quick: bool, only: str | None, skip: str | None,
               output: Path | None, write_docs: Path | None) -> None:
    """Every benchmark (or --only some), each in a process of its own; progress on stderr,
    the run on stdout (summary, or JSON) and in --output; exit 1 unless every goal was met."""
    import shlex

    from openmotion.bench import report, suite

    try:
        names = suite.select(_names(only), _names(skip) or ())
    except ValueError as exc:
        raise _fail(f"error: {exc}") from None
    if not names:
        raise _fail("error: --only and --skip leave no benchmark to run")
    _read_page(write_docs)  # a wrong page fails before the long run, which reads it again
    _started()
    command = shlex.join(["openmotion", "bench", "all", *(["--quick"] if quick else []),
                          *(["--only", only] if only else []), *(["--skip", skip] if skip else []),
                          *(["-o", str(output)] if output else []),
                          *(["--write-docs", str(write_docs)] if write_docs else [])])
    run = suite.run_suite(names, quick=quick, command=command,
                          echo=lambda text: typer.echo(text, err=True))
    text = json.dumps(run, indent=1, default=str)
    if output is not None:
        try:
            output.parent.mkdir(parents=True, exist_ok=True)
            output.write_text(text + "\n")
        except OSError as exc:
            raise _fail(f"error: cannot write {output}: {exc.strerror}") from None
        typer.echo(f"bench all: written to {output}", err=True)
    if write_docs is not None:
        _write_page(write_docs, None, run, report)
    typer.echo(text if json_output else suite.summary(run))
    if not run["passed"]:
        raise typer.Exit(1)


def _read_page(page: Path | None) -> str | None:
    """The page --write-docs names, read before a long run so that a wrong path fails first."""
    if page is None:
        return None
    try:
        text = page.read_text()
    except OSError as exc:
        raise _fail(f"error: cannot read {page}: {exc.strerror}") from None
    from openmotion.bench import report

    if report.BEGIN.format(name=report.SUMMARY) not in text:
        raise _fail(f"error: {page} has no {report.BEGIN.format(name=report.SUMMARY)} block")
    return text


def _write_page(page: Path, text: str | None, run: dict[str, Any], report: Any) -> None:
    try:
        page.write_text(report.fill(text or page.read_text(), run))
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    except OSError as exc:
        raise _fail(f"error: cannot write {page}: {exc.strerror}") from None
    typer.echo(f"bench: figures written to {page}", err=True)


def _bench_report(file: Path | None, write_docs: Path | None) -> None:
    """Render the file of a 'bench all' run: markdown on stdout, or into --write-docs."""
    from openmotion.bench import report

    if file is None:
        raise _fail("error: bench report needs FILE, the JSON file of a 'bench all' run")
    try:
        run = report.load_run(file)
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    if write_docs is None:
        typer.echo(report.markdown(run), nl=False)
        return
    _write_page(write_docs, _read_page(write_docs), run, report)


class _OptionalRayAddress(TyperCommand):
    """``--ray`` without a value means ``--ray local`` (typer's options cannot leave their
    value out): a bare ``--ray`` is the last argument or followed by another option."""

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        from openmotion.sweep.run import RAY_LOCAL

        args = list(args)
        for number, arg in enumerate(args):
            if arg == "--":
                break
            if arg == "--ray" and (number + 1 == len(args) or args[number + 1].startswith("-")):
                args[number] = f"--ray={RAY_LOCAL}"
        return super().parse_args(ctx, args)


@app.command(cls=_OptionalRayAddress)
def sweep(
    sweep_file: Annotated[Path, typer.Argument(metavar="SWEEP", help="A sweep file: base "
                                                                   "scenario, parameters, "
                                                                   "metrics (docs/sweeps.md).")],
    output: Annotated[Path | None, typer.Option(
        "--output", "-o", help="Directory for the finished points, results.parquet and "
        "summary.png; the same command again resumes from it. Default: the sweep file's name "
        "with '.sweep', in the working directory.", show_default=False)] = None,
    workers: Annotated[int | None, typer.Option(
        min=1, help="Worker processes, or the CPUs of a local Ray cluster. Default: the CPUs "
        "this process may use.", show_default=False)] = None,
    ray: Annotated[str | None, typer.Option(
        "--ray", metavar="[ADDRESS]", help="Run the points on Ray: alone (or 'local') starts a "
        "local cluster on 127.0.0.1; an address (auto, HOST:6379, ray://HOST:10001) joins a "
        "running one.", show_default=False)] = None,
    retries: Annotated[int, typer.Option(min=0, help="New attempts for a point whose worker "
                                                     "process died.")] = 2,
    figure: Annotated[bool, typer.Option("--figure/--no-figure",
                                         help="Draw summary.png.")] = True,
    json_output: JsonFlag = False,
) -> None:
    """Run a scenario many times with parameters varied: one row per point in a Parquet
    table, a summary figure. Exit 1 when a point failed."""
    from openmotion.sweep import MissingExtra, load_sweep, require_extra, run_sweep

    _started()
    try:
        require_extra(ray=ray is not None)
        loaded = load_sweep(sweep_file)
    except MissingExtra as exc:
        raise _fail(f"error: {exc}") from None
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    directory = output or Path(f"{sweep_file.stem}.sweep")
    bar = _SweepBar(enabled=not json_output)
    try:
        table = run_sweep(loaded, directory, workers=workers, retries=retries, figure=figure,
                          ray=False if ray is None else ray,
                          progress=bar)
    except KeyboardInterrupt:
        bar.close()
        raise _fail(f"interrupted: {bar.done} of {bar.total} points are stored in "
                    f"{directory}; the same command again resumes", 130) from None
    except ConnectionError as exc:
        raise _fail(f"error: cannot join the Ray cluster at {ray}: {exc}") from None
    except OSError as exc:
        raise _fail(f"error: cannot write {exc.filename}: {exc.strerror}") from None
    finally:
        bar.close()
    _report_sweep(table, directory, bar.reused, figure, json_output)
    if (table["status"] != "done").any():
        raise typer.Exit(1)


class _SweepBar:
    """The sweep's progress on stderr: points done of all, failed, time left."""

    def __init__(self, enabled: bool) -> None:
        from rich.console import Console

        self.console = Console(stderr=True)
        self.enabled = enabled and self.console.is_terminal
        self.done = self.total = self.reused = 0
        self.bar: Any = None
        self.task: Any = None

    def __call__(self, progress: Any) -> None:
        self.done, self.total, self.reused = progress.done, progress.total, progress.reused
        if not self.enabled:
            return
        if self.bar is None:
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeRemainingColumn,
            )

            self.bar = Progress(TextColumn("points"), BarColumn(), MofNCompleteColumn(),
                                TextColumn("failed {task.fields[failed]}"),
                                TextColumn("left"), TimeRemainingColumn(),
                                console=self.console, transient=True)
            self.bar.start()
            self.task = self.bar.add_task("sweep", total=progress.total,
                                          completed=progress.done, failed=progress.failed)
        self.bar.update(self.task, completed=progress.done, failed=progress.failed)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
            self.bar = None


def _report_sweep(table: Any, directory: Path, reused: int, figure: bool,
                  json_output: bool) -> None:
    from openmotion.sweep import TABLE_FILE

    failed = table[table["status"] != "done"]
    files = {"table": str(directory / TABLE_FILE),
             "figure": str(directory / "summary.png") if figure else None}
    if json_output:
        typer.echo(json.dumps({
            "output": str(directory), **files, "points": len(table),
            "done": len(table) - len(failed), "failed": len(failed), "reused": reused,
            "failures": [{"index": int(row["index"]), "point_id": row["point_id"],
                          "error": row["error"]} for _, row in failed.iterrows()]}, indent=2))
        return
    typer.echo(f"{len(table)} points: {len(table) - len(failed)} done, {len(failed)} failed, "
               f"{reused} reused from {directory}")
    for _, row in failed.head(SHOWN_FAILURES).iterrows():
        typer.echo(f"  point {row['index']} ({row['point_id'][:12]}): {row['error']}")
    if len(failed) > SHOWN_FAILURES:
        typer.echo(f"  ... and {len(failed) - SHOWN_FAILURES} more (the table's error column)")
    typer.echo(f"table: written to {files['table']}", err=True)
    if figure:
        typer.echo(f"figure: written to {files['figure']}", err=True)


@app.command()
def view(
    scenario: ScenarioArgument = None,
    speed: Annotated[float, typer.Option(help="Virtual seconds per wall second.")] = 1.0,
    port: Annotated[int, typer.Option(min=0, max=65535,
                                      help="TCP port of the page (0: a free one).")] = 8765,
    host: Annotated[str, typer.Option(help="Interface to listen on: an IP address or a host "
                                           "name. Anything but loopback lets other machines "
                                           "control the simulation.")] = "127.0.0.1",
    no_open: Annotated[bool, typer.Option("--no-open", help="Do not open a browser.")] = False,
    start_now: Annotated[bool, typer.Option(
        "--start-now", help="Start the scenario at once instead of when the first page "
        "connects (headless use).")] = False,
) -> None:
    """Watch a scenario live in the browser: paced runtime, machine, scope, controls."""
    from openmotion.viewer import Session, serve

    _started()
    _check_host(host)
    path = _scenario_path(scenario)
    try:
        session = Session.for_scenario(path, speed=speed, wait_for_page=not start_now)
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    except ValueError as exc:
        raise _fail(f"error: {exc}") from None
    waits = "" if start_now else "; the scenario starts when the page connects"
    try:
        serve(session, host, port, open_browser=not no_open,
              announce=lambda url: typer.echo(f"openmotion view: {url} (Ctrl+C stops{waits})",
                                              err=True))
    except OSError as exc:
        raise _fail(f"error: cannot listen on {host}:{port}: {exc.strerror or exc}") from None


@app.command()
def fmu(
    scenario: ScenarioArgument = None,
    output: Annotated[Path | None, typer.Option(
        "--output", "-o", help="The FMU file to write (.fmu). Default: the scenario's name "
        "with .fmu, in the current directory.", show_default=False)] = None,
    command: Annotated[list[str] | None, typer.Option(
        "--command", "-c", metavar="OBJECT.COMMAND", help="A command the FMU takes as "
        "inputs (x.move_absolute: Execute, its inputs; Done, Busy, Error ... out); repeat "
        "for more.", show_default=False)] = None,
    all_signals: Annotated[bool, typer.Option(
        "--all-signals", help="Every signal of the machine model as an output, not only "
        "those the scenario records.")] = False,
    stop_time: Annotated[float | None, typer.Option(
        metavar="SECONDS", help="The default experiment's stop "
        "time. Default: the scenario's duration, or where 'openmotion run' ends it.",
        show_default=False)] = None,
) -> None:
    """Export a scenario as an FMI 2.0 co-simulation FMU: its signals as outputs, chosen
    commands as inputs, doStep in whole cycles (docs/endpoints.md)."""
    _started()
    path = _scenario_path(scenario)
    target = output if output is not None else Path(f"{path.stem}.fmu")
    try:
        from openmotion.endpoints.fmi import export_fmu

        written = export_fmu(path, target, commands=command or (), all_signals=all_signals,
                             stop_time=stop_time)
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    except ImportError as exc:
        raise _fail(f"error: exporting an FMU needs pythonfmu ({exc}); install it with "
                    "pip install 'openmotion[fmi]'") from None
    except OSError as exc:
        raise _fail(f"error: cannot write {exc.filename or target}: "
                    f"{exc.strerror or exc}") from None
    typer.echo(f"fmu: written to {written}", err=True)


SERVE_EXAMPLE = "virtual_commissioning"  #: what ``openmotion serve`` serves without an argument


@app.command("serve")
def serve_command(
    scenario: Annotated[str | None, typer.Argument(
        metavar="SCENARIO", show_default=False,
        help="A scenario file, or the name of a shipped example (see 'openmotion examples'). "
             f"Default: the shipped {SERVE_EXAMPLE} example (a CA rail and a planar field).")]
    = None,
    pace: Annotated[str, typer.Option(
        metavar="wall|lockstep", help="wall: virtual time follows the wall clock (times "
        "--speed); lockstep: it moves only when a client steps it (Host.Step).")] = "wall",
    speed: Annotated[float, typer.Option(help="Virtual seconds per wall second (wall "
                                              "pace).")] = 1.0,
    kernel: Annotated[str, typer.Option(
        metavar="process|thread", help="process: the machine steps in a process of its own, "
        "so busy servers never make a cycle late; thread: in the servers' process.")]
    = "process",
    kernel_priority: Annotated[str, typer.Option(
        metavar="realtime|nice|normal", help="What the kernel process asks the scheduler "
        "for: real time for its thread (else a lower nice value), a lower nice value, or "
        "nothing. Only what the system allows is taken.")] = "realtime",
    opcua: Annotated[bool, typer.Option("--opcua", help="Serve OPC UA.")] = False,
    opcua_port: Annotated[int, typer.Option(min=0, max=65535, help="TCP port of the OPC UA "
                                                                   "server (0: a free one).")]
    = 4840,
    opcua_security: Annotated[str, typer.Option(
        metavar="POLICIES", help="OPC UA security policies, comma-separated: none, "
        "basic256sha256 (makes a self-signed server certificate if --opcua-cert-dir has "
        "none).")] = "none",
    opcua_cert_dir: Annotated[Path | None, typer.Option(
        metavar="DIRECTORY", help="Where the OPC UA server keeps its key and certificate. "
        "Default: a temporary directory, a new certificate each run.",
        show_default=False)] = None,
    ads: Annotated[bool, typer.Option("--ads", help="Serve ADS.")] = False,
    ads_port: Annotated[int, typer.Option(min=0, max=65535, help="TCP port of the ADS "
                                                                 "server.")] = 48898,
    bind: Annotated[str, typer.Option(metavar="ADDRESS", help="Address to listen on. "
                                      "Anything but loopback lets other machines read and, "
                                      "with credentials, drive the simulation.")]
    = "127.0.0.1",
    user: Annotated[list[str] | None, typer.Option(
        metavar="NAME:PASSWORD", help="A user who may command the machine (repeat for more); "
        "anonymous clients only read.", show_default=False)] = None,
    users_file: Annotated[Path | None, typer.Option(
        metavar="PATH", help="Users who may command: one NAME:PASSWORD a line.",
        show_default=False)] = None,
    trust: Annotated[list[Path] | None, typer.Option(
        metavar="CERTIFICATE", help="A client certificate (DER or PEM) whose OPC UA sessions "
        "may command (repeat for more).", show_default=False)] = None,
    writable: Annotated[bool, typer.Option(
        "--writable", help="Let clients without credentials command the machine (ADS "
        "writes, anonymous OPC UA calls); not with --user.")] = False,
    duration: Annotated[float | None, typer.Option(
        min=0.0, help="Stop after this many wall seconds. Default: until Ctrl+C.",
        show_default=False)] = None,
) -> None:
    """Serve a scenario's machine to OPC UA and ADS clients, paced by the wall clock or in
    lockstep with a client; a status line shows clients, pace and lateness."""
    from openmotion.endpoints import EndpointUnavailable, serve
    from openmotion.endpoints.serve import parse_user, read_users

    _started()
    if pace not in ("wall", "lockstep"):
        raise _fail(f"error: --pace must be wall or lockstep, not {pace!r}")
    if kernel not in ("process", "thread"):
        raise _fail(f"error: --kernel must be process or thread, not {kernel!r}")
    if kernel_priority not in ("realtime", "nice", "normal"):
        raise _fail("error: --kernel-priority must be realtime, nice or normal, not "
                    f"{kernel_priority!r}")
    if not (opcua or ads):
        raise _fail("error: choose at least one endpoint: --opcua, --ads")
    _check_host(bind, "--bind")
    path = _scenario_path(scenario if scenario is not None else SERVE_EXAMPLE)
    try:
        users = dict(parse_user(text) for text in user or ())
        if users_file is not None:
            users.update(read_users(users_file))
        if writable and (users or trust):
            raise ConfigError("--writable lets anonymous clients command; with --user, "
                              "--users-file or --trust only they may: choose one")
        security = tuple(name.strip().lower() for name in opcua_security.split(",")
                         if name.strip())
        served = serve(path, pace=pace, speed=speed, bind=bind, kernel=kernel,
                       kernel_priority=kernel_priority,
                       opcua={"port": opcua_port, "writable": writable, "users": users,
                              "certificates": tuple(trust or ()), "security": security,
                              "certificate_dir": opcua_cert_dir} if opcua else False,
                       ads={"port": ads_port, "writable": writable} if ads else False)
        served.start()
    except EndpointUnavailable as exc:
        raise _fail(f"error: {exc}") from None
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    except OSError as exc:
        raise _fail(f"error: {exc.strerror or exc}") from None
    try:
        urls = " · ".join(f"{name} {url}" for name, url in served.urls().items())
        typer.echo(f"openmotion serve: {urls} (Ctrl+C stops)", err=True)
        _status_loop(served, duration)
    except KeyboardInterrupt:
        pass
    finally:
        served.stop()
    typer.echo(f"stopped: {served.line()}", err=True)


STATUS_EVERY = 0.5  #: seconds between two updates of the live status line
STATUS_PLAIN_EVERY = 10.0  #: seconds between two status lines when stderr is no terminal


def _status_loop(served: Any, duration: float | None) -> None:
    """Show the status line until ``duration`` is over (or Ctrl+C): one live rich line on
    a terminal, a plain line every ``STATUS_PLAIN_EVERY`` seconds otherwise."""
    from rich.console import Console
    from rich.live import Live

    console = Console(stderr=True, highlight=False)
    end = None if duration is None else time.monotonic() + duration
    live = Live(served.line(), console=console, transient=True) if console.is_terminal \
        else None
    last_plain = time.monotonic()
    if live is not None:
        live.start()
    try:
        while end is None or time.monotonic() < end:
            time.sleep(min(STATUS_EVERY, max(0.0, end - time.monotonic()))
                       if end is not None else STATUS_EVERY)
            if live is not None:
                live.update(served.line())
            elif time.monotonic() - last_plain >= STATUS_PLAIN_EVERY:
                last_plain = time.monotonic()
                typer.echo(served.line(), err=True)
            if not served.host.running:
                break
    finally:
        if live is not None:
            live.stop()


def _scenario_path(argument: str | None) -> Path:
    """The file a scenario argument names (a path, or a shipped example's name); exit 2 with
    a hint when it names neither."""
    from openmotion.examples import resolve_scenario

    path = resolve_scenario(argument)
    if not path.exists():
        raise _fail(f"error: {argument}: no such file, and no shipped example of that name "
                    "('openmotion examples' lists them)")
    return path


def _check_host(host: str, flag: str = "--host") -> None:
    """Exit 2 unless ``host`` is an IP address or a well-formed host name; warn off loopback."""
    import ipaddress
    import re

    try:
        address = ipaddress.ip_address(host)
    except ValueError:
        label = r"(?!-)[A-Za-z0-9-]{1,63}(?<!-)"
        if len(host) > 253 or not re.fullmatch(rf"{label}(\.{label})*\.?", host):
            raise _fail(f"error: {flag} {host!r} is neither an IP address nor a host "
                        "name") from None
        loopback = host.lower().rstrip(".") == "localhost"
    else:
        loopback = address.is_loopback
    if not loopback:
        typer.echo(f"warning: listening on {host}: anyone who reaches this address can "
                   "watch and control the simulation", err=True)


def main() -> None:
    """The ``openmotion`` command (also ``python -m openmotion``)."""
    gc.disable()  # until the command's modules are loaded (_started); short commands never
    app(prog_name="openmotion")


if __name__ == "__main__":
    main()
