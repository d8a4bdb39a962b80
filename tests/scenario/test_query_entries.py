"""The TcMC blocks that scenario files reach since issue 20 ("Scenario files reach every
block"): MC_MoveAbsoluteOrRestart (TcMC §3.6), the read blocks (§4.3-§4.5), the parameter
blocks (§4.6-§4.11) and F_GetVersionTcMC (§5.1), and how a check reads a query's outputs
(``output``, D-218)."""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.axis.parameters import AxisParameters
from openmotion.scenario import (
    CommandRow,
    ScenarioError,
    ScenarioResult,
    parse_scenario,
    run_scenario,
)

READS = """\
name: reads
axes:
  - name: x
    parameters: {max_velocity: 500, acceleration: 2000, deceleration: 2000, jerk: 20000}
timeline:
  - {id: on, at: 0, axis: x, command: power}
  - {id: version, at: 0, command: get_version, version_element: 2}
  - {id: pos0, at: 0.001, axis: x, command: read_actual_position}
  - {id: still, at: 0.001, axis: x, command: read_status}
  - {id: write, at: 0.002, axis: x, command: write_parameter, parameter_number: 1004,
     value: 500}
  - {id: acc, at: 0.003, axis: x, command: read_parameter, parameter_number: 1004,
     read_mode: once}
  - {id: limit_on, at: 0.003, axis: x, command: write_bool_parameter, parameter_number: 1015,
     value: true}
  - {id: limit, at: 0.004, axis: x, command: read_bool_parameter, parameter_number: 1015}
  - {id: set, at: 0.004, axis: x, command: read_parameter_set}
  - {id: unknown, at: 0.004, axis: x, command: read_parameter, parameter_number: 999}
  - {id: go, at: 0.01, axis: x, command: move_absolute_or_restart, position: 100,
     velocity: 200}
  - {id: moving, at: 0.05, axis: x, command: read_status}
  - {id: again, at: 0.1, axis: x, command: move_absolute_or_restart, restart: go,
     position: 40, velocity: 100}
  - {id: no_error, when: again.done, axis: x, command: read_axis_error}
  - {id: pos1, when: again.done, axis: x, command: read_actual_position}
checks:
  - {command: still, result: done, output: standstill, value: 1}
  - {command: moving, result: done, output: discrete_motion, value: 1}
  - {command: moving, result: done, output: accelerating, value: 1}
  - {command: acc, result: done, output: value, value: 500}
  - {command: limit, result: done, output: value, value: 1}
  - {command: set, result: done, output: acceleration, value: 500}
  - {command: pos1, result: done, output: position, value: 40, tolerance: 1e-6}
  - {command: no_error, result: done, output: axis_error_id, value: 0}
  - {command: unknown, result: error, error_id: INVALID_PARAMETER_NUMBER}
"""


def rows(result: ScenarioResult) -> dict[str, CommandRow]:
    return {row.id: row for row in result.commands}


@pytest.fixture(scope="module")
def reads() -> ScenarioResult:
    return run_scenario(parse_scenario(READS))


def test_reads_and_parameters_pass_their_checks(reads: ScenarioResult) -> None:
    """TcMC §4.3-§4.11: each block's outputs, read by the checks (D-218)."""
    assert reads.passed, [check for check in reads.checks if not check.passed]


def test_a_query_row_keeps_every_output(reads: ScenarioResult) -> None:
    """§4.4, §4.11: the row's value holds all outputs; the summary lists them."""
    by_id = rows(reads)
    status = by_id["still"].value_detail
    assert "standstill 1" in status and "discrete_motion 0" in status
    fields = [name for name in AxisParameters.__dataclass_fields__]
    assert all(f"{name} " in by_id["set"].value_detail for name in fields)
    summary = reads.summary()
    assert "position 0" in summary and "version " in summary


def test_get_version_reads_openmotions_own_version(reads: ScenarioResult) -> None:
    """TcMC §5.1: element 2 is the minor number (F_GetVersionTcMC, D-217: no axis)."""
    row = rows(reads)["version"]
    assert row.result == "DONE" and row.axis == ""
    assert row.value_detail == f"version {om.plcopen.F_GetVersionTcMC(2)}"


