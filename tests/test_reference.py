"""Tests of the brute-force reference itself, against answers derived on paper."""

from __future__ import annotations

import numpy as np
import pytest
from reference import (
    angular_extent_reference,
    geometry_segments,
    nearest_hit_distances,
    random_box,
    random_scene,
    random_static,
    reference_visibility,
)
from shapely import affinity
from shapely.geometry import LineString, MultiLineString, MultiPolygon, Point, Polygon, box

N = 4000
TOL = 2.0 / N  # discretisation error of the fractions is ~1/n


# ----------------------------------------------------------------------------------------------
# Angular extent
# ----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("d", [1.0, 3.0, 10.0, 57.0])
def test_extent_unit_square_near_face_at_d(d):
    # Near face at x = d, y in [-0.5, 0.5]: the extreme rays go through the near corners.
    start, width = angular_extent_reference([0.0, 0.0], box(d, -0.5, d + 1.0, 0.5))
    assert width == pytest.approx(2 * np.arctan(0.5 / d), rel=1e-12)
    assert start == pytest.approx(-np.arctan(0.5 / d), rel=1e-12)


@pytest.mark.parametrize("d", [2.0, 10.0, 57.0])
def test_extent_unit_square_centred_at_d(d):
    # Centred at distance d: the near corners are at x = d - 0.5, hence atan(0.5 / (d - 0.5)).
    res = reference_visibility([0.0, 0.0], [box(d - 0.5, -0.5, d + 0.5, 0.5)], n_rays=N)
    assert res.visibility[0] == 1.0
    assert res.occluders == [{}] and res.static_occluders == [{}]
    assert res.angular_extent[0] == pytest.approx(2 * np.arctan(0.5 / (d - 0.5)), rel=1e-12)


def test_extent_straddling_wrap_and_observer_offset():
    o = np.array([12.0, -7.0])
    sq = box(o[0] - 11.0, o[1] - 0.5, o[0] - 10.0, o[1] + 0.5)  # directly at -x
    start, width = angular_extent_reference(o, sq)
    a = np.arctan(0.5 / 10.0)
    assert width == pytest.approx(2 * a, rel=1e-12)
    assert start == pytest.approx(np.pi - a, rel=1e-12)
    assert start + width > np.pi  # straddles the wrap; naive min/max of atan2 would give ~2*pi


def test_extent_large_nonconvex_polygon_wrapping():
    # A "C" shape around the observer (opening towards +x) covers more than pi but less than 2*pi.
    c_shape = Polygon([(3, -1), (3, -3), (-3, -3), (-3, 3), (3, 3), (3, 1), (2, 1), (2, 2), (-2, 2),
                       (-2, -2), (2, -2), (2, -1)])  # fmt: skip
    start, width = angular_extent_reference([0.0, 0.0], c_shape)
    assert width == pytest.approx(2 * np.pi - 2 * np.arctan(1 / 3), rel=1e-12)
    assert start == pytest.approx(np.arctan(1 / 3), rel=1e-12)


def test_extent_matches_full_circle_ray_scan():
    rng = np.random.default_rng(1)
    for _ in range(20):
        o = rng.uniform(-5, 5, 2)
        poly = random_box(rng, o + rng.uniform(-30, 30, 2))
        if poly.intersects(Point(o)):
            continue
        start, width = angular_extent_reference(o, poly)
        angles = np.linspace(-np.pi, np.pi, 20001)
        hit = np.isfinite(nearest_hit_distances(o, [poly], angles)[:, 0])
        inside = (angles - start) % (2 * np.pi) <= width
        step = angles[1] - angles[0]
        # Disagreement only possible within one step of the extent's ends.
        near_end = np.minimum(
            np.abs((angles - start + np.pi) % (2 * np.pi) - np.pi),
            np.abs((angles - start - width + np.pi) % (2 * np.pi) - np.pi),
        )
        assert np.all((hit == inside) | (near_end < step))


def test_extent_rejects_observer_inside():
    with pytest.raises(ValueError):
        angular_extent_reference([0.5, 0.5], box(0, 0, 1, 1))
    with pytest.raises(ValueError):
        angular_extent_reference([1.0, 0.5], box(0, 0, 1, 1))  # on the boundary


# ----------------------------------------------------------------------------------------------
# Visibility on paper
# ----------------------------------------------------------------------------------------------


def test_wall_covering_half_the_extent():
    target = box(10, -0.5, 11, 0.5)
    wall = LineString([(5, 0), (5, -5)])  # covers directions [-pi/4, 0]: the lower half of the extent
    res = reference_visibility([0, 0], [target], [wall], n_rays=N)
    assert res.visibility[0] == pytest.approx(0.5, abs=TOL)
    assert res.static_occluders[0].keys() == {0}
    assert res.static_occluders[0][0] == pytest.approx(0.5, abs=TOL)
    assert res.occluders == [{}]


