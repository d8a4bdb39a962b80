"""Scenario entries of options structs take their fields from the struct (D-235): a field added
to ST_GearInPosCAOptions (the CA move and halt options, the gear-ins on planar tracks) is
reachable from files at once."""

from __future__ import annotations

import dataclasses

import pytest
from pydantic import ValidationError, create_model

from openmotion.core.special_values import MC_DEFAULT, InputValue
from openmotion.planar import ST_GearInPosOnTrackOptions, ST_GearInPosOnTrackWithMasterMoverOptions
from openmotion.scenario.planar_gearing import GearInPosOnTrack, GearInPosOnTrackWithMasterMover
from openmotion.scenario.schema import _Model, option_fields
from openmotion.scenario.transport import GearInPosCa, HaltCa, MoveAbsoluteCa, MoveRelativeCa
from openmotion.transport.blocks import (
    ST_HaltCAOptions,
    ST_MoveAbsoluteCAOptions,
    ST_MoveRelativeCAOptions,
)
from openmotion.transport.enums import SyncMode
from openmotion.transport.gear_blocks import ST_GearInPosCAOptions


@pytest.mark.parametrize(("entry", "options"), [
    (GearInPosCa, ST_GearInPosCAOptions), (MoveAbsoluteCa, ST_MoveAbsoluteCAOptions),
    (MoveRelativeCa, ST_MoveRelativeCAOptions), (HaltCa, ST_HaltCAOptions),
    (GearInPosOnTrack, ST_GearInPosOnTrackOptions),
    (GearInPosOnTrackWithMasterMover, ST_GearInPosOnTrackWithMasterMoverOptions)])
def test_every_option_is_a_field_of_its_entry_with_the_struct_default(entry: type,
                                                                      options: type) -> None:
    for field in dataclasses.fields(options):
        assert field.name in entry.model_fields, field.name
        assert entry.model_fields[field.name].default == field.default, field.name


@dataclasses.dataclass(frozen=True)
class _NewOptions:
    """An options struct as a later manual might extend one."""

    lookahead: InputValue = MC_DEFAULT
    strict: bool = False
    mode: SyncMode = SyncMode.NON_MODULO
    dynamics_reference_system: int = 0


def test_a_new_option_becomes_a_field_typed_by_its_annotation() -> None:
    entry = create_model("Entry", __base__=_Model, **option_fields(
        _NewOptions, skip=("strict",), types={"dynamics_reference_system": int}))
    assert list(entry.model_fields) == ["lookahead", "mode", "dynamics_reference_system"]
    made = entry.model_validate({"lookahead": "MC_DEFAULT", "mode": "positive"})
    assert made.lookahead is MC_DEFAULT and made.mode is SyncMode.POSITIVE
    with pytest.raises(ValidationError, match="must be one of non_modulo"):
        entry.model_validate({"mode": "sideways"})
    with pytest.raises(ValidationError, match="lookahead"):
        entry.model_validate({"lookahead": "soon"})
    assert entry.model_validate({"lookahead": 2.5}).lookahead == 2.5  # still usable