def test_written_acceleration_is_the_default_of_the_later_move(reads: ScenarioResult) -> None:
    """§4.9: MC_WriteParameter(1004) makes 500 the default acceleration of the move."""
    trace = reads.trace
    assert max(trace["x.set_acceleration"]) == pytest.approx(500.0, rel=1e-9)


def test_restart_retargets_the_running_move_as_one_command(reads: ScenarioResult) -> None:
    """TcMC §3.6: a new edge of the same block while it moves retargets the move; both rows
    end with that one command, at the new target."""
    by_id = rows(reads)
    assert by_id["go"].result == by_id["again"].result == "DONE"
    assert by_id["go"].ended_at == by_id["again"].ended_at
    assert reads.trace["x.set_position"][-1] == pytest.approx(40.0, abs=1e-9)
    assert max(reads.trace["x.set_position"]) < 100.0  # it never reached the first target


def test_restart_after_the_move_ended_starts_a_new_move() -> None:
    """§3.6: once the block's move has ended, its new edge starts a move of its own."""
    result = run_scenario(parse_scenario("""\
name: restart
axes: [{name: x}]
timeline:
  - {at: 0, axis: x, command: power}
  - {id: go, at: 0, axis: x, command: move_absolute_or_restart, position: 10, velocity: 100}
  - {id: again, when: go.done, axis: x, command: move_absolute_or_restart, restart: go,
     position: 20, velocity: 100}
"""))
    by_id = rows(result)
    assert by_id["go"].ended_at < by_id["again"].ended_at
    assert result.trace["x.set_position"][-1] == pytest.approx(20.0, abs=1e-9)


@pytest.mark.parametrize(("check", "message"), [
    ("{command: still, result: done, output: moving, value: 1}",
     "'still' has no output 'moving' (outputs: error_stop, disabled,"),
    ("{command: still, result: done, value: 1}",
     "'still' is a query; name the output to compare in 'output'"),
    ("{command: on, result: done, output: position, value: 1}",
     "'on' is no query entry"),
    ("{command: still, result: done, output: standstill}", "'output' needs 'value'"),
])
def test_a_wrong_output_is_a_load_error_and_a_right_one_loads(check: str, message: str) -> None:
    """D-218: ``output`` names an output of a query entry, checked when the file loads."""
    text = """\
name: t
axes: [{name: x}]
timeline:
  - {id: on, at: 0, axis: x, command: power}
  - {id: still, at: 0, axis: x, command: read_status}
checks:
  - CHECK
"""
    with pytest.raises(ScenarioError) as info:
        parse_scenario(text.replace("CHECK", check))
    assert message in str(info.value)
    parse_scenario(text.replace("CHECK", "{command: still, result: done, output: standstill, "
                                         "value: 1}"))


def test_a_restart_of_an_entry_that_is_no_restartable_move_is_refused() -> None:
    """§3.6: only an MC_MoveAbsoluteOrRestart block can be triggered again."""
    with pytest.raises(ScenarioError, match="'on' is not the id of a "
                                            "move_absolute_or_restart entry"):
        parse_scenario("""\
name: t
axes: [{name: x}]
timeline:
  - {id: on, at: 0, axis: x, command: power}
  - {at: 0, axis: x, command: move_absolute_or_restart, restart: on, position: 1, velocity: 1}
""")


def test_a_failed_output_check_says_what_it_saw() -> None:
    """D-218: the check's detail names the output and how far off it was."""
    result = run_scenario(parse_scenario("""\
name: t
axes: [{name: x}]
timeline:
  - {at: 0, axis: x, command: power}
  - {id: pos, at: 0, axis: x, command: read_actual_position}
checks:
  - {command: pos, result: done, output: position, value: 3}
"""))
    assert not result.passed
    assert result.checks[0].detail == "DONE 0, off by -3"
    assert result.checks[0].name == "pos done position value 3 ± 1e-09 at end"