def test_wall_behind_target_does_not_occlude():
    target = box(10, -0.5, 11, 0.5)
    walls = [LineString([(20, -5), (20, 5)]), MultiLineString([[(11, -3), (11, 3)], [(30, 0), (40, 0)]])]
    res = reference_visibility([0, 0], [target], walls, n_rays=N)
    assert res.visibility[0] == 1.0
    assert res.static_occluders == [{}]


def test_target_fully_behind_bigger_box():
    target = box(20, -1, 24, 1)
    big = box(8, -3, 12, 3)
    res = reference_visibility([0, 0], [target, big], n_rays=N)
    assert res.visibility[0] == 0.0
    assert res.occluders[0] == {1: 1.0}
    assert res.visibility[1] == 1.0
    assert res.occluders[1] == {}


def test_partial_occlusion_by_box_exact_fraction():
    # Target near face x=10, y in [-1, 1]; occluder near face x=5, y in [0, 3] -> blocks [0, a/2 of extent].
    target = box(10, -1, 12, 1)
    occ = box(5, 0, 6, 3)
    res = reference_visibility([0, 0], [target, occ], n_rays=N)
    assert res.visibility[0] == pytest.approx(0.5, abs=TOL)
    assert res.occluders[0][1] == pytest.approx(0.5, abs=TOL)


def test_two_occluders_union_not_sum():
    target = box(10, -1, 12, 1)
    a = box(5, -0.25, 6, 0.5)  # blocks directions with y/x in [-0.05, 0.1] (at x=5)
    b = box(4, 0, 4.5, 0.6)  # blocks y/x in [0, 0.15] (near face at x=4)
    res = reference_visibility([0, 0], [target, a, b], n_rays=N)
    half = np.arctan(0.1)
    frac = lambda lo, hi: (np.arctan(hi) - np.arctan(lo)) / (2 * half)  # noqa: E731
    assert res.occluders[0][1] == pytest.approx(frac(-0.05, 0.1), abs=TOL)
    assert res.occluders[0][2] == pytest.approx(frac(0.0, 0.1), abs=TOL)  # clipped to the extent
    assert res.visibility[0] == pytest.approx(1 - frac(-0.05, 0.1), abs=TOL)


def test_straddling_wrap_equals_mirrored_scene():
    o = np.array([3.0, 2.0])
    # Scene at -x of the observer: target straddling the -pi/pi direction, a partial occluder in
    # front, a box behind it, and a static wall.
    target = box(o[0] - 14, o[1] - 0.8, o[0] - 10, o[1] + 1.2)
    # occ1 covers the upper part of the extent (tan above ~0.04), the wall the lower part (below ~-0.0375).
    occ1 = Polygon([(o[0] - 6, o[1] + 0.5), (o[0] - 5, o[1] + 0.2), (o[0] - 4.5, o[1] + 1.9), (o[0] - 6, o[1] + 1.4)])
    occ2 = box(o[0] - 25, o[1] - 3, o[0] - 15, o[1] + 3)  # behind, not an occluder
    wall = LineString([(o[0] - 8, o[1] - 0.3), (o[0] - 8, o[1] - 4)])
    statics = [wall]
    scene = [target, occ1, occ2]
    res = reference_visibility(o, scene, statics, n_rays=N)
    start, width = res.extent_start[0], res.angular_extent[0]
    assert start + width > np.pi  # really straddles
    lo, hi = np.arctan(0.2 / 5), np.arctan(0.3 / 8)  # visible: between the wall and occ1
    assert res.visibility[0] == pytest.approx((lo + hi) / width, abs=TOL)

    mirror = lambda g: affinity.scale(g, xfact=-1.0, origin=tuple(o))  # noqa: E731
    res_m = reference_visibility(o, [mirror(g) for g in scene], [mirror(g) for g in statics], n_rays=N)
    np.testing.assert_allclose(res_m.angular_extent, res.angular_extent, rtol=1e-12)
    np.testing.assert_allclose(res_m.visibility, res.visibility, atol=TOL)
    # a -> pi - a maps [start, start + width] onto [pi - start - width, pi - start]
    assert (res_m.extent_start[0] - (np.pi - start - width)) % (2 * np.pi) == pytest.approx(0, abs=1e-12)
    for r1, r2 in [(res.occluders, res_m.occluders), (res.static_occluders, res_m.static_occluders)]:
        for d1, d2 in zip(r1, r2, strict=True):
            assert d1.keys() == d2.keys()
            for k in d1:
                assert d1[k] == pytest.approx(d2[k], abs=TOL)
    assert res.occluders[0].keys() == {1}
    assert res.static_occluders[0].keys() == {0}


