"""A position sent as an array of numbers becomes its dataclass with its fields' types."""

from __future__ import annotations

import pytest

from openmotion.endpoints import MachineHost, WireError, coerce
from openmotion.examples import examples_dir
from openmotion.planar.positions import PositionXYC


def test_an_int_field_of_a_position_becomes_an_int() -> None:
    host = MachineHost.for_scenario(examples_dir() / "planar_two_movers.yaml", pace="lockstep")
    (target,) = host.command(host.model.find("one"), "move_to_position").inputs
    position = coerce(target, [120.0, 240.0, 90.0, 7.0], host.model)
    assert position == PositionXYC(120.0, 240.0, 90.0, 7)
    assert isinstance(position.reference_id, int)
    with pytest.raises(WireError, match="reference_id takes a whole number"):
        coerce(target, [120.0, 240.0, 90.0, 7.5], host.model)
    assert coerce(target, [0, 0, 0, 0], host.model) == PositionXYC()
