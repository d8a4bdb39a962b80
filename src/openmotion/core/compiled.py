"""How openmotion compiles its loops (numba): one set of options for every kernel.

Every compiled loop of the package is decorated with ``compiled``: cached on disk next to its
module (numba's ``cache=True``), with numpy's error model (a float division by zero gives inf
or nan, as the numpy formulation each loop replaced did, instead of raising). One set of
options matters for the cost of the first run: numba compiles the numpy functions a loop
calls (``np.empty``, ``np.zeros``...) once per set of options, so loops with mixed options
would compile them twice (D-157).

Nothing is compiled at import: a loop compiles (or loads from the cache) with the argument
types of its first call. ``inline=True`` is for small helpers that callers pass constants
to: numba would compile a separate copy for each constant (a ``Literal`` type), while an
inlined helper is typed as part of its caller.

``search_right`` and ``sort_in_place`` stand for ``numpy.searchsorted`` and ``numpy.sort``
in the loops: numba's own versions cost more to compile (about a second on the first run)
than the few lines do.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np
from numba import njit
from numpy.typing import NDArray

F = TypeVar("F", bound=Callable[..., Any])

#: numba.njit's options; no loop is passed as a first-class function, so none needs the C
#: callback wrapper numba would otherwise build (a tenth of the compile time)
OPTIONS: dict[str, Any] = {"cache": True, "error_model": "numpy", "no_cfunc_wrapper": True}


def compiled(func: F | None = None, *, inline: bool = False) -> Any:
    """``numba.njit`` with the package's options (``OPTIONS``); ``inline``: typed and inlined
    into each compiled caller (numba's ``inline="always"``) rather than compiled apart."""
    options = dict(OPTIONS, inline="always") if inline else dict(OPTIONS)

    def decorate(function: F) -> Any:
        try:
            return njit(**options)(function)
        except RuntimeError as exc:  # no folder to cache in: compile in every process
            if "no locator available" not in str(exc):
                raise
            _warn_uncached(exc)
            return njit(**dict(options, cache=False))(function)

    return decorate if func is None else decorate(func)


_warned = False  #: ``_warn_uncached`` said it once


def _warn_uncached(exc: RuntimeError) -> None:
    """numba finds no writable folder for its cache (the package's ``__pycache__``, then the
    user's cache folder): the loops still run, but every process compiles them again."""
    global _warned
    if not _warned:
        _warned = True
        warnings.warn(f"compiled loops are not cached, every run compiles them ({exc}); set "
                      "NUMBA_CACHE_DIR to a writable folder", RuntimeWarning, stacklevel=4)


@compiled
def search_right(a: NDArray[np.float64], v: float) -> int:
    """``numpy.searchsorted(a, v, side="right")`` for a sorted ``a``: numba's binary search,
    NaN sorting last."""
    lo, hi = 0, a.size
    while lo < hi:
        mid = lo + ((hi - lo) >> 1)
        if math.isnan(v) or a[mid] <= v:
            lo = mid + 1
        else:
            hi = mid
    return lo


@compiled
def true_indices(mask: NDArray[np.bool_]) -> NDArray[np.int64]:
    """``numpy.flatnonzero(mask)``: the indices where ``mask`` holds, ascending."""
    found = np.empty(mask.size, dtype=np.int64)
    count = 0
    for k in range(mask.size):
        if mask[k]:
            found[count] = k
            count += 1
    return found[:count]


@compiled
def sort_in_place(a: NDArray[np.float64]) -> None:
    """Sort ``a`` ascending, NaN last, as ``numpy.sort``: by insertion (stable), quick on the
    few sorted runs the loops join. Equal values keep their order, so an array with both 0.0
    and -0.0 may come out in another order than numpy's."""
    for i in range(1, a.size):
        value = a[i]
        j = i
        while j > 0 and (value < a[j - 1] or (math.isnan(a[j - 1]) and not math.isnan(value))):
            a[j] = a[j - 1]
            j -= 1
        a[j] = value
