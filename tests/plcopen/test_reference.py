"""MC_SetReferenceFlag (TcMC §4.15; rule 114), MC_ReadAxisComponents (§4.9; Open Q25) and
F_GetVersionTcMC (§5.1; rule 142)."""

from __future__ import annotations

import pytest

import openmotion as om
from openmotion.plcopen.reference import MC_ReadAxisComponents, MC_SetReferenceFlag
from openmotion.plcopen.version import F_GetVersionTcMC

# -- MC_SetReferenceFlag --------------------------------------------------------------------------


def test_set_reference_flag_true_and_false_set_homed() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    assert not axis.homed
    fb = MC_SetReferenceFlag()
    fb(axis, execute=True, reference_flag=True)
    assert axis.homed
    assert fb.done and not fb.busy and not fb.error
    fb(axis, execute=False)
    fb(axis, execute=True, reference_flag=False)
    assert not axis.homed
    assert fb.done


def test_set_reference_flag_needs_no_power_and_does_not_move() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x", position=12.5)
    fb = MC_SetReferenceFlag()
    fb(axis, execute=True, reference_flag=True)
    rt.run(0.01)
    assert axis.homed
    assert axis.position == 12.5 and axis.set_position == 12.5


def test_set_reference_flag_done_shows_one_cycle_on_a_pulse() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    fb = MC_SetReferenceFlag(axis)
    history = []
    for i in range(5):  # Execute TRUE for one cycle only
        fb(execute=i == 0, reference_flag=True)
        history.append((fb.busy, fb.done, fb.error))
        rt.step()
    assert history[0] == (False, True, False)  # Done in the cycle of the edge
    assert all(h == (False, False, False) for h in history[1:])  # and for that cycle only
    assert axis.homed


def test_set_reference_flag_only_on_the_rising_edge() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    fb = MC_SetReferenceFlag()
    fb(axis, execute=True, reference_flag=True)
    axis.homed = False  # someone else clears it
    fb(axis, execute=True, reference_flag=True)  # level, not edge: nothing happens
    assert not axis.homed


def test_set_reference_flag_after_a_completed_home_can_clear_it() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x", reference_mode=om.ReferenceMode.DIRECT)
    assert axis.power()
    home = axis.home()
    rt.run_until(home)
    assert home.done and axis.homed
    fb = MC_SetReferenceFlag()
    fb(axis, execute=True, reference_flag=False)
    assert fb.done
    assert not axis.homed


# -- MC_ReadAxisComponents ------------------------------------------------------------------------


def test_read_axis_components_returns_the_configured_values() -> None:
    rt = om.Runtime()
    drive = om.DriveModel(model="lag", time_constant=0.01, dead_time=0.002)
    axis = rt.add_axis(
        "x", drive=drive, sync_pulse_distance=4.0, sync_pulse_offset=1.5,
        reference_mode=om.ReferenceMode.SYNC_PULSE, encoder_scaling_factor=0.001,
        max_position_lag=2.5, position_lag_filter_time=0.05,
        enable_position_lag_monitoring=False,
    )
    fb = MC_ReadAxisComponents()
    assert fb.axis_components == {}
    fb(axis, execute=True)
    assert fb.done and not fb.busy and not fb.error
    c = fb.axis_components
    assert set(c) == {"encoder", "drive", "controller"}
    assert c["encoder"]["sync_pulse_distance"] == 4.0
    assert c["encoder"]["sync_pulse_offset"] == 1.5
    assert c["encoder"]["reference_mode"] is om.ReferenceMode.SYNC_PULSE
    assert c["encoder"]["scaling_factor"] == 0.001
    assert c["drive"] == {"model": "lag", "time_constant": 0.01, "dead_time": 0.002}
    assert c["controller"]["enable_position_lag_monitoring"] is False
    assert c["controller"]["max_position_lag"] == 2.5
    assert c["controller"]["position_lag_filter_time"] == 0.05


def test_read_axis_components_is_a_snapshot_kept_after_execute_falls() -> None:
    rt = om.Runtime()
    axis = rt.add_axis("x")
    fb = MC_ReadAxisComponents()
    fb(axis, execute=True)
    assert fb.axis_components["drive"]["model"] == "ideal"
    assert fb.axis_components["encoder"]["sync_pulse_distance"] == 10.0
    axis.parameters.max_position_lag = 9.0
    fb(axis, execute=True)  # no new edge: the snapshot stays
    assert fb.axis_components["controller"]["max_position_lag"] == 5.0
    fb(axis, execute=False)
    fb(axis, execute=False)
    assert not fb.done
    assert fb.axis_components["controller"]["max_position_lag"] == 5.0
    fb(axis, execute=True)
    assert fb.axis_components["controller"]["max_position_lag"] == 9.0


@pytest.mark.parametrize("block", [MC_SetReferenceFlag, MC_ReadAxisComponents])
def test_commands_are_timed_at_the_runtime_now(block: type) -> None:
    """The Done command carries the cycle time of the rising edge, not 0.0."""
    rt = om.Runtime()
    axis = rt.add_axis("x")
    rt.run(1.0)
    fb = block()
    fb(axis, execute=True)
    assert fb.done
    assert fb.command.issued_at == fb.command.ended_at == rt.now == pytest.approx(1.0)


def test_blocks_without_an_axis_are_a_type_error() -> None:
    with pytest.raises(TypeError, match="needs an axis"):
        MC_ReadAxisComponents()(execute=True)


# -- F_GetVersionTcMC -----------------------------------------------------------------------------


def test_version_elements_are_the_parts_of_openmotion_version() -> None:
    major, minor, revision = (int(part) for part in om.__version__.split(".")[:3])
    assert F_GetVersionTcMC(1) == major
    assert F_GetVersionTcMC(2) == minor
    assert F_GetVersionTcMC(3) == revision


@pytest.mark.parametrize("element", [0, 4, -1, 100, True])
def test_other_version_elements_give_0(element: int) -> None:
    assert F_GetVersionTcMC(element) == 0


def test_version_suffixes_are_ignored(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(om, "__version__", "2.10rc1")
    assert (F_GetVersionTcMC(1), F_GetVersionTcMC(2), F_GetVersionTcMC(3)) == (2, 10, 0)
