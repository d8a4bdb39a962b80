"""A trace re-read from its file draws the same figure as the run drew (D-170): the default
CSV with its sidecar and the NPZ, for each kind of figure; `openmotion plot` on the default
trace writes the same image bytes as `run --plot`."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from openmotion.cli import app
from openmotion.scenario import examples_dir, run_scenario
from openmotion.trace import default_figure, plot_trace, read_trace, save_plot, write_trace

runner = CliRunner()
DPI = 40  #: small and fixed: the same pixels for the same figure
#: one shipped example per figure
FIGURES = {"single_move": "scope", "ca_starter_kit": "rail", "planar_two_movers": "planar",
           "gantry_contour": "path"}


def artists(figure) -> list[tuple]:
    """What a figure shows, panel by panel: each line's data, style and colour, each text,
    each patch's outline and colour; and the figure's own texts (title, legends)."""
    figure.canvas.draw()
    content: list[tuple] = [("title", figure.get_suptitle() if hasattr(figure, "get_suptitle")
                             else "")]
    for panel in figure.axes:
        content.append(("panel", panel.get_title(), panel.get_xlabel(), panel.get_ylabel(),
                        panel.get_xlim(), panel.get_ylim()))
        for line in panel.get_lines():
            x, y = line.get_data()
            content.append(("line", line.get_gid(), tuple(map(float, x)), tuple(map(float, y)),
                            line.get_color(), line.get_linestyle(), line.get_marker(),
                            line.get_zorder()))
        for text in panel.texts:
            content.append(("text", text.get_text(), tuple(text.get_position()),
                            text.get_zorder()))
        for patch in panel.patches:
            content.append(("patch", patch.get_gid(), repr(patch.get_path().vertices.tolist()),
                            patch.get_facecolor(), patch.get_edgecolor()))
        legend = panel.get_legend()
        if legend is not None:
            content.append(("legend", tuple(text.get_text() for text in legend.get_texts())))
    content += [("figure legend", tuple(text.get_text() for text in legend.get_texts()))
                for legend in figure.legends]
    return content


@pytest.fixture(scope="module", params=sorted(FIGURES))
def run(request: pytest.FixtureRequest):
    return request.param, run_scenario(examples_dir() / f"{request.param}.yaml", figure=True)


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_the_figure_of_a_re_read_trace_is_the_runs_figure(run, suffix: str,
                                                          tmp_path: Path) -> None:
    name, result = run
    trace = result.trace
    again = read_trace(write_trace(trace, tmp_path / f"{name}{suffix}"))
    assert default_figure(again) == default_figure(trace) == FIGURES[name]
    assert again.events and again.title == result.scenario.name
    assert artists(plot_trace(again)) == artists(plot_trace(trace))
    first = save_plot(trace, tmp_path / "first.png", title=result.scenario.name, dpi=DPI)
    second = save_plot(again, tmp_path / "second.png", dpi=DPI)  # the trace's own title
    assert first.read_bytes() == second.read_bytes()


@pytest.fixture
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("example", ["single_move", "planar_two_movers"])
def test_plot_of_the_default_trace_writes_the_image_run_plot_wrote(in_tmp: Path,
                                                                  example: str) -> None:
    scenario = str(examples_dir() / f"{example}.yaml")
    result = runner.invoke(app, ["run", scenario, "--plot", "run.png", "-q"])
    assert result.exit_code == 0, result.output
    assert (in_tmp / "trace.events.json").exists()
    result = runner.invoke(app, ["plot", "trace.csv"])
    assert result.exit_code == 0, result.output
    assert "note:" not in result.stderr
    assert (in_tmp / "trace.png").read_bytes() == (in_tmp / "run.png").read_bytes()
