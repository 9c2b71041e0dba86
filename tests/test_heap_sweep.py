"""The sweep's step 3 (engines/sweep/heap_sweep.py) on its own: the intervals it returns against the pieces' distances
computed directly along each interval's middle direction, on piece tables made by steps 1 and 2 from random scenes
of boxes (overlapping, duplicated, crossing, and in map coordinates)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from conftest import boxes_table
from hypothesis import given, settings
from hypothesis import strategies as st

from omega_prime_visibility.engines.sweep import SweepEngine
from omega_prime_visibility.engines.sweep.heap_sweep import nearest_intervals, piece_reach, unhidden_by_top
from omega_prime_visibility.engines.sweep.pieces import (
    EX,
    EY,
    HI,
    LO,
    NUM,
    FrameEdges,
    StaticEdges,
    crossing_cuts,
    cut_pieces,
    front_facing_edges,
    shifted_object_edges,
)
from omega_prime_visibility.geometry.occlusion import MIN_PIECE
from omega_prime_visibility.inputs.scene import load_objects
from omega_prime_visibility.inputs.statics import load_static_occluders


def piece_table(boxes: list[tuple[float, float, float, float, float]], offset: float = 0.0) -> np.ndarray:
    """Steps 1 and 2 for an observer at ``(offset, offset)`` among ``boxes`` (x, y, length, width, yaw, shifted by
    ``offset`` too): the pieces the sweep is given."""
    table = boxes_table([(x + offset, y + offset, length, width, yaw) for x, y, length, width, yaw in boxes])
    frame = load_objects(table, on_invalid="raise").frame_objects(0)
    engine = SweepEngine(load_static_occluders(None))
    observer = np.array([[offset, offset]])
    fields, ang = engine._frame_inputs(frame, observer)
    edges, statics = FrameEdges(*fields), StaticEdges(*engine._static_edges)
    seg = shifted_object_edges(edges.coords, edges.following, offset, offset)
    see_through = np.zeros(len(frame), dtype=bool)
    kept, record_edge, records = front_facing_edges(
        seg, ang[0], edges, statics, see_through, np.zeros(0, dtype=bool), offset, offset, np.inf,
        np.zeros(0, dtype=np.int64),
    )  # fmt: skip
    cut_offsets, cuts = crossing_cuts(kept, record_edge, records, edges.cross_first, edges.cross_second)
    pieces, _ = cut_pieces(kept, record_edge, records, cut_offsets, cuts)
    return pieces


def distances(pieces: np.ndarray, theta: float) -> np.ndarray:
    """Each piece's distance (metres) along the bearing ``theta``, inf where its bearings do not cover it."""
    dx, dy = np.cos(theta), np.sin(theta)
    with np.errstate(divide="ignore", invalid="ignore"):  # (a piece seen edge-on along theta: not hit)
        d = pieces[:, NUM] / (dx * pieces[:, EY] - dy * pieces[:, EX])
    return np.where((pieces[:, LO] <= theta) & (theta <= pieces[:, HI]) & (d > 0), d, np.inf)


def check_sweep(pieces: np.ndarray) -> None:
    lo, hi, top, tie_offsets, ties = nearest_intervals(pieces, True)
    assert np.all(lo <= hi) and np.all(np.diff(lo) >= 0) and np.all(hi[:-1] <= lo[1:])
    # the intervals cover exactly the bearings some piece covers
    events = np.unique(np.concatenate([pieces[:, LO], pieces[:, HI]]))
    covered = [(a, b) for a, b in itertools.pairwise(events) if distances(pieces, 0.5 * (a + b)).min() < np.inf]
    assert [(float(a), float(b)) for a, b in zip(lo, hi, strict=True) if b > a] == [
        (float(a), float(b)) for a, b in covered
    ]
    for q in range(len(lo)):
        if hi[q] - lo[q] < 1e-6:  # (the middle of a sliver is no clear witness)
            continue
        d = distances(pieces, 0.5 * (lo[q] + hi[q]))
        assert d[top[q]] <= d.min() * (1 + 1e-9), "the top is the nearest piece"
        listed = set(ties[tie_offsets[q] : tie_offsets[q + 1]].tolist())
        for p in listed:  # a tie is a piece the top does not hide along some of the interval
            a, b = unhidden_by_top(pieces, top[q], p, lo[q], hi[q])
            assert b - a >= MIN_PIECE
        coincident = np.flatnonzero(np.abs(d - d[top[q]]) <= 1e-12 * d[top[q]])
        assert set(coincident.tolist()) - {int(top[q])} <= listed, "a piece on the top's own line ties with it"


BOX = st.tuples(
    st.floats(-30, 30), st.floats(-12, 12), st.floats(1, 15), st.floats(0.5, 4), st.floats(-np.pi, np.pi)
).filter(lambda b: np.hypot(b[0], b[1]) > b[2] + b[3])  # (none contains the observer)


@settings(max_examples=150, deadline=None)
@given(st.lists(BOX, min_size=1, max_size=25), st.integers(0, 3), st.sampled_from([0.0, 3.0e5]))
def test_the_top_of_every_interval_is_the_nearest_piece(boxes, duplicates, offset) -> None:
    """Random boxes (they may overlap and cross), some of them twice (coincident pieces that must tie), the
    observer at the origin or in map coordinates."""
    check_sweep(piece_table(boxes + boxes[:duplicates], offset))


def test_a_long_side_beside_the_observer_ties_with_its_duplicate_only() -> None:
    # a truck in the next lane and its duplicate, a car in front of both: the truck's long side is nearer to its line
    # than the car is (so the line's distance cannot tell that the car hides it); its nearest point is not
    boxes = [(20.0, 3.5, 16.0, 2.5, 0.0), (20.0, 3.5, 16.0, 2.5, 0.0), (8.0, 1.6, 4.5, 1.9, 0.0)]
    pieces = piece_table(boxes)
    check_sweep(pieces)
    farthest, nearest = piece_reach(pieces)
    assert np.all(nearest <= farthest) and np.all(nearest > 0)


@pytest.mark.parametrize("n", [1, 50, 400])
def test_many_pieces_ending_at_one_bearing(n: int) -> None:
    # a fan of boxes whose ends share bearings (a checkerboard along a ray): the ends leave the heap of active pieces
    # in the order of a stable sort of all ends
    boxes = [(10.0 + 3 * k, 0.0, 2.0, 2.0, 0.0) for k in range(n)] + [
        (10.0 + 3 * k, 4.0, 2.0, 2.0, 0.0) for k in range(n)
    ]
    check_sweep(piece_table(boxes))


def test_a_piece_of_no_width_changes_nothing_and_a_bearing_that_is_no_number_is_refused() -> None:
    pieces = piece_table([(10.0, 0.0, 4.0, 2.0, 0.3), (20.0, 2.0, 4.0, 2.0, 0.0), (15.0, -3.0, 6.0, 2.0, 1.0)])
    point = pieces[1:2].copy()
    point[0, HI] = point[0, LO]  # it ends where it starts
    plain = nearest_intervals(pieces, True)
    with_point = nearest_intervals(np.concatenate([pieces, point]), True)
    for a, b in zip(plain, with_point, strict=True):
        assert np.array_equal(a, b)
    broken = pieces.copy()
    broken[0, LO] = np.nan
    with pytest.raises(ValueError, match="not a number"):
        nearest_intervals(broken, True)
