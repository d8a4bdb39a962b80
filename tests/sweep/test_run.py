"""Running sweeps on the process pool: the table, failed points, dead workers, resume."""

from __future__ import annotations

import sys
from pathlib import Path

import pandas
import pytest

from openmotion.sweep import (
    TABLE_FILE,
    MissingExtra,
    SweepProgress,
    compared,
    load_sweep,
    run_sweep,
)
from openmotion.sweep.faults import EXIT_CODE, FaultHook, runs

VELOCITY = {"path": "timeline[go].velocity", "values": [100.0, 200.0, 400.0]}
MAX_VELOCITY = {"path": "axes[0].parameters.max_velocity", "values": [1000.0, -1.0]}


def test_the_table_has_one_row_per_point_in_index_order(write_sweep, tmp_path: Path) -> None:
    table = run_sweep(write_sweep(parameters=[VELOCITY]), tmp_path / "out", workers=2)
    assert list(table["index"]) == [0, 1, 2]
    assert list(table["timeline[go].velocity"]) == [100.0, 200.0, 400.0]
    assert list(table["status"]) == ["done"] * 3 and list(table["error"]) == [""] * 3
    assert list(table["x.set_position.final"]) == [20.0] * 3
    peaks = list(table["x.set_velocity.max"])
    assert peaks[0] == pytest.approx(100.0) and peaks[0] < peaks[1] < peaks[2]
    assert list(table["commands.done"]) == [2, 2, 2] and list(table["commands.error"]) == [0] * 3
    assert table["run.end_time"].is_monotonic_decreasing
    assert (table["cycle_cost.cpu_per_cycle"] > 0).all()
    assert list(table.columns[-2:]) == ["cycle_cost.cpu", "cycle_cost.cpu_per_cycle"]
    assert set(table["openmotion_version"]) == {"0.1.0"}
    stored = pandas.read_parquet(tmp_path / "out" / TABLE_FILE)
    pandas.testing.assert_frame_equal(stored, table, check_exact=True)
    assert (tmp_path / "out" / "summary.png").read_bytes()[:4] == b"\x89PNG"


def test_an_invalid_point_is_recorded_as_failed_and_the_sweep_goes_on(write_sweep) -> None:
    table = run_sweep(write_sweep(parameters=[MAX_VELOCITY]), workers=2)
    assert list(table["status"]) == ["done", "failed"]
    assert table["error"][1].startswith("invalid scenario: axes[0].parameters.max_velocity: "
                                        "must be a finite number > 0")
    assert pandas.isna(table["x.set_position.final"][1])
    assert table["x.set_position.final"][0] == 20.0


def test_a_run_that_raises_is_recorded_as_failed_with_its_message(write_sweep) -> None:
    table = run_sweep(write_sweep(parameters=[VELOCITY], metrics=[
        {"signal": "x.gap", "stats": ["min"]}, {"run": ["cycles"]}]), workers=1)
    assert set(table["status"]) == {"failed"}
    assert table["error"][0] == ("ValueError: metric signal 'x.gap': no recorded signal "
                                 "matches (recorded: x.set_position, x.set_velocity)")


def _refuse_point_one(point) -> None:
    if point.index == 1:
        raise RuntimeError("hook refused point 1")


def test_a_point_hook_that_raises_fails_that_point_only(write_sweep) -> None:
    table = run_sweep(write_sweep(parameters=[VELOCITY]), workers=1, on_point=_refuse_point_one)
    assert list(table["status"]) == ["done", "failed", "done"]
    assert table["error"][1] == "RuntimeError: hook refused point 1"


def test_a_point_whose_worker_dies_is_run_again(write_sweep, tmp_path: Path) -> None:
    markers = tmp_path / "markers"
    markers.mkdir()
    sweep = load_sweep(write_sweep(parameters=[VELOCITY], repeat=2))
    table = run_sweep(sweep, workers=2, on_point=FaultHook(markers, exit_at=3))
    assert (markers / "exited").exists()  # the worker did die
    assert list(table["status"]) == ["done"] * 6
    counts = runs(markers)
    assert counts[table["point_id"][3]] == 2
    assert sorted(counts.values()) == [1, 1, 1, 1, 1, 2]
    again = run_sweep(sweep, workers=1)
    pandas.testing.assert_frame_equal(compared(table, sweep), compared(again, sweep),
                                      check_exact=True)


