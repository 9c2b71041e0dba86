"""The kernel decorator (_compiled/kernel.py): a kernel is numba's dispatcher to numba and to its callers, made on
first need; the argument types it matches against the ahead-of-time build are numba's own."""

from __future__ import annotations

import pickle

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from omega_prime_visibility._compiled.ahead_build import type_key
from omega_prime_visibility._compiled.kernel import Kernel, njit, value_key
from omega_prime_visibility.geometry import sorting


@njit(cache=False, inline="always")
def _scaled(value, factor=2.0):
    return value * factor


@njit(cache=False)
def _sum_scaled(values, factor):
    total = 0.0
    for v in values:
        total += _scaled(v, factor)
    return total


@njit(cache=False)
def _with_default(values, offset=1.5):
    return values + offset


def test_kernels_call_kernels_as_numba_functions() -> None:
    # (1 + 2 + 3) * 3: the inlined kernel called from a kernel, both compiled by numba
    assert _sum_scaled(np.array([1.0, 2.0, 3.0]), 3.0) == 18.0
    assert isinstance(_sum_scaled, Kernel) and isinstance(_sum_scaled.dispatcher, numba.core.registry.CPUDispatcher)
    assert len(_sum_scaled.signatures) == 1  # (the dispatcher's own attributes)


def test_defaults_and_keywords_reach_the_function() -> None:
    values = np.array([1.0, -2.0])
    assert _with_default(values).tolist() == [2.5, -0.5]
    assert _with_default(values, 0.25).tolist() == [1.25, -1.75]
    assert _with_default(values, offset=-1.0).tolist() == [0.0, -3.0]
    assert _with_default.py_func(values).tolist() == [2.5, -0.5]


def test_a_kernel_pickles_as_itself_and_reads_as_its_function() -> None:
    assert pickle.loads(pickle.dumps(sorting.sorted_values)) is sorting.sorted_values
    assert sorting.sorted_values.__name__ == "sorted_values"
    assert sorting.sorted_values.__module__ == "omega_prime_visibility.geometry.sorting"
    assert "np.sort" in sorting.sorted_values.__doc__
    assert repr(sorting.sorted_values) == "<kernel omega_prime_visibility.geometry.sorting.sorted_values>"
    with pytest.raises(AttributeError):
        _ = sorting.sorted_values.__no_such_attribute__


def test_a_kernel_is_numbas_dispatcher_to_numba() -> None:
    assert numba.typeof(_scaled) == numba.types.Dispatcher(_scaled.dispatcher)


DTYPES = [np.bool_, np.int8, np.int32, np.int64, np.uint8, np.uint64, np.float32, np.float64, np.complex128]


@st.composite
def arrays(draw):
    """Arrays as kernels get them: any of the dtypes, 0 to 3 dimensions, sliced, transposed or read-only."""
    dtype = draw(st.sampled_from(DTYPES))
    shape = draw(hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4))
    array = np.zeros(shape, dtype=dtype)
    if array.ndim and draw(st.booleans()):
        array = array[tuple(slice(None, None, draw(st.sampled_from([1, 2, -1]))) for _ in shape)]
    if array.ndim > 1 and draw(st.booleans()):
        array = array.T
    if draw(st.booleans()):
        array.flags.writeable = False
    return array


scalars = st.one_of(
    st.booleans(),
    st.integers(-(2**63), 2**63 - 1),
    st.floats(allow_nan=True),
    st.none(),
    st.sampled_from([np.float64(1.5), np.float32(2.0), np.int32(-3), np.int64(7), np.uint8(9), np.bool_(True)]),
)
values = st.recursive(st.one_of(scalars, arrays()), lambda inner: st.tuples(inner, inner), max_leaves=4)


@settings(max_examples=300, deadline=None)
@given(values)
def test_argument_types_are_numbas(value) -> None:
    # the key a value is matched by is the one of the type numba gives it: the build runs only where numba would
    # run the same machine code
    assert value_key(value) == type_key(numba.typeof(value))


def test_values_the_build_never_takes() -> None:
    unaligned = np.frombuffer(bytes(17), dtype=np.uint8)[1:].view(np.float64)
    assert not unaligned.flags.aligned
    assert value_key(unaligned) != type_key(numba.typeof(unaligned))  # (numba's type says aligned: not the build's)
    for value in ([1.0], "text", 2**64, np.zeros(2, dtype=">f8"), np.zeros(2, dtype=[("a", "f8")]), 1j):
        assert value_key(value) is None
    assert value_key((1.0, [2])) is None
