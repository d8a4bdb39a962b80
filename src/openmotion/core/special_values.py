"""The MC_LREAL special input values of the MC3 libraries (TF5410 §11.2).

They are sentinels, not magic floats: ``velocity=MC_MAXIMUM`` can never be confused with a
number a user typed. TcMC's own convention, 0 = "axis default" for dynamics inputs (TcMC §3.1),
is honoured as well; see ``resolve_dynamic``.
"""

from __future__ import annotations

from typing import Final


class SpecialValue:
    """One reserved input value; compared by identity."""

    __slots__ = ("name",)

    def __init__(self, name: str) -> None:
        self.name = name

    def __repr__(self) -> str:
        return self.name

    def __reduce__(self) -> str:
        return self.name


MC_DEFAULT: Final = SpecialValue("MC_DEFAULT")  #: use the input's default (axis parameter)
MC_MAXIMUM: Final = SpecialValue("MC_MAXIMUM")  #: use the input's maximum (axis parameter)
MC_IGNORE: Final = SpecialValue("MC_IGNORE")  #: the input is ignored
MC_INVALID: Final = SpecialValue("MC_INVALID")  #: must be set by the user; no default exists

#: MC_Home.Position: use the configured calibration value (TcMC §3.14)
DEFAULT_HOME_POSITION: Final = SpecialValue("DEFAULT_HOME_POSITION")

SPECIAL_VALUES: Final = {
    v.name: v for v in (MC_DEFAULT, MC_MAXIMUM, MC_IGNORE, MC_INVALID, DEFAULT_HOME_POSITION)
}

InputValue = float | SpecialValue
