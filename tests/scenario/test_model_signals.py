"""Every signal of the machine model is a scenario signal (D-234): a CA group's, a planar
part's, which scenario files could not name before, are recorded, checked and waited on like an
axis's, and a wrong name is refused naming the choices."""

from __future__ import annotations

import pytest

from openmotion.scenario import ScenarioError, parse_scenario, run_scenario

CA = """\
name: ca state
duration: 0.05
axes: [{name: a}, {name: b}]
ca_groups: [{name: g, axes: [a]}]
timeline:
  - {id: go, when: g.state == standby, axis: b, command: power}
record: {signals: [g.state, a.gap, a.set_position]}
checks:
  - {signal: g.state, expect: standby, at: end}
  - {signal: g.state, expect: 2, tolerance: 0, when: go.done}
"""


def test_a_ca_group_state_is_recorded_checked_and_waited_on() -> None:
    result = run_scenario(parse_scenario(CA))
    assert result.passed, result.checks
    assert [check.detail for check in result.checks] == ["standby", "standby"]
    assert "g.state" in result.trace.columns
    assert result.trace["g.state"][-1] == result.trace["g.state"][0]  # enabled before t = 0


@pytest.mark.parametrize(("signal", "expected"), [
    ("g.speed", "'g.speed': a CA group's signal is one of state"),
    ("b.gap", "'b' is in no CA group (ca_groups[].axes)"),
    ("part 16#01010020.state",
     "unknown planar part 'part 16#01010020' (planar.environment.parts: none)"),
])
def test_a_wrong_signal_name_names_the_choices(signal: str, expected: str) -> None:
    with pytest.raises(ScenarioError) as info:
        parse_scenario(CA.replace("[g.state, a.gap", f"[{signal}, a.gap"), "bad.yaml")
    assert f"bad.yaml:7: record.signals[0]: {expected}" in str(info.value), str(info.value)
    assert parse_scenario(CA).signals[0] == "g.state"  # a valid file still loads
