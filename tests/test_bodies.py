"""Convex bodies (threed.bodies) and directions on the cube (threed.cube): footprints cut into convex parts, ray
entries, solid angles, and the exact engine on static prisms against an independent mesh ray caster."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from conftest import cap_directions

from omega_prime_visibility.engines.silhouette3d import box_visibility
from omega_prime_visibility.threed.bodies import (
    MAX_PART_VERTICES,
    bodies_from_boxes,
    containing_origin,
    convex_parts,
    entries,
    prisms_from_footprints,
)
from omega_prime_visibility.threed.cube import SQUARE, ring_solid_angle, silhouettes, solid_angles

EYE = np.array([0.0, 0.0, 1.25])


@pytest.mark.parametrize(
    "polygon",
    [
        shapely.Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]),  # L
        shapely.box(0, 0, 10, 6).difference(shapely.box(3, 2, 7, 4)),  # a courtyard
        shapely.Polygon([(0, 0), (4, 0), (4, 3), (3, 1), (2, 3), (1, 1), (0, 3)]),  # a comb
        shapely.Point(0, 0).buffer(5, 1),  # convex: one part
        shapely.Point(0, 0).buffer(5, 16),  # a convex 64-gon: fans of at most 8 vertices
    ],
)
def test_convex_parts_tile_the_footprint(polygon) -> None:
    parts = [shapely.Polygon(p) for p in convex_parts(polygon)]
    assert all(p.is_valid and abs(p.convex_hull.area - p.area) < 1e-9 for p in parts)
    assert all(shapely.is_ccw(p.exterior) for p in parts)
    assert sum(p.area for p in parts) == pytest.approx(polygon.area, rel=1e-12)
    assert shapely.union_all(parts).symmetric_difference(polygon).area < 1e-9
    assert all(len(p.exterior.coords) - 1 <= MAX_PART_VERTICES for p in parts)
    split = polygon.convex_hull.area - polygon.area > 1e-9 or len(polygon.exterior.coords) - 1 > MAX_PART_VERTICES
    assert (len(parts) > 1) == split


def test_entries_of_a_prism_and_a_wall() -> None:
    bodies = prisms_from_footprints(
        [shapely.Polygon([(10, -1), (12, -1), (12, 1), (10, 1)]), shapely.LineString([(5, -3), (5, 3)])],
        tops=[2.0, 1.0],
        bases=[0.0, 0.0],
    ).relative_to(EYE)
    assert bodies.source.tolist() == [0, 1]
    d = np.array([[1.0, 0, 0], [1.0, 0, 0], [1.0, 0, 0.5], [1.0, 0.7, 0], [-1.0, 0, 0]])
    which = np.array([0, 1, 0, 1, 0])
    # the eye at 1.25 m sees the prism's face x = 10 and the 1 m wall at x = 5 only below its top
    assert entries(bodies, which, d).tolist() == [10.0, math.inf, math.inf, math.inf, math.inf]
    down = np.array([[1.0, 0, -0.1], [1.0, 0, -0.3]])  # at x = 5: z = 0.75 (on the wall), z = -0.25 (below it)
    assert entries(bodies, np.array([1, 1]), down).tolist() == [pytest.approx(5.0), math.inf]
    assert containing_origin(bodies).tolist() == [False, False]
    inside = prisms_from_footprints([shapely.box(-1, -1, 1, 1)], tops=[3.0], bases=[0.0]).relative_to(EYE)
    assert containing_origin(inside).tolist() == [True]


def test_solid_angles_subtract_holes_and_ignore_lines() -> None:
    ring = shapely.box(-0.5, -0.5, 0.5, 0.5)
    hole = shapely.box(-0.1, -0.1, 0.1, 0.1)
    whole, inner = (ring_solid_angle(np.asarray(g.exterior.coords)[:-1]) for g in (ring, hole))
    got = solid_angles(np.array([ring.difference(hole), shapely.LineString([(0, 0), (1, 1)]), None]))
    assert got.tolist() == pytest.approx([whole - inner, 0.0, 0.0], rel=1e-12)
    assert solid_angles(np.array([SQUARE]))[0] * 6 == pytest.approx(4 * math.pi, rel=1e-14)


def test_a_box_footprint_prism_casts_the_silhouette_of_the_same_box() -> None:
    box = np.array([[10.0, 1.0, 1.0, 4.0, 2.0, 2.0, 0.0, 0.0, 0.3]])  # on the ground (z 0..2), turned 0.3 rad
    footprint = shapely.Polygon(bodies_from_boxes(box).vertices[::2, :2][[0, 2, 3, 1]])
    prism = prisms_from_footprints([footprint], tops=[2.0], bases=[0.0]).relative_to(EYE)
    as_box = bodies_from_boxes(box).relative_to(EYE)
    for f in range(6):
        a, b = silhouettes(prism, f)[0], silhouettes(as_box, f)[0]
        assert (a is None) == (b is None)
        if a is not None:
            assert a.symmetric_difference(b).area < 1e-12


def walls(buildings: list[shapely.Geometry], tops: list[float]):
    """The buildings as the ray engine's wall triangles (from -1 m to their tops, no caps), as one mesh."""
    import trimesh

    from omega_prime_visibility.inputs.statics import load_static_occluders
    from omega_prime_visibility.threed.statics import static_solids

    triangles = static_solids(load_static_occluders(buildings), heights=tops).triangles
    return trimesh.Trimesh(vertices=triangles.reshape(-1, 3), faces=np.arange(3 * len(triangles)).reshape(-1, 3))


