"""Issue 22, point 4: a scenario exported as an FMI 2.0 co-simulation FMU, simulated by fmpy.

fmpy loads the FMU into this process (pythonfmu's binary uses the running interpreter); the
FMU's class is the openmotion under test. The shipped example of docs/endpoints.md
(single_move) is exported and its outputs compared with ``openmotion run``'s trace sample by
sample, bit for bit: both step the same runtime the same cycles and read the same signals.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
pytest.importorskip("pythonfmu")

from openmotion.cli import app  # noqa: E402
from openmotion.core.errors import ConfigError, ErrorId  # noqa: E402
from openmotion.endpoints.fmi import INPUT_ERROR, MachineUnit, StepError, export_fmu  # noqa: E402
from openmotion.examples import resolve_scenario  # noqa: E402
from openmotion.scenario import run_scenario  # noqa: E402

CYCLE = 0.001
MOVE = "x.move_absolute"
#: an axis powered at t = 0 and nothing else: the FMU's inputs drive it
STILL_AXIS = """\
name: still axis
cycle_time: 0.001
duration: 0.6
axes:
  - name: x
    parameters: {max_velocity: 500.0, acceleration: 5000.0, deceleration: 5000.0,
                 jerk: 100000.0}
timeline:
  - {at: 0.0, axis: x, command: power}
record:
  signals: [x.set_position, x.position, x.state]
"""


@pytest.fixture(autouse=True)
def _restore_sys_path() -> object:
    """pythonfmu puts every instance's resources folder on sys.path; take them off again."""
    before = list(sys.path)
    yield
    sys.path[:] = before


