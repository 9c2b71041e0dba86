"""The plain environment (engines/visilibity/plain.py): where it applies it is, to the bit, the environment the
engine's general construction builds; it applies whenever no two bodies meet and no courtyard holds the viewpoint;
built for many viewpoints in one call, it is each one's.
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
from omega_prime_visibility.engines.visilibity.plain import APART, plain_environment, plain_environments, rings_apart
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


def test_many_viewpoints_in_one_call_are_each_ones() -> None:
    """Three frames of traffic beside a courtyard building and one with the viewpoint in the courtyard, two
    viewpoints a frame (all objects but the ego as holes; every other one): the batch gives each viewpoint's own
    answer, back to back."""
    rng = np.random.default_rng(3)
    frames = []
    for f in range(3):
        observer, objects, _, _ = random_scene(rng, 8, overlap=f == 1, with_statics=False, include_ego=True)
        frames.append((observer, objects))
    frames.append((np.array([55.0, -25.0]), frames[0][1]))  # in the courtyard (the objects stay where they were)
    engine = VisiLibityEngine(load_static_occluders([courtyard(40.0, -40.0)]))
    singles, coords, offsets, starts, targets, eyes, in_envs = [], [], [0], [0], [0], [], []
    for observer, objects in frames:
        frame = load_objects(scene_table(observer, objects, True)).frame_objects(0)
        origin = engine._use_origin(np.asarray(observer, dtype=np.float64))
        ring_coords = np.ascontiguousarray(frame.rings.coords, dtype=np.float64)
        ring_offsets = np.ascontiguousarray(frame.rings.offsets, dtype=np.int64)
        eye = np.asarray(observer, dtype=np.float64) - origin
        where = (*origin.tolist(), *eye.tolist())
        parts = _parts_at(engine, origin)
        for every in (1, 2):
            env = np.zeros(len(frame), dtype=bool)
            env[1::every] = True
            single = plain_environment(ring_coords, ring_offsets, 0, len(frame), *where, env, *parts, engine.box_margin)
            singles.append(single)
            targets.append(targets[-1] + len(frame))
            eyes.append(eye)
            in_envs.append(env)
        coords.append(ring_coords)
        offsets += (ring_offsets[1:] + offsets[-1]).tolist()
        starts.append(starts[-1] + len(frame))
    views = np.arange(len(singles), dtype=np.int64)
    origins = np.zeros((len(views), 2))
    frame_of_view = views // 2
    rings = (np.concatenate(coords), np.array(offsets, dtype=np.int64))
    plain, vertex_offsets, vertices, count_offsets, counts = plain_environments(
        views, frame_of_view, np.array(starts, dtype=np.int64), np.array(targets, dtype=np.int64),
        np.concatenate(in_envs), *rings, origins, np.array(eyes), *_parts_at(engine, origins[0]), engine.box_margin,
    )  # fmt: skip
    assert plain.tolist() == [single[0] for single in singles]
    assert plain[0] and not plain[6] and not plain[7]  # the courtyard holds the last two viewpoints
    for i, (ok, own_vertices, own_counts) in enumerate(singles):
        if ok:
            assert np.array_equal(vertices[vertex_offsets[i] : vertex_offsets[i + 1]], own_vertices)
            assert np.array_equal(counts[count_offsets[i] : count_offsets[i + 1]], own_counts)