def test_object_touching_far_side_is_not_an_occluder():
    target = box(10, -0.5, 11, 0.5)
    touching_far = box(11, -1, 13, 1)  # shares the target's far face
    res = reference_visibility([0, 0], [target, touching_far], n_rays=N)
    assert res.visibility[0] == 1.0
    assert res.occluders[0] == {}
    # ... but the target occludes the part of it behind the shared face.
    assert res.occluders[1].keys() == {0}


def test_object_touching_near_side_is_an_occluder():
    target = box(10, -0.5, 11, 0.5)
    touching_near = box(9, -0.25, 10, 0.25)  # shares part of the target's near face
    res = reference_visibility([0, 0], [target, touching_near], n_rays=N)
    assert res.occluders[0].keys() == {1}
    expected = 1 - (np.arctan(0.25 / 9) * 2) / (2 * np.arctan(0.5 / 10))
    assert res.visibility[0] == pytest.approx(expected, abs=TOL)


def test_overlapping_objects():
    target = box(10, -1, 14, 1)
    inner = box(11, -0.5, 12, 0.5)  # inside the target: hidden by it, never in front of it
    overlapping = box(8, 0, 12, 3)  # overlaps the target and starts in front of it
    res = reference_visibility([0, 0], [target, inner, overlapping], n_rays=N)
    assert 1 not in res.occluders[0]
    assert 2 in res.occluders[0]
    assert res.visibility[1] == 0.0
    assert res.occluders[1].keys() == {0, 2}


def test_transparent_object_never_blocks():
    target = box(20, -1, 22, 1)
    big = box(8, -3, 12, 3)
    ego = box(-2, -1, 2, 1)  # contains the observer
    res = reference_visibility([0, 0], [ego, target, big], transparent=[True, False, True], n_rays=N)
    assert res.visibility[1] == 1.0
    assert res.occluders[1] == {}
    assert np.isnan(res.visibility[0]) and np.isnan(res.visibility[2])
    assert res.occluders[0] == {} and res.occluders[2] == {}
    assert np.isnan(res.angular_extent[0])  # observer inside the ego
    assert res.angular_extent[2] == pytest.approx(2 * np.arctan(3 / 8))


def test_observer_inside_non_transparent_object_raises():
    with pytest.raises(ValueError):
        reference_visibility([0, 0], [box(-1, -1, 1, 1)])


def test_target_in_hole_of_static_ring_and_through_a_gap():
    ring = Polygon([(-20, -20), (20, -20), (20, 20), (-20, 20)], [[(5, -5), (15, -5), (15, 5), (5, 5)]])
    target = box(9, -0.5, 10, 0.5)
    res = reference_visibility([0, 0], [target], [ring], n_rays=N)
    assert res.visibility[0] == 0.0  # the hole's near wall is the ring itself
    assert res.static_occluders[0] == {0: 1.0}
    # The observer inside the hole of a ring sees the target inside the same hole.
    res2 = reference_visibility([7, 0], [target], [ring], n_rays=N)
    assert res2.visibility[0] == 1.0
    # A MultiPolygon and a thin wall with a gap in the middle.
    gap = MultiPolygon([box(5, -3, 6, -0.25), box(5, 0.25, 6, 3)])
    res3 = reference_visibility([0, 0], [target], [gap], n_rays=N)
    # A ray gets through iff it clears the far end of the slit (x = 6): |tan| < 0.25 / 6.
    expected = 2 * np.arctan(0.25 / 6) / (2 * np.arctan(0.5 / 9))
    assert res3.visibility[0] == pytest.approx(expected, abs=TOL)


# ----------------------------------------------------------------------------------------------
# Building blocks and generators
# ----------------------------------------------------------------------------------------------


def test_geometry_segments_counts():
    assert geometry_segments(box(0, 0, 1, 1)).shape == (4, 4)
    holed = Polygon(box(0, 0, 10, 10).exterior.coords, [box(1, 1, 2, 2).exterior.coords])
    assert geometry_segments(holed).shape == (8, 4)
    assert geometry_segments(LineString([(0, 0), (1, 0), (1, 1)])).shape == (2, 4)
    assert geometry_segments(MultiLineString([[(0, 0), (1, 0)], [(2, 0), (3, 0)]])).shape == (2, 4)
    assert geometry_segments(np.array([[0, 0], [1, 0], [0, 1]])).shape == (3, 4)