@pytest.fixture(scope="module")
def single_move_fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The documented example, exported as docs/endpoints.md says (its stop time from a run)."""
    out = tmp_path_factory.mktemp("fmu") / "single_move.fmu"
    from typer.testing import CliRunner

    result = CliRunner().invoke(app, ["fmu", "single_move", "-o", str(out),
                                      "--command", MOVE])
    assert result.exit_code == 0, result.output
    return out


@pytest.fixture()
def still_axis(tmp_path: Path) -> Path:
    path = tmp_path / "still_axis.yaml"
    path.write_text(STILL_AXIS, encoding="utf-8")
    return path


def _description(fmu: Path) -> str:
    return zipfile.ZipFile(fmu).read("modelDescription.xml").decode("utf-8")


def test_the_fmu_outputs_equal_the_run_trace_sample_by_sample(single_move_fmu: Path) -> None:
    trace = run_scenario(resolve_scenario("single_move")).trace
    result = fmpy.simulate_fmu(str(single_move_fmu), output_interval=CYCLE)
    assert len(result) == len(trace) == 1963  # the default experiment ends where run ends
    assert np.array_equal(result["time"], trace.time)
    for column in trace.signals:
        assert np.array_equal(result[column], trace[column]), column
    # the command nobody drove stays at rest, outputs FALSE
    assert not result[f"{MOVE}.Busy"].any() and not result[f"{MOVE}.Done"].any()


def test_the_model_description_carries_units_types_and_the_scenario(
        single_move_fmu: Path) -> None:
    text = _description(single_move_fmu)
    model = fmpy.read_model_description(str(single_move_fmu), validate=True)
    variables = {v.name: v for v in model.modelVariables}
    assert variables["x.set_velocity"].unit == "mm/s"
    assert variables["x.set_velocity"].causality == "output"
    assert variables[f"{MOVE}.Execute"].type == "Boolean"
    assert variables[f"{MOVE}.Execute"].causality == "input"
    assert variables[f"{MOVE}.position"].unit == "mm"
    assert variables[f"{MOVE}.ErrorID"].type == "Integer"
    assert variables[f"{MOVE}.buffer_mode"].type == "Integer"
    assert variables[f"{MOVE}.acceleration"].start == "NaN"  # MC_DEFAULT, valid XML Schema
    assert variables[f"{MOVE}.velocity"].start == "0"  # required: a number to set
    assert model.defaultExperiment.stepSize == "0.001"
    assert [unit.name for unit in model.unitDefinitions] == ["mm", "mm/s", "mm/s²", "mm/s³"]
    assert "single move" in text  # the scenario's name in the model's description
    names = zipfile.ZipFile(single_move_fmu).namelist()
    assert "resources/scenario.yaml" in names and "resources/openmotion_fmu.json" in names
    assert "binaries/linux64/OpenmotionMachine.so" in names


def test_execute_rising_edge_moves_the_axis_and_done_follows(tmp_path: Path,
                                                             still_axis: Path) -> None:
    fmu = export_fmu(still_axis, tmp_path / "still.fmu", commands=[MOVE])
    names = ["time", f"{MOVE}.Execute", f"{MOVE}.position", f"{MOVE}.velocity"]
    rows = np.array([(0.0, False, 40.0, 200.0), (0.1, True, 40.0, 200.0),
                     (0.5, False, 40.0, 200.0)],
                    dtype=[(names[0], float), (names[1], bool), (names[2], float),
                           (names[3], float)])
    result = fmpy.simulate_fmu(str(fmu), output_interval=0.01, input=rows)
    time, position = result["time"], result["x.set_position"]
    done, busy = result[f"{MOVE}.Done"], result[f"{MOVE}.Busy"]
    assert np.all(position[time <= 0.1 + 1e-9] == 0.0)  # nothing moves before the edge
    assert busy[np.isclose(time, 0.11)].all()
    first_done = time[done.argmax()]
    assert done.any() and 0.2 < first_done < 0.5
    assert position[done.argmax()] == 40.0 and result["x.position"][-1] == 40.0
    assert not busy[done].any()
    # Execute fell at 0.5: Done shows one more step, then resets (PLCopen)
    assert done[np.isclose(time, 0.5)].all() and not done[time > 0.505].any()
    assert not result[f"{MOVE}.Error"].any() and not result[f"{MOVE}.ErrorID"].any()


def test_a_bad_input_value_is_an_fb_error_and_the_axis_stays(tmp_path: Path,
                                                            still_axis: Path) -> None:
    fmu = export_fmu(still_axis, tmp_path / "still.fmu", commands=[MOVE])
    rows = np.array([(0.0, True, 40.0, 7), (1.0, True, 40.0, 7)],  # 7: no BufferMode
                    dtype=[("time", float), (f"{MOVE}.Execute", bool),
                           (f"{MOVE}.position", float), (f"{MOVE}.buffer_mode", np.int32)])
    result = fmpy.simulate_fmu(str(fmu), output_interval=0.05, input=rows, stop_time=0.2)
    assert result[f"{MOVE}.Error"][1:].all()
    assert result[f"{MOVE}.ErrorID"][-1] == int(INPUT_ERROR) == ErrorId.INVALID_PARAMETER_VALUE
    assert not result[f"{MOVE}.Busy"].any()
    assert np.all(result["x.set_position"] == 0.0)


def test_a_level_command_follows_its_input(tmp_path: Path, still_axis: Path) -> None:
    fmu = export_fmu(still_axis, tmp_path / "still.fmu", commands=["x.power"])
    rows = np.array([(0.0, True), (0.2, False)],
                    dtype=[("time", float), ("x.power.enable", bool)])
    result = fmpy.simulate_fmu(str(fmu), output_interval=0.05, input=rows)
    status, time = result["x.power.Status"], result["time"]
    assert status[time < 0.2 - 1e-9].all() and not status[time > 0.2 + 1e-9].any()


def test_the_default_experiment_ends_on_the_traces_last_row(tmp_path: Path,
                                                            still_axis: Path) -> None:
    sparse = tmp_path / "sparse.yaml"  # 601 cycles recorded every 7th: the last row at 0.595 s
    sparse.write_text(STILL_AXIS.replace("duration: 0.6", "duration: 0.601").replace(
        "record:", "record:\n  every: 7"), encoding="utf-8")
    experiment = fmpy.read_model_description(
        str(export_fmu(sparse, tmp_path / "sparse.fmu"))).defaultExperiment
    assert float(experiment.stepSize) == 0.007
    assert float(experiment.stopTime) == 85 * 7 * 0.001


def test_all_signals_gives_every_signal_of_the_model(tmp_path: Path, still_axis: Path) -> None:
    recorded = MachineUnit(still_axis, signals=["x.set_position", "x.position", "x.state"])
    every = MachineUnit(still_axis)
    assert len(every.signals) > len(recorded.signals) == 3
    fmu = export_fmu(still_axis, tmp_path / "all.fmu", all_signals=True)
    outputs = [v.name for v in fmpy.read_model_description(str(fmu)).modelVariables
               if v.causality == "output"]
    assert outputs == [name for name, _ in every.signals]


# -- communication steps ----------------------------------------------------------------------

def test_a_step_of_no_whole_cycles_is_refused_and_the_unit_stays_usable(
        still_axis: Path) -> None:
    unit = MachineUnit(still_axis, commands=[MOVE])
    with pytest.raises(StepError, match=r"0.0015 s is not a whole number of cycles of 0.001"):
        unit.step(0.0, 0.0015)
    with pytest.raises(StepError, match="not a whole number"):
        unit.step(0.0, 0.0)
    with pytest.raises(StepError, match=r"machine stands at t = 0"):
        unit.step(0.004, 0.001)
    assert unit.now == 0.0
    unit.step(0.0, 0.003)
    assert unit.runtime.cycle == 3
    unit.step(0.003, 0.002000000001)  # a sum of steps rounds: whole cycles within 1e-6
    assert unit.runtime.cycle == 5


def test_fmpy_gets_an_error_status_with_the_reason_for_a_bad_step(tmp_path: Path,
                                                                  still_axis: Path) -> None:
    fmu = export_fmu(still_axis, tmp_path / "still.fmu")
    messages: list[str] = []

    def log(env: object, name: bytes, status: int, category: bytes, message: bytes) -> None:
        messages.append(message.decode())

    with pytest.raises(fmpy.fmi1.FMICallException, match="fmi2DoStep failed"):
        fmpy.simulate_fmu(str(fmu), output_interval=0.0025, logger=log, debug_logging=True)
    assert any("0.0025 s is not a whole number of cycles of 0.001 s" in m for m in messages)
    # the same process instantiates the FMU again (pythonfmu 0.7 would crash here, D-270)
    result = fmpy.simulate_fmu(str(fmu), output_interval=0.002, stop_time=0.01)
    assert len(result) == 6


def test_the_fmu_runs_in_a_fresh_python_with_the_fmpy_command(tmp_path: Path,
                                                            still_axis: Path) -> None:
    fmu = export_fmu(still_axis, tmp_path / "still.fmu")
    out = tmp_path / "out.csv"
    script = textwrap.dedent(f"""
        import fmpy, numpy
        result = fmpy.simulate_fmu({str(fmu)!r}, output_interval=0.01, stop_time=0.05)
        fmpy.util.write_csv({str(out)!r}, result)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=300, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    lines = out.read_text().splitlines()
    assert lines[0].split(",")[:3] == ['"time"', '"x.set_position"', '"x.position"']
    assert len(lines) == 7


