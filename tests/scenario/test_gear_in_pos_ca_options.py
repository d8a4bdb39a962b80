"""Every option of MC_GearInPosCA from scenario files (TF5410 §9.1.2.1, §8.1.4; issue 20:
"GearInPosCA options except the gap mode are unreachable")."""

from __future__ import annotations

import inspect

import pytest

from openmotion.core.errors import ConfigError
from openmotion.scenario import parse_scenario, run_scenario
from openmotion.scenario.transport import CaGroupParametersSpec, GearInPosCa
from openmotion.transport import CaGroup, CaGroupParameters

ISSUE_CASE = """\
name: gear options
duration: 3.0
axes:
  - {name: belt}
  - {name: m1, position: 0.0}
ca_groups:
  - {name: xts, axes: [m1], parameters: {rail_is_ring: false, rail_length: 10000.0,
     gear_in_pos_default_dynamics_after_sync: maximum_slave_dynamics}}
timeline:
  - {at: 0, axis: belt, command: power}
  - {at: 0, axis: belt, command: move_velocity, velocity: 200.0}
  - {id: sync, at: 0, axis: m1, command: gear_in_pos_ca, master: belt,
     master_sync_position: 1000.0, slave_sync_position: 500.0, sync_strategy: early,
     velocity: 500.0, OPTIONS}
record:
  signals: [belt.set_position, m1.set_position, m1.set_velocity]
checks:
  - {name: in sync, signal: m1.set_position, expect: 12.750889359326493, tolerance: 1.0e-6,
     when: sync.in_gear}
  - {name: never backwards, signal: m1.set_velocity, min: 0.0, at: always}
"""


def test_direction_reversal_from_a_file_waits_and_syncs_forwards() -> None:
    """The issue's case as a file: with direction_reversal_allowed false the mover stands,
    then syncs forwards, in sync at 12.75 (belt at 512.75), never backwards (D-204)."""
    result = run_scenario(parse_scenario(ISSUE_CASE.replace(
        "OPTIONS", "direction_reversal_allowed: false")))
    assert result.passed, result.checks
    row = next(r for r in result.commands if r.id == "sync")
    assert row.result == "BUSY"  # GearInPosCA never ends Done


def test_the_fastest_sync_from_a_file_goes_backwards() -> None:
    result = run_scenario(parse_scenario(ISSUE_CASE.replace(
        "OPTIONS", "minimal_slave_position: MC_IGNORE")))
    failed = {check.name for check in result.checks if not check.passed}
    assert failed == {"in sync", "never backwards"}


def test_every_option_of_the_entry_reaches_the_group_call(monkeypatch: pytest.MonkeyPatch
                                                          ) -> None:
    """Each non-default option of a gear_in_pos_ca entry arrives at CaGroup.gear_in_pos."""
    options = {
        "after_sync_velocity": 1500.0, "after_sync_acceleration": 2000.0,
        "after_sync_deceleration": 1000.0, "after_sync_jerk": 20000.0,
        "master_velocity_undershoot_allowed": False, "minimal_slave_position": -1.0,
        "direction_reversal_allowed": False, "override_slave_dynamic_restrictions": True,
        "gap_control_mode": "fast", "master_signal_correction": "none",
    }
    text = ", ".join(f"{k}: {str(v).lower() if isinstance(v, bool) else v}"
                     for k, v in options.items())
    seen: dict = {}
    original = CaGroup.gear_in_pos

    def spy(self: CaGroup, master: object, slave: object, **kwargs: object) -> object:
        seen.update(kwargs)
        return original(self, master, slave, **kwargs)

    monkeypatch.setattr(CaGroup, "gear_in_pos", spy)
    run_scenario(parse_scenario(ISSUE_CASE.replace("OPTIONS", text).replace("3.0", "0.01")))
    for name, value in options.items():
        got = seen[name]
        assert (got.name.lower() if hasattr(got, "name") else got) == value, name


def test_the_entry_has_a_field_for_every_parameter_of_the_group_method() -> None:
    """Kept true as the API grows: gear_in_pos_ca reaches every input and option."""
    parameters = set(inspect.signature(CaGroup.gear_in_pos).parameters) - {"self", "slave"}
    assert parameters <= set(GearInPosCa.model_fields)
    assert set(CaGroupParametersSpec.model_fields) == {
        name for name in inspect.signature(CaGroupParameters).parameters}


@pytest.mark.parametrize(("option", "message"), [
    ("master_signal_correction: sideways", "master_signal_correction"),
    ("direction_reversal_allowed: 0", "direction_reversal_allowed"),
    ("after_sync_jerk: fast", "after_sync_jerk"),
    ("slave_sync_position_reference_system: -1", "slave_sync_position_reference_system"),
])
def test_a_bad_option_is_a_config_error_naming_it(option: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        parse_scenario(ISSUE_CASE.replace("OPTIONS", option))


def test_a_reference_system_other_than_the_motor_path_fails_the_command() -> None:
    """Accepted by the file (an OTCID), refused by the command as by the block (D-207)."""
    result = run_scenario(parse_scenario(ISSUE_CASE.replace(
        "OPTIONS", "dynamics_reference_system: 31").replace("3.0", "0.01")))
    row = next(r for r in result.commands if r.id == "sync")
    assert row.result == "ERROR" and "dynamics_reference_system" in row.message
