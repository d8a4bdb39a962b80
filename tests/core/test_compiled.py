"""The loops that stand for numpy functions in compiled code give numpy's answers (D-157),
and importing the package compiles nothing."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numba
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numba import njit

from openmotion.core.compiled import OPTIONS, search_right, sort_in_place, true_indices
from openmotion.planar.traffic_kernels import _bounds, group_by_track, in_order

_FLOATS = st.one_of(st.floats(allow_nan=True, allow_infinity=True, width=64),
                    st.sampled_from([0.0, 1.0, -1.0, 2.5]))  # ties


@given(st.lists(_FLOATS, max_size=40), _FLOATS)
def test_search_right_is_numpys(values: list[float], v: float) -> None:
    a = np.sort(np.array(values, dtype=float))
    assert search_right(a, v) == np.searchsorted(a, v, side="right")


@given(st.lists(st.booleans(), max_size=40))
def test_true_indices_are_numpys_flatnonzero(values: list[bool]) -> None:
    mask = np.array(values, dtype=np.bool_)
    assert true_indices(mask).tolist() == np.flatnonzero(mask).tolist()


@given(st.lists(st.one_of(st.floats(min_value=0.0, allow_nan=False, allow_infinity=True),
                          st.just(float("nan")), st.sampled_from([0.0, 1.0, 3.0])),
                max_size=60))
def test_sort_in_place_is_numpys_without_signed_zeros(values: list[float]) -> None:
    a = np.array(values, dtype=float)
    expected = np.sort(a)
    sort_in_place(a)
    assert a.tobytes() == expected.tobytes()


def test_sort_in_place_keeps_equal_values_in_order() -> None:
    a = np.array([3.0, 0.0, np.nan, -0.0, 1.0, 0.0])
    sort_in_place(a)
    assert np.signbit(a[:3]).tolist() == [False, True, False]  # 0.0, -0.0, 0.0 as they came
    assert a[3:5].tolist() == [1.0, 3.0] and np.isnan(a[5])


@njit
def _min_max(x: np.ndarray) -> tuple[float, float]:
    return x.min(), x.max()  # what the traffic's footprint search called before


@given(st.lists(_FLOATS, min_size=1, max_size=30))
def test_bounds_are_compiled_min_and_max(values: list[float]) -> None:
    x = np.array(values, dtype=float)
    assert np.array(_bounds(x)).tobytes() == np.array(_min_max(x)).tobytes()


@given(st.lists(st.tuples(st.integers(0, 5), _FLOATS), max_size=40))
def test_riders_by_track_then_arc_length_are_numpys_lexsort(riders: list) -> None:
    index = np.array([t for t, _ in riders], dtype=np.int64)
    s = np.array([v for _, v in riders], dtype=float)
    place, grouped, tails = group_by_track(index)
    first_met = {t: i for i, t in enumerate(dict.fromkeys(index.tolist()))}  # in order met
    expected = np.array([first_met[t] for t in index.tolist()], dtype=np.int64)
    assert place.tolist() == expected.tolist()
    assert grouped.tolist() == np.argsort(expected, kind="stable").tolist()
    assert tails.tolist() == np.cumsum(np.bincount(expected, minlength=len(first_met))).tolist()
    assert in_order(s, grouped, tails).tolist() == np.lexsort((s, expected)).tolist()


def test_one_set_of_options_for_every_loop() -> None:
    """Mixed options would compile numba's numpy functions once per set (D-157)."""
    assert OPTIONS == {"cache": True, "error_model": "numpy", "no_cfunc_wrapper": True}


def test_importing_the_package_compiles_nothing() -> None:
    """A loop compiles (or loads) at its first call, never at import: a run pays only for
    the loops it uses."""
    code = textwrap.dedent("""
        from numba.core import event
        compiled = []
        class Listener(event.Listener):
            def on_start(self, ev): compiled.append(ev.data["dispatcher"].py_func.__name__)
            def on_end(self, ev): pass
        event.register("numba:compile", Listener())
        import openmotion, openmotion.planar, openmotion.scenario, openmotion.coordinated
        import openmotion.rail.kernels, openmotion.planar.traffic
        print(len(compiled), compiled[:5])
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=dict(os.environ), check=True)
    assert out.stdout.split()[0] == "0", out.stdout


@pytest.mark.skipif(not hasattr(numba.config, "CACHE_LOCATOR_CLASSES"),
                    reason="this numba cannot be told to find no cache folder")
def test_without_a_cache_folder_the_loops_compile_in_every_process() -> None:
    """A read-only install without a writable user cache folder: numba finds nowhere to
    cache; the package still imports and runs, and says once why it is slow."""
    code = textwrap.dedent("""
        import numpy as np
        from openmotion.core.compiled import search_right
        import openmotion.planar.traffic
        print(search_right(np.array([1.0, 2.0, 2.0]), 2.0))
    """)
    env = dict(os.environ, NUMBA_CACHE_LOCATOR_CLASSES="IPythonCacheLocator")  # none fits
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=env, check=True)
    assert out.stdout.strip() == "3"
    assert out.stderr.count("RuntimeWarning: compiled loops are not cached") == 1, out.stderr
