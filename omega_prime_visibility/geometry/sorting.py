"""The sorts the kernels use, written once here instead of numba's ``np.argsort``/``np.sort``/``np.unique`` (whose
quicksort and mergesort are compiled anew for every kind, dtype and layout: several seconds of a first call).

- :func:`insertion_sort`: a few values in place (the cuts of a pair test);
- :func:`argsort_stable`: ``np.argsort(keys, kind="stable")`` of float64 or int64 keys, insertion runs merged;
- :func:`argsort_floats`: the same order for float64 keys, by radix sort where there are many (the sweep's
  bearings);
- :func:`sorted_values`, :func:`unique_values`: ``np.sort`` and ``np.unique``.
"""

from __future__ import annotations

import numpy as np

from .._compiled.kernel import njit


@njit(cache=True, inline="always")
def insertion_sort(values, n):
    """Sort ``values[:n]`` ascending in place, by insertion (fast for the few values of a pair test; inlined, so a
    loop calling it pays no reference counting). Equal values keep their order; without NaN the result is the
    order ``np.sort`` gives, but for ``-0.0`` and ``+0.0``, which it may order either way.

    >>> values = np.array([3.0, 1.0, 2.0, 9.0])
    >>> insertion_sort(values, 3); values.tolist()
    [1.0, 2.0, 3.0, 9.0]
    """
    for a in range(1, n):
        value = values[a]
        b = a - 1
        while b >= 0 and values[b] > value:
            values[b + 1] = values[b]
            b -= 1
        values[b + 1] = value


INSERTION_RUN = 16  # runs of this many items are sorted by insertion before merging


@njit(cache=True, inline="always")
def _after(a, b):
    """Whether key ``a`` sorts after key ``b`` (NaN after every number, as numpy sorts)."""
    return a > b or (a != a and b == b)


@njit(cache=True)
def argsort_stable(keys):
    """Positions that sort ``keys`` ascending, equal keys in their order: ``np.argsort(keys, kind="stable")``.

    Parameters
    ----------
    keys : ndarray, shape (n,)
        Numbers (float64 or int64, C-contiguous: pass ``column.copy()`` for a column of a table); NaN sorts last.

    Returns
    -------
    ndarray, shape (n,), int64

    Examples
    --------
    >>> import numpy as np
    >>> argsort_stable(np.array([2.0, np.nan, 1.0, 2.0, -0.5])).tolist()
    [4, 2, 0, 3, 1]
    """
    n = len(keys)
    order = np.arange(n)
    for lo in range(0, n, INSERTION_RUN):  # runs sorted by insertion ...
        for a in range(lo + 1, min(lo + INSERTION_RUN, n)):
            x = order[a]
            b = a - 1
            while b >= lo and _after(keys[order[b]], keys[x]):
                order[b + 1] = order[b]
                b -= 1
            order[b + 1] = x
    if n <= INSERTION_RUN:
        return order
    other = np.empty(n, dtype=np.int64)
    width = INSERTION_RUN
    while width < n:  # ... then merged bottom-up, between two buffers
        for lo in range(0, n, 2 * width):
            mid, hi = min(lo + width, n), min(lo + 2 * width, n)
            i, j = lo, mid
            for out in range(lo, hi):
                if j >= hi or (i < mid and not _after(keys[order[i]], keys[order[j]])):
                    other[out] = order[i]
                    i += 1
                else:
                    other[out] = order[j]
                    j += 1
        order, other = other, order
        width *= 2
    return order


RADIX_MIN = 128
"""From this many keys on, :func:`argsort_floats` sorts by radix: about twice as fast as the merges at 500 keys (whose
comparisons are branches the processor cannot predict), slower below about a hundred."""

_SIGN = np.uint64(1) << np.uint64(63)
_BYTE = np.uint64(255)


@njit(cache=True)
def argsort_floats(keys):
    """:func:`argsort_stable` of float64 keys (NaN last, ``-0.0`` equal to ``+0.0``, equal keys in their order), by
    a least-significant-byte radix sort from :data:`RADIX_MIN` keys on.

    Each key becomes a 64-bit unsigned integer whose order is the keys' order (the sign bit set on a positive
    number, all bits flipped on a negative one, every zero the integer of ``+0.0`` and every NaN the largest), then
    the positions are distributed by its bytes, the lowest first; a pass whose byte is the same for every key is
    skipped. Each pass keeps the order of the previous one among equal bytes, so the result is the stable order.

    Examples
    --------
    >>> import numpy as np
    >>> keys = np.concatenate([np.linspace(1.0, -1.0, 200), [np.nan, -0.0, 0.0, -np.inf]])
    >>> bool(np.array_equal(argsort_floats(keys), np.argsort(keys, kind="stable")))
    True
    >>> argsort_floats(np.array([2.0, np.nan, 1.0, 2.0, -0.5])).tolist()  # (few keys: argsort_stable)
    [4, 2, 0, 3, 1]
    """
    n = len(keys)
    if n < RADIX_MIN:
        return argsort_stable(keys)
    raw = keys.view(np.uint64)
    bits = np.empty(n, dtype=np.uint64)
    for i in range(n):
        x = keys[i]
        if x != x:
            bits[i] = ~np.uint64(0)
        elif x == 0.0:
            bits[i] = _SIGN
        elif raw[i] & _SIGN:
            bits[i] = ~raw[i]
        else:
            bits[i] = raw[i] | _SIGN
    order = np.arange(n)
    # the buffers of a pass; each pass writes into the other pair, which it then becomes (swapped by copying the
    # references once per pass, outside the loops over keys)
    next_order = np.empty(n, dtype=np.int64)
    next_bits = np.empty(n, dtype=np.uint64)
    count = np.empty(256, dtype=np.int64)
    for byte in range(8):
        shift = np.uint64(8 * byte)
        count[:] = 0
        for i in range(n):
            count[(bits[i] >> shift) & _BYTE] += 1
        if count[(bits[0] >> shift) & _BYTE] == n:
            continue  # the same byte everywhere: this pass would not move anything
        total = 0
        for d in range(256):
            c = count[d]
            count[d] = total
            total += c
        for i in range(n):
            d = (bits[i] >> shift) & _BYTE
            at = count[d]
            count[d] = at + 1
            next_order[at] = order[i]
            next_bits[at] = bits[i]
        order, next_order = next_order, order
        bits, next_bits = next_bits, bits
    return order


@njit(cache=True)
def sorted_values(values):
    """A sorted copy of ``values`` (as :func:`argsort_stable` takes them): ``np.sort(values)``.

    Examples
    --------
    >>> import numpy as np
    >>> sorted_values(np.array([3.0, -1.0, 2.0])).tolist()
    [-1.0, 2.0, 3.0]
    """
    return values[argsort_stable(values)]


@njit(cache=True)
def unique_values(values):
    """The distinct ``values``, ascending: ``np.unique(values)``.

    Examples
    --------
    >>> import numpy as np
    >>> unique_values(np.array([5, 1, 5, 3, 1])).tolist()
    [1, 3, 5]
    """
    ordered = sorted_values(values)
    keep = np.ones(len(ordered), dtype=np.bool_)
    for i in range(1, len(ordered)):
        keep[i] = ordered[i] != ordered[i - 1]
    return ordered[keep]
