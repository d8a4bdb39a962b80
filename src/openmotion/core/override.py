"""The velocity override in one meaning: a fraction 0...1 inside (``Axis.override``, the
planners' factor). The edges keep the manual's units and convert here, once: percent at the
FB inputs (MC_Power.Override, MC_SetOverride, TcMC §3.x/§4.x) and in traces; the PlcToNc
DWORD 0...1 000 000 of the cyclic interface (TcMC §4.1) and MC_OverrideFilter (§4.19)."""

PERCENT = 100.0  #: percent at a fraction of 1 (override 100 %)
DWORD_FULL_SCALE = 1_000_000  #: the PlcToNc override DWORD at 100 %


def fraction_from_percent(percent: float) -> float:
    """An FB's Override [%] as the fraction the axis runs with."""
    return percent / PERCENT


def percent_from_fraction(fraction: float) -> float:
    """The axis' override fraction in percent, as FBs and traces show it."""
    return fraction * PERCENT


def dword_from_fraction(fraction: float) -> int:
    """The override fraction as the PlcToNc DWORD: 0.5 (50 %) gives 500 000."""
    return round(fraction * DWORD_FULL_SCALE)
