"""The shared numba building blocks (geometry/kernels.py) against numpy: the sorts replace numpy's within kernels."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from omega_prime_visibility.geometry.kernels import INSERTION_RUN, argsort_stable, sorted_values, unique_values

# few distinct values, so that ties (and runs of ties across the insertion runs' borders) are common
FLOATS = hnp.arrays(
    np.float64,
    st.integers(0, 6 * INSERTION_RUN),
    elements=st.sampled_from([-1e300, -2.5, -0.0, 0.0, 1.0, 1.0 + 2e-16, 3.0, np.inf, -np.inf, np.nan]),
)
INTS = hnp.arrays(np.int64, st.integers(0, 6 * INSERTION_RUN), elements=st.integers(-4, 4))


@settings(max_examples=300, deadline=None)
@given(FLOATS)
def test_argsort_stable_is_numpys_stable_argsort(keys: np.ndarray) -> None:
    assert argsort_stable(keys).tolist() == np.argsort(keys, kind="stable").tolist()
    np.testing.assert_array_equal(sorted_values(keys), np.sort(keys))


@settings(max_examples=200, deadline=None)
@given(INTS)
def test_integer_keys_and_unique_values(keys: np.ndarray) -> None:
    assert argsort_stable(keys).tolist() == np.argsort(keys, kind="stable").tolist()
    assert unique_values(keys).tolist() == np.unique(keys).tolist()


def test_long_random_keys() -> None:
    """Many merge passes (up to 2**14 items), random keys with ties."""
    rng = np.random.default_rng(0)
    for n in (INSERTION_RUN + 1, 1000, 2**14 + 3):
        keys = rng.integers(0, n // 3, n).astype(np.float64)
        assert np.array_equal(argsort_stable(keys), np.argsort(keys, kind="stable"))