def test_retries_are_bounded_and_a_lost_point_is_tried_again_on_resume(
        write_sweep, tmp_path: Path) -> None:
    markers, out = tmp_path / "markers", tmp_path / "out"
    markers.mkdir()
    path = write_sweep(parameters=[VELOCITY])
    table = run_sweep(path, out, workers=2, retries=0, on_point=FaultHook(markers, exit_at=1))
    assert list(table["status"]) == ["done", "failed", "done"]
    assert table["error"][1] == f"worker died (exit code {EXIT_CODE}) on each of 1 attempts"
    seen: list[SweepProgress] = []
    resumed = run_sweep(path, out, workers=2, on_point=FaultHook(markers), progress=seen.append)
    assert seen[0] == SweepProgress(done=2, failed=0, reused=2, total=3)
    assert list(resumed["status"]) == ["done"] * 3
    assert runs(markers)[table["point_id"][0]] == 1


def test_an_interrupted_sweep_resumes_without_recomputing_finished_points(
        write_sweep, tmp_path: Path) -> None:
    markers, out = tmp_path / "markers", tmp_path / "out"
    markers.mkdir()
    path = write_sweep(parameters=[VELOCITY], repeat=3)

    def stop_after_three(progress: SweepProgress) -> None:
        if progress.done >= 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(path, out, workers=2, on_point=FaultHook(markers), progress=stop_after_three)
    stored = {p.stem for p in (out / "points").glob("*.json")}
    assert len(stored) >= 3 and not (out / TABLE_FILE).exists()
    seen: list[SweepProgress] = []
    table = run_sweep(path, out, workers=2, on_point=FaultHook(markers), progress=seen.append)
    assert seen[0].reused == len(stored) and seen[-1] == SweepProgress(9, 0, len(stored), 9)
    assert list(table["status"]) == ["done"] * 9
    counts = runs(markers)
    assert all(counts[point_id] == 1 for point_id in stored)
    assert set(counts) == set(table["point_id"])


def test_stored_rows_of_other_metrics_are_computed_again(write_sweep, tmp_path: Path) -> None:
    out = tmp_path / "out"
    run_sweep(write_sweep(parameters=[VELOCITY]), out, workers=2, figure=False)
    seen: list[SweepProgress] = []
    table = run_sweep(write_sweep(parameters=[VELOCITY], metrics=[{"run": ["cycles"]}]), out,
                      workers=2, progress=seen.append, figure=False)
    assert seen[0].reused == 0 and list(table.columns[-3:]) == ["run.cycles", "scenario_hash",
                                                                 "openmotion_version"]


def test_a_missing_extra_names_what_to_install(write_sweep, monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    with pytest.raises(MissingExtra, match=r"sweeps need pyarrow: install them with pip "
                                           r"install 'openmotion\[sweep\]'"):
        run_sweep(write_sweep(parameters=[VELOCITY]))
    monkeypatch.setitem(sys.modules, "ray", None)
    with pytest.raises(MissingExtra, match="sweeps need pyarrow, ray"):
        run_sweep(write_sweep(parameters=[VELOCITY]), ray=True)


def test_the_sweep_extra_and_the_test_extra_install_what_sweeps_import() -> None:
    """CI installs ``.[test]``: the Ray tests need what the ``sweep`` extra holds."""
    import tomllib

    from openmotion.sweep.run import EXTRA, RAY_MODULES, TABLE_MODULES

    extras = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text(
        encoding="utf-8"))["project"]["optional-dependencies"]
    names = {requirement.split(">")[0].split("[")[0] for requirement in extras[EXTRA]}
    assert names == set(TABLE_MODULES + RAY_MODULES)
    assert set(extras[EXTRA]) <= set(extras["test"])
