"""The sorts of geometry/sorting.py against numpy's: they replace numpy's within kernels, so must give its order."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from omega_prime_visibility.geometry.sorting import (
    INSERTION_RUN,
    RADIX_MIN,
    argsort_floats,
    argsort_stable,
    sorted_values,
    unique_values,
)

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


# the bit patterns a radix sort on the keys' bytes could get wrong: both zeros, subnormals, the extremes, NaN with and
# without its sign bit, and numbers that differ in the lowest byte only
EDGES = np.array(
    [
        *(0.0, -0.0, 5e-324, -5e-324, 2.2e-308, 1.7976931348623157e308, -1.7976931348623157e308, np.inf, -np.inf),
        *(1.0, np.nextafter(1.0, 2.0), np.nextafter(1.0, 0.0), -1.0, np.nextafter(-1.0, 0.0), np.pi, -np.pi),
        *(np.nan, -np.nan, float.fromhex("0x1.0000000000001p+0")),
    ]
)


@settings(max_examples=200, deadline=None)
@given(hnp.arrays(np.float64, st.integers(0, 3 * RADIX_MIN), elements=st.sampled_from(EDGES.tolist())))
def test_argsort_floats_is_numpys_stable_argsort(keys: np.ndarray) -> None:
    """Many ties among the edge cases, around and above the size where the radix sort takes over."""
    assert argsort_floats(keys).tolist() == np.argsort(keys, kind="stable").tolist()


def test_argsort_floats_on_bearings_and_sign_of_nan() -> None:
    rng = np.random.default_rng(1)
    for n in (RADIX_MIN - 1, RADIX_MIN, 600, 5000):
        keys = rng.uniform(-np.pi, np.pi, n)
        keys[rng.integers(0, n, n // 5)] = keys[rng.integers(0, n, n // 5)]  # repeated bearings (shared corners)
        keys[rng.integers(0, n, 3)] = [-0.0, np.nan, 0.0]
        assert np.array_equal(argsort_floats(keys), np.argsort(keys, kind="stable")), n
    negative_nan = np.frombuffer(np.uint64(0xFFF8000000000001).tobytes(), dtype=np.float64)
    keys = np.concatenate([np.full(RADIX_MIN, 1.0), negative_nan, [np.nan, -np.inf]])
    assert np.array_equal(argsort_floats(keys), np.argsort(keys, kind="stable"))
