"""The ``openmotion`` command: thin functions over the public API (style §6).

stdout carries the result (the summary table, or one JSON object with ``--json``); stderr
carries the progress bar, notes on written files and errors. Exit codes: 0 ok, 1 a scenario
check failed, 2 a usage or configuration error.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Annotated, Any

import typer

from openmotion.core.errors import ConfigError

app = typer.Typer(name="openmotion", no_args_is_help=True, add_completion=False,
                  pretty_exceptions_enable=False,
                  help="Deterministic PLCopen motion-control simulator.")

JsonFlag = Annotated[bool, typer.Option("--json", help="Print one JSON object: no colour, "
                                                        "no progress bar.")]
WALL_DELAY = 1.0  #: seconds of wall time before a progress bar appears


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
    scenario: Annotated[Path | None, typer.Argument(
        help="Scenario file. Default: the shipped examples/single_move.yaml.",
        show_default=False)] = None,
    trace: Annotated[Path, typer.Option(help="Where to write the trace: CSV, or NPZ (with the "
                                             "command events and the layout) for a .npz "
                                             "name.")] = Path("trace.csv"),
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
    """Run a scenario in virtual time: summary table on stdout, trace to a CSV or NPZ file."""
    from openmotion.scenario import default_scenario, run_scenario
    from openmotion.trace import image_format, save_plot, write_trace

    path = scenario or default_scenario()
    bar = _ProgressBar(enabled=not (json_output or quiet))
    try:
        if plot is not None:
            image_format(plot)  # before the run, not after it
        result = run_scenario(path, progress=bar, figure=plot is not None)
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    finally:
        bar.close()
    try:
        write_trace(result.trace, trace)
        if plot is not None:
            save_plot(result.trace, plot, title=result.scenario.name)
    except OSError as exc:
        raise _fail(f"error: cannot write {exc.filename}: {exc.strerror}") from None
    if json_output:
        data = result.to_dict()
        data["file"] = str(path)
        data["trace"]["path"] = str(trace)
        data["plot"] = None if plot is None else str(plot)
        typer.echo(json.dumps(data, indent=2))
    elif not quiet:
        _print_summary(result)
        rows, columns = len(result.trace), len(result.trace.columns)
        typer.echo(f"trace: {rows} rows x {columns} columns written to {trace}", err=True)
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
    scenario: Annotated[Path, typer.Argument(help="Scenario file to validate.")],
) -> None:
    """Validate a scenario file without running it; list every problem."""
    from openmotion.scenario import ScenarioError, load_scenario

    try:
        model = load_scenario(scenario)
    except ScenarioError as exc:
        for problem in exc.problems:
            typer.echo(f"ConfigError: {problem}", err=True)
        raise typer.Exit(2) from None
    typer.echo(f"{scenario}: ok ({len(model.axes)} axes, {len(model.timeline)} timeline "
               f"entries, {len(model.checks)} checks)")


@app.command()
def plot(
    trace: Annotated[Path, typer.Argument(help="Trace written by 'openmotion run': CSV, or NPZ "
                                               "(with the command events and the layout).")],
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
    from openmotion.trace import image_format, read_trace, save_plot

    target = output or trace.with_suffix(".png")
    names = [name.strip() for value in signals or () for name in value.split(",")]
    try:
        image_format(target)
        data = read_trace(trace)
        save_plot(data, target, title=trace.stem, signals=[name for name in names if name] or None)
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    except OSError as exc:
        raise _fail(f"error: cannot write {exc.filename}: {exc.strerror}") from None
    typer.echo(f"plot: written to {target}", err=True)


@app.command()
def bench(
    name: Annotated[str, typer.Argument(help="Benchmark to run: axes, otg, fbcall, ca, "
                                             "planar, trace.")],
    json_output: JsonFlag = False,
    quick: Annotated[bool, typer.Option("--quick", help="Small sizes: a smoke run, not a "
                                                        "measurement.")] = False,
) -> None:
    """Run one benchmark and print its table (performance.md)."""
    try:
        from openmotion.bench import runner
    except ImportError as exc:
        raise _fail(f"error: the benchmarks are not available ({exc})") from None
    names = getattr(runner, "BENCHMARKS", None)
    if names is not None and name not in names:
        raise _fail(f"error: unknown benchmark {name!r}; choose one of: {', '.join(names)}")
    bar = _ProgressBar(enabled=not json_output)
    try:
        result = runner.run_benchmark(name, quick=quick, progress=bar.message)
    except (KeyError, ValueError) as exc:
        if names is None:  # the runner alone knows its names
            raise _fail(f"error: {exc}") from None
        raise
    finally:
        bar.close()
    typer.echo(json.dumps(result, indent=2, default=str) if json_output
               else runner.render(result))


@app.command()
def view(
    scenario: Annotated[Path | None, typer.Argument(
        help="Scenario file. Default: the shipped examples/single_move.yaml.",
        show_default=False)] = None,
    speed: Annotated[float, typer.Option(help="Virtual seconds per wall second.")] = 1.0,
    port: Annotated[int, typer.Option(help="TCP port of the page (0: a free one).")] = 8765,
    host: Annotated[str, typer.Option(help="Interface to listen on.")] = "127.0.0.1",
    no_open: Annotated[bool, typer.Option("--no-open", help="Do not open a browser.")] = False,
    start_now: Annotated[bool, typer.Option(
        "--start-now", help="Start the scenario at once instead of when the first page "
        "connects (headless use).")] = False,
) -> None:
    """Watch a scenario live in the browser: paced runtime, machine, scope, controls."""
    from openmotion.scenario import default_scenario
    from openmotion.viewer import Session, serve

    try:
        session = Session.for_scenario(scenario or default_scenario(), speed=speed,
                                       wait_for_page=not start_now)
    except ConfigError as exc:
        raise _fail(f"ConfigError: {exc}") from None
    except ValueError as exc:
        raise _fail(f"error: {exc}") from None
    try:
        serve(session, host, port, open_browser=not no_open,
              announce=lambda url: typer.echo(f"openmotion view: {url} (Ctrl+C stops)",
                                              err=True))
    except OSError as exc:
        raise _fail(f"error: cannot listen on {host}:{port}: {exc.strerror or exc}") from None


if __name__ == "__main__":
    app()