def test_nearest_hit_distances_simple():
    d = nearest_hit_distances([0, 0], [box(2, -1, 3, 1), LineString([(5, -5), (5, 5)])], [0.0, np.pi, 0.3])
    np.testing.assert_allclose(d[0], [2.0, 5.0])
    assert np.isinf(d[1]).all()
    np.testing.assert_allclose(d[2], [2 / np.cos(0.3), 5 / np.cos(0.3)])


@pytest.mark.parametrize("seed", range(6))
def test_random_scenes_consistency_and_prefilter(seed):
    rng = np.random.default_rng(seed)
    overlap, statics, ego = bool(seed % 2), seed % 3 != 0, seed < 3
    o, objs, stats, transp = random_scene(rng, 8, overlap=overlap, with_statics=statics, include_ego=ego)
    assert len(objs) == 8 + ego and transp.sum() == ego
    pt = Point(o)
    if ego:
        assert objs[0].contains(pt)
    for i, g in enumerate(objs):
        assert g.is_valid
        assert transp[i] or not g.intersects(pt)
    for g in stats:
        assert g.is_valid and not g.intersects(pt)
    if not overlap:
        geoms = objs + stats
        assert not any(geoms[i].intersects(geoms[j]) for i in range(len(geoms)) for j in range(i))
    res = reference_visibility(o, objs, stats, transp, n_rays=1000)
    raw = reference_visibility(o, objs, stats, transp, n_rays=1000, prefilter=False)
    np.testing.assert_array_equal(res.visibility, raw.visibility)
    assert res.occluders == raw.occluders and res.static_occluders == raw.static_occluders
    for i in np.flatnonzero(~transp):
        v = res.visibility[i]
        fr = [*res.occluders[i].values(), *res.static_occluders[i].values()]
        assert 0.0 <= v <= 1.0
        assert (v == 1.0) == (not fr)
        if fr:  # blocked fraction is the measure of a union
            assert max(fr) - 1e-12 <= 1 - v <= sum(fr) + 1e-12
        assert all(transp[j] == 0 and j != i for j in res.occluders[i])


def test_generators_cover_all_static_kinds_and_wrap():
    rng = np.random.default_rng(7)
    kinds = {"box": Polygon, "L": Polygon, "U": Polygon, "star": Polygon, "multipolygon": MultiPolygon,
             "line": LineString, "multiline": MultiLineString}  # fmt: skip
    for kind, cls in kinds.items():
        g = random_static(rng, (5.0, 5.0), kind)
        assert isinstance(g, cls) and g.is_valid
    for kind in ("L", "U", "star"):
        g = random_static(rng, (0.0, 0.0), kind)
        assert g.convex_hull.area > g.area + 1e-9  # non-convex
    wrapped = 0
    for seed in range(10):
        o, objs, _, transp = random_scene(np.random.default_rng(seed), 6, include_ego=True)
        for i, g in enumerate(objs):
            if transp[i]:
                continue
            assert np.hypot(*(np.asarray(g.centroid.coords[0]) - o)) <= 60.0 + 1e-9
            s, w = angular_extent_reference(o, g)
            wrapped += s + w > np.pi
    assert wrapped >= 3
    b = random_box(rng)
    assert 3.0 * 1.5 - 1e-9 <= b.area <= 18 * 2.6 + 1e-9


def test_hypothesis_strategy_if_available():
    hypothesis = pytest.importorskip("hypothesis")
    from reference import scenes

    @hypothesis.settings(max_examples=10, deadline=None)
    @hypothesis.given(scenes(max_objects=4))
    def check(scene):
        o, objs, stats, transp = scene
        res = reference_visibility(o, objs, stats, transp, n_rays=200)
        assert np.all(np.isnan(res.visibility) == transp)

    check()


def test_occlusion_confirmed_sees_slivers_and_rejects_bodies_behind() -> None:
    from reference import occlusion_confirmed

    target = box(10, -1, 12, 1)  # extent: tan(bearing) in [-0.1, 0.1]
    # a post whose top corner (5, -0.5 + 1e-5) reaches 2e-6 (in tan) into the extent, in front of the target:
    # about 1e-5 of the extent, thinner than the spacing of 20,000 rays across it, seen by the focused rays
    post = box(4.9, -3, 5, -0.5 + 1e-5)
    assert reference_visibility((0, 0), [target, post], n_rays=20000).occluders[0] == {}
    assert occlusion_confirmed((0, 0), target, post)
    assert not occlusion_confirmed((0, 0), target, box(20, -3, 22, 3))  # behind
    assert not occlusion_confirmed((0, 0), target, box(12, -1, 13, 1))  # touching the far face