# -- export errors ----------------------------------------------------------------------------

def test_unknown_commands_are_config_errors_before_anything_is_written(
        tmp_path: Path, still_axis: Path) -> None:
    target = tmp_path / "x.fmu"
    with pytest.raises(ConfigError, match=r"no command 'move_absolut'.*did you mean "
                                          r"'move_absolute'"):
        export_fmu(still_axis, target, commands=["x.move_absolut"])
    with pytest.raises(ConfigError, match=r"no object 'y'; one of x"):
        export_fmu(still_axis, target, commands=["y.move_absolute"])
    with pytest.raises(ConfigError, match=r"not 'OBJECT.COMMAND'"):
        export_fmu(still_axis, target, commands=["move_absolute"])
    with pytest.raises(ConfigError, match=r"ends in .fmu"):
        export_fmu(still_axis, tmp_path / "x.zip")
    with pytest.raises(ConfigError, match=r"no directory"):
        export_fmu(still_axis, tmp_path / "missing" / "x.fmu")
    with pytest.raises(ConfigError, match=r"stop time must be a number > 0"):
        export_fmu(still_axis, target, stop_time=0.0)
    assert list(tmp_path.iterdir()) == [still_axis]
    assert export_fmu(still_axis, target, commands=[MOVE]) == target  # usable afterwards