@pytest.mark.parametrize("seed", range(3))
def test_random_boxes_among_buildings_agree_with_a_mesh_ray_caster(seed: int) -> None:
    # boxes among non-convex buildings (L shapes and courtyards, as prisms from -1 m to their height): the exact
    # engine against the share of random directions towards each box that trimesh's own ray caster, on the
    # buildings as wall triangles and the boxes as meshes, sees hit that box first
    import trimesh

    rng = np.random.default_rng(seed)
    buildings, tops = [], []
    for k in range(3):
        x, y = 15 + 12 * k, rng.uniform(-12, 12)
        b = shapely.box(x, y, x + 8, y + 6)
        cut = shapely.box(x + 3, y + 2, x + 9, y + 7) if k % 2 == 0 else shapely.box(x + 2, y + 2, x + 5, y + 4)
        buildings.append(b.difference(cut))
        tops.append(rng.uniform(2.0, 6.0))
    boxes = []
    while len(boxes) < 6:
        c = np.array([rng.uniform(6, 50), rng.uniform(-14, 14), 0.0])
        size = np.array([4.5, 1.8, rng.uniform(1.4, 3.5)])
        c[2] = size[2] / 2
        footprint = shapely.Point(c[:2]).buffer(np.linalg.norm(size[:2]) / 2)
        if all(not footprint.intersects(g) for g in buildings) and all(
            np.linalg.norm(c[:2] - b[:2]) > 5.2 for b in boxes
        ):
            boxes.append(np.r_[c, size, 0.0, 0.0, rng.uniform(-1, 1)])
    boxes = np.array(boxes)
    statics = prisms_from_footprints(buildings, tops=tops, bases=[-1.0] * 3)
    visible, extent, _, _, _ = box_visibility(boxes, EYE, statics=statics)
    box_meshes = [trimesh.creation.box(extents=b[3:6], transform=_pose(b)) for b in boxes]
    scene = trimesh.util.concatenate([*box_meshes, walls(buildings, tops)])
    owner = np.concatenate([np.full(len(m.faces), k) for k, m in enumerate(box_meshes)] + [np.full(
        len(scene.faces) - sum(len(m.faces) for m in box_meshes), -1)])  # fmt: skip
    for k in range(len(boxes)):
        share, count = _monte_carlo(scene, owner, boxes[k], k, rng)
        sigma = max(math.sqrt(share * (1 - share) / count), 1 / count)
        assert visible[k] / extent[k] == pytest.approx(share, abs=5 * sigma + 2e-3), k


def _pose(b: np.ndarray) -> np.ndarray:
    c, s = math.cos(b[8]), math.sin(b[8])
    pose = np.eye(4)
    pose[:3, :3] = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
    pose[:3, 3] = b[:3]
    return pose


def _monte_carlo(scene, owner, b, k, rng, n=40_000) -> tuple[float, int]:
    """Share of random directions in the cone around box ``b``'s bounding sphere that hit it first, among those
    that hit it (trimesh's ray caster)."""
    dirs = cap_directions(b[:3], np.linalg.norm(b[3:6]) / 2, EYE, n, rng)
    first = scene.ray.intersects_first(np.repeat(EYE[None], n, 0), dirs)
    alone = bodies_from_boxes(b[None]).relative_to(EYE)
    on_target = np.isfinite(entries(alone, np.zeros(n, dtype=np.int64), dirs))
    seen = on_target & (first >= 0) & (owner[np.maximum(first, 0)] == k)
    return float(seen.sum() / max(on_target.sum(), 1)), int(on_target.sum())
