"""Figures: every shipped example gets its default figure as a valid image, the lines drawn
are the trace's numbers, events are marked, colours tell every object and command apart,
labels stay readable, and the CLI's plot and run --plot work."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from matplotlib import colormaps
from matplotlib.colors import to_hex
from matplotlib.image import imread
from matplotlib.transforms import Bbox
from typer.testing import CliRunner

from openmotion.cli import app
from openmotion.scenario import ScenarioResult, examples_dir, run_scenario
from openmotion.trace import (
    Trace,
    default_figure,
    distinct_colors,
    figure_signals,
    plot_trace,
    read_trace,
    save_plot,
)
from openmotion.trace.planar import planar_figure
from openmotion.trace.plot import mark_refusals
from openmotion.trace.scope import scope_figure

EXAMPLES = sorted(examples_dir().glob("*.yaml"))
FORMATS = ("png", "svg", "pdf")
DPI = 30  #: small: the tests check files, not looks
runner = CliRunner()


def is_image(path: Path, kind: str) -> bool:
    head = path.read_bytes()[:512]
    if kind == "png":
        return head.startswith(b"\x89PNG\r\n\x1a\n") and imread(path).ndim == 3
    if kind == "svg":
        return head.startswith(b"<?xml") and b"<svg" in head
    return head.startswith(b"%PDF-")


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[ScenarioResult, Path]]:
    """Every example run once with its figure, saved in one of the three formats each."""
    folder = tmp_path_factory.mktemp("figures")
    out = {}
    for number, path in enumerate(EXAMPLES):
        result = run_scenario(path, figure=True)
        image = folder / f"{path.stem}.{FORMATS[number % 3]}"
        save_plot(result.trace, image, title=result.scenario.name, dpi=DPI)
        out[path.stem] = (result, image)
    return out


@pytest.mark.parametrize("name", [path.stem for path in EXAMPLES])
def test_every_example_gets_its_default_figure_as_a_valid_image(runs, name: str) -> None:
    result, image = runs[name]
    assert is_image(image, image.suffix[1:]), image
    # the planar plot with planar movers (virtual_commissioning has a CA rail too)
    expected = "planar" if name.startswith("planar") or result.scenario.planar \
        else "rail" if name.startswith("ca_") \
        else "path" if result.scenario.axes_groups else "scope"
    assert default_figure(result.trace) == expected


def test_figure_runs_record_what_the_figure_needs_after_the_scenarios_own_signals(
        runs) -> None:
    result, _ = runs["planar_choreography"]
    own = result.scenario.signals
    assert result.trace.signals[:len(own)] == tuple(own)
    needed = figure_signals(result.trace.layout)
    assert len(needed) == 8 * 3 and set(needed) <= set(result.trace.signals)
    plain = run_scenario(examples_dir() / "planar_two_movers.yaml")
    assert plain.trace.signals == tuple(plain.scenario.signals)  # no figure: no extra columns


def test_the_scope_lines_are_the_traces_numbers(runs) -> None:
    trace = runs["single_move"][0].trace
    figure = scope_figure(trace)
    lines = {line.get_gid(): line for panel in figure.axes for line in panel.get_lines()}
    for column in trace.signals:
        x, y = lines[column].get_data()
        assert np.asarray(x).tobytes() == trace.time.tobytes(), column
        assert np.asarray(y).tobytes() == trace[column].tobytes(), column
    assert len(figure.axes) == 5  # position, velocity, acceleration, jerk, following error


def test_the_scope_marks_the_command_events(runs) -> None:
    trace = runs["abort_and_blend"][0].trace
    figure = scope_figure(trace, ["x.set_velocity"])
    panel = figure.axes[0]
    marks = {line.get_gid(): line for line in panel.get_lines()}
    issued = [e for e in trace.events if e.result == "ISSUED"]
    assert all(f"event:{e.label}" in marks for e in issued)
    for result in ("DONE", "ABORTED", "ERROR"):
        times = [e.time for e in trace.events if e.result == result]
        assert list(marks[f"events:{result}"].get_xdata()) == times, result


def test_the_planar_paths_are_the_traces_numbers_and_refusals_are_marked(runs) -> None:
    trace = runs["planar_choreography"][0].trace
    panel = planar_figure(trace).axes[0]
    lines = {line.get_gid(): line for line in panel.get_lines()}
    for mover in ("m1", "m2", "m8"):
        x, y = lines[mover].get_data()
        assert np.array_equal(x, trace[f"{mover}.x"]) and np.array_equal(y, trace[f"{mover}.y"])
    refused = {f"refused:{e.label}" for e in trace.events if e.result == "ERROR"}
    assert refused == {gid for gid in lines if str(gid).startswith("refused:")}
    assert {"refused:m1_step", "refused:m8_out"} <= refused
    stators = [p for p in panel.patches if p.get_gid() == "stator"]
    assert len(stators) == 16


def test_parts_get_a_panel_per_coordinate_system(runs) -> None:
    trace = runs["planar_parts"][0].trace
    figure = planar_figure(trace)
    assert [panel.get_title() for panel in figure.axes] == [
        "coordinate system 16#01010060", "coordinate system 16#010100A0"]
    outlines = [p.get_gid() for p in figure.axes[1].patches if str(p.get_gid()).startswith("part")]
    assert sorted(outlines) == ["part 16#01010030", "part 16#01010080"]


def test_the_rail_plot_draws_every_mover_of_the_group(runs) -> None:
    trace = runs["ca_starter_kit"][0].trace
    figure = plot_trace(trace)
    movers = trace.layout["ca_groups"]["xts"]["movers"]
    drawn = {line.get_gid() for line in figure.axes[0].get_lines()}
    assert set(movers) <= drawn and len(movers) == 10


# -- the CLI -----------------------------------------------------------------------------------


@pytest.fixture
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_run_plot_writes_the_figure_and_plot_redraws_it_from_the_npz(in_tmp: Path) -> None:
    single = str(examples_dir() / "single_move.yaml")
    result = runner.invoke(app, ["run", single, "--trace", "t.npz", "--plot", "f.pdf", "-q"])
    assert result.exit_code == 0, result.output
    assert is_image(in_tmp / "f.pdf", "pdf")
    assert read_trace(in_tmp / "t.npz").events  # the NPZ holds the events
    result = runner.invoke(app, ["plot", "t.npz", "-o", "s.svg",
                                 "--signals", "x.set_position,x.velocity", "-s", "x.set_jerk"])
    assert result.exit_code == 0, result.output
    assert is_image(in_tmp / "s.svg", "svg") and "plot: written to s.svg" in result.stderr


@pytest.mark.parametrize(("arguments", "message"), [
    (["plot", "t.npz", "-o", "f.jpg"], "f.jpg: the image format comes from the suffix"),
    (["plot", "t.npz", "--signals", "x.speed"], "signals: 'x.speed' is neither a column nor"),
    (["run", "--plot", "f.gif"], "f.gif: the image format comes from the suffix"),
])
def test_bad_plot_requests_exit_2_before_any_work(in_tmp: Path, arguments: list[str],
                                                  message: str) -> None:
    assert runner.invoke(app, ["run", "-q", "--trace", "t.npz"]).exit_code == 0
    (in_tmp / "trace.csv").unlink(missing_ok=True)
    result = runner.invoke(app, arguments)
    assert result.exit_code == 2 and result.stderr.startswith(f"ConfigError: {message}"), \
        result.output
    assert not (in_tmp / "trace.csv").exists()  # run --plot with a bad suffix does not run


def test_save_plot_takes_the_format_from_the_suffix(runs, tmp_path: Path) -> None:
    trace = runs["touch_probe"][0].trace
    for kind in FORMATS:
        assert is_image(save_plot(trace, tmp_path / f"t.{kind.upper()}", dpi=DPI), kind)


# -- colours and labels ------------------------------------------------------------------------


@pytest.mark.parametrize("count", [0, 1, 10, 12, 20, 21, 60, 300])
def test_distinct_colors_are_all_different(count: int) -> None:
    colors = distinct_colors(count)
    assert len(colors) == count == len(set(colors))
    assert colors[:10] == [to_hex(color) for color in colormaps["tab10"].colors][:count]


def test_twelve_commands_on_the_path_get_twelve_colours(runs) -> None:
    trace = runs["scara_pick_place"][0].trace
    plane = plot_trace(trace).axes[0]
    spans = {line.get_gid().split(":", 1)[1]: line.get_color() for line in plane.get_lines()
             if str(line.get_gid()).startswith("scara:") and line.get_linestyle() == "-"
             and line.get_gid() != "scara:tcp"}
    assert len(spans) == 12 and len(set(spans.values())) == 12, spans
    legend = [text.get_text() for text in plane.get_legend().get_texts()]
    assert legend[:12] == list(spans)  # each named in the legend, in order


def test_many_objects_on_the_scope_get_colours_of_their_own() -> None:
    objects = [f"a{number}" for number in range(14)]
    trace = Trace(("time", *(f"{name}.set_position" for name in objects)), np.zeros((3, 15)))
    lines = scope_figure(trace).axes[0].get_lines()
    assert len({line.get_color() for line in lines}) == 14


def test_mover_names_are_drawn_above_the_refusal_crosses_and_clear_of_them(runs) -> None:
    trace = runs["planar_choreography"][0].trace
    figure = planar_figure(trace)
    panel = figure.axes[0]
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    names = [text for text in panel.texts if str(text.get_gid()).startswith("name:")]
    labels = [text for text in panel.texts if str(text.get_gid()).startswith("refused-label:")]
    crosses = [line for line in panel.get_lines() if str(line.get_gid()).startswith("refused:")]
    assert len(names) == 8 and len(labels) == len(crosses) >= 5
    assert min(text.get_zorder() for text in names) > max(
        mark.get_zorder() for mark in [*crosses, *labels])
    half = 9 / 2 * figure.dpi / 72  # a cross's half size [px]
    boxes = [Bbox.from_bounds(*(panel.transData.transform(line.get_xydata()[0]) - half),
                              2 * half, 2 * half) for line in crosses]
    boxes += [text.get_window_extent(renderer) for text in labels]
    for number, name in enumerate(names):
        extent = name.get_window_extent(renderer)
        others = boxes + [other.get_window_extent(renderer) for other in names[number + 1:]]
        assert not any(extent.overlaps(box) for box in others), name.get_text()


def test_refusals_at_one_point_get_their_labels_one_under_the_other() -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure()
    FigureCanvasAgg(figure)
    panel = figure.add_subplot()
    mark_refusals(panel, [(1.0, 2.0, "first"), (1.0, 2.0, "second"), (3.0, 2.0, "third")])
    offsets = {text.get_text(): text.xyann for text in panel.texts}
    assert offsets["first"] == offsets["third"] != offsets["second"]
    assert offsets["second"][1] < offsets["first"][1]


@pytest.mark.parametrize("name", [path.stem for path in EXAMPLES])
def test_no_label_of_a_default_figure_overlaps_another(runs, name: str) -> None:
    figure = plot_trace(runs[name][0].trace)
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    for panel in figure.axes:
        texts = [text for text in panel.texts if text.get_text()]
        extents = [text.get_window_extent(renderer) for text in texts]
        for number, extent in enumerate(extents):
            clash = [other.get_text() for other, box in zip(texts[number + 1:],
                                                            extents[number + 1:], strict=True)
                     if extent.overlaps(box)]
            assert not clash, (texts[number].get_text(), clash)


def test_commands_issued_together_share_one_scope_label(runs) -> None:
    trace = runs["abort_and_blend"][0].trace
    top = scope_figure(trace).axes[0]
    labels = [text.get_text() for text in top.texts]
    assert {"enable, first", "abort, queued", "brake, refused"} <= set(labels)
    issued = [event.label for event in trace.events if event.result == "ISSUED"]
    assert [name for label in labels for name in label.split(", ")] == issued
