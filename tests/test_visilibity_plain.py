"""The plain environment (engines/visilibity/plain.py): where it applies it is, to the bit, the environment the
engine's general construction builds; it applies whenever no two bodies meet and no courtyard holds the viewpoint.
Random scenes (boxes, L, U and star-shaped buildings, lines, a courtyard building) with and without overlaps, at
small and at map coordinates; the ring test on paper."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from conftest import scene_table
from reference import random_scene

from omega_prime_visibility.engines.visilibity import VisiLibityEngine
from omega_prime_visibility.engines.visilibity.chunk import _parts_at
from omega_prime_visibility.engines.visilibity.plain import APART, plain_environment, rings_apart
from omega_prime_visibility.geometry.rings import Rings
from omega_prime_visibility.inputs.scene import load_objects
from omega_prime_visibility.inputs.statics import load_static_occluders
from omega_prime_visibility.table.pipeline import viewpoints

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


@pytest.mark.parametrize(
    ("other", "apart"),
    [
        (SQUARE + np.array([1.5, 0.0]), True),  # half a metre to the side
        (SQUARE + np.array([1.0 + 2 * APART, 0.5]), True),  # twice the limit away
        (SQUARE + np.array([1.0 + APART / 2, 0.5]), False),  # nearer than the limit
        (SQUARE + np.array([1.0, 1.0]), False),  # touching at a corner
        (SQUARE + np.array([0.5, 0.5]), False),  # overlapping
        (SQUARE * np.array([0.2, 3.0]) + np.array([0.4, -1.0]), False),  # a cross: no corner inside the other
        (SQUARE * 0.25 + np.array([0.3, 0.3]), False),  # inside
        (SQUARE * 5.0 - [2.0, 2.0], False),  # around it
    ],
)
def test_rings_apart_on_paper(other: np.ndarray, apart: bool) -> None:
    coords = np.concatenate([SQUARE, other])
    assert rings_apart(coords, 0, 4, 4, 8, APART) == apart
    assert rings_apart(coords, 4, 8, 0, 4, APART) == apart


def courtyard(x: float, y: float) -> shapely.Polygon:
    """A 30 m square building with a 10 m courtyard, its corner at ``(x, y)``."""
    return shapely.Polygon(
        [(x, y), (x + 30, y), (x + 30, y + 30), (x, y + 30)],
        [[(x + 10, y + 10), (x + 20, y + 10), (x + 20, y + 20), (x + 10, y + 20)]],
    )


def general_and_plain(observer, objects, statics, blocking_share: float, rng):
    """The general construction's polygons and :func:`plain_environment`'s answer for the ego's viewpoint."""
    table = scene_table(observer, objects, True)
    frame = load_objects(table).frame_objects(0)
    static = load_static_occluders(statics)
    (view,) = viewpoints(frame, np.array([0]), static)
    engine = VisiLibityEngine(static)
    origin = engine._use_origin(np.asarray(view.position, dtype=np.float64))
    eye = np.asarray(view.position, dtype=np.float64) - origin
    in_env = ~view.transparent & (rng.random(len(frame)) < blocking_share)
    coords = np.ascontiguousarray(frame.rings.coords, dtype=np.float64)
    offsets = np.ascontiguousarray(frame.rings.offsets, dtype=np.int64)
    rings = Rings(coords - origin, offsets)
    general = engine._build_environment(rings, in_env, ~view.static_transparent, eye)
    parts = _parts_at(engine, origin)
    answer = plain_environment(
        coords, offsets, 0, len(frame), *origin.tolist(), *eye.tolist(), in_env, *parts, engine.box_margin
    )
    return general, answer, view


@pytest.mark.parametrize("seed", range(24))
@pytest.mark.parametrize("offset", [0.0, 4.0e5], ids=["small", "map coordinates"])
def test_the_plain_environment_is_the_general_construction(seed: int, offset: float) -> None:
    rng = np.random.default_rng(seed)
    overlap = seed % 2 == 0
    observer, objects, statics, _ = random_scene(rng, 14, overlap=overlap, with_statics=True, include_ego=True)
    if seed % 3 == 0:  # a building with a courtyard, beside the scene or around the viewpoint
        corner = observer - 15.0 if seed % 6 == 0 else observer + np.array([70.0, -15.0])
        statics = [*statics, courtyard(*corner)]
    shift = np.array([offset, offset])
    observer = observer + shift
    objects = [shapely.transform(p, lambda c: c + shift) for p in objects]
    statics = [shapely.transform(g, lambda c: c + shift) for g in statics]
    general, (plain, vertices, counts), view = general_and_plain(observer, objects, statics, 0.9, rng)
    if view.static_transparent.any():
        pytest.skip("the viewpoint lies in a static occluder: the chunk takes the general construction")
    if plain:
        assert counts.tolist() == [len(p) for p in general]
        assert np.array_equal(vertices, np.concatenate(general))
    bodies = [*objects[1:], *statics]
    meet = any(shapely.distance(a, b) <= 1e-6 for k, a in enumerate(bodies) for b in bodies[k + 1 :] if not a.is_empty)
    enclosed = seed % 6 == 0
    if not meet and not enclosed:
        assert plain, "no two bodies meet, no courtyard holds the viewpoint: the environment is the plain one"
    if enclosed:
        assert not plain