def test_cli_errors_exit_2_with_the_reason(tmp_path: Path, still_axis: Path) -> None:
    from typer.testing import CliRunner

    runner = CliRunner()
    unknown = runner.invoke(app, ["fmu", "no_such_scenario", "-o", str(tmp_path / "a.fmu")])
    assert unknown.exit_code == 2
    assert "no such file, and no shipped example" in unknown.output
    bad = runner.invoke(app, ["fmu", str(still_axis), "-o", str(tmp_path / "a.fmu"),
                              "-c", "x.fly"])
    assert bad.exit_code == 2
    assert "ConfigError: command 'x.fly': 'x' has no command 'fly'" in bad.output
    assert not (tmp_path / "a.fmu").exists()
    good = runner.invoke(app, ["fmu", str(still_axis), "-o", str(tmp_path / "a.fmu"),
                               "-c", MOVE, "-c", "x.power", "--stop-time", "0.2"])
    assert good.exit_code == 0, good.output
    assert "fmu: written to" in good.output
    assert 'stopTime="0.2"' in _description(tmp_path / "a.fmu")


# -- inputs of every wire kind ----------------------------------------------------------------

def _set(unit: MachineUnit, **values: object) -> None:
    variables = {v.name: v for v in unit.variables}
    for name, value in values.items():
        variables[name].set(value)  # type: ignore[misc]


def test_vector_and_object_inputs_become_the_commands_arguments() -> None:
    from openmotion.planar import PositionXYC

    unit = MachineUnit(resolve_scenario("planar_two_movers"),
                       commands=["one.move_to_position", "one.join_track"])
    names = [v.name for v in unit.variables if v.causality == "input"]
    assert names == ["one.move_to_position.Execute", "one.move_to_position.target.x",
                     "one.move_to_position.target.y", "one.move_to_position.target.c",
                     "one.move_to_position.target.reference_id", "one.join_track.Execute",
                     "one.join_track.track"]
    move, join = unit.ports
    _set(unit, **{"one.move_to_position.target.x": 120.0, "one.move_to_position.target.y": 60.0})
    arguments = move.command.arguments(move.inputs.given(), unit.model)
    assert arguments["target"] == PositionXYC(120.0, 60.0, 0.0, 0)
    # no track of that name: the command is not started, Error and a warning instead
    warnings: list[str] = []
    unit.log = warnings.append
    _set(unit, **{"one.join_track.Execute": True, "one.join_track.track": "nowhere"})
    unit.step(0.0, 0.001)
    assert join.state.error and join.state.error_id == int(INPUT_ERROR)
    assert warnings and "nowhere" in warnings[0]


def test_an_axes_group_position_is_one_real_per_axis() -> None:
    unit = MachineUnit(resolve_scenario("gantry_contour"),
                       commands=["gantry.move_linear_absolute"])
    (port,) = unit.ports
    reals = [v for v in unit.variables if v.name.startswith(
        "gantry.move_linear_absolute.position[")]
    assert [v.name[-3:] for v in reals] == ["[1]", "[2]", "[3]"]
    assert {v.unit for v in reals} == {"mm"}
    _set(unit, **{v.name: float(i) for i, v in enumerate(reals, start=1)})
    arguments = port.command.arguments(port.inputs.given(), unit.model)
    assert arguments["position"] == [1.0, 2.0, 3.0]
    assert "velocity" not in arguments  # NaN: MC_DEFAULT, left to the command
