"""The VisiLibity engine builds a valid environment every frame, whatever overlaps the scene holds."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from conftest import boxes_table, scene_table
from reference import random_scene

from omega_prime_visibility.api import transparency_masks
from omega_prime_visibility.engines.visilibity import VisiLibityEngine
from omega_prime_visibility.scene import load_objects, load_static_occluders


def engine_and_frame(table, statics):
    objects = load_objects(table)
    frame = objects.frame_objects(0)
    static = load_static_occluders(statics)
    observer = frame.position[0]
    transparent, static_transparent = (m[0] for m in transparency_masks(frame, np.array([0]), static))
    return VisiLibityEngine(static), frame, observer, transparent, static_transparent


@pytest.mark.parametrize("seed", range(30))
def test_environment_is_valid_on_random_overlapping_scenes(seed: int) -> None:
    rng = np.random.default_rng(seed)
    observer, objects, statics, _ = random_scene(rng, 10, overlap=True, with_statics=True, include_ego=True)
    engine, frame, o, transparent, static_transparent = engine_and_frame(scene_table(observer, objects, True), statics)
    env, _ = engine.environment(frame, o, transparent, static_transparent)
    assert env.is_valid(engine.epsilon)
    assert env.h() >= 1


def test_environment_valid_when_bodies_touch_at_a_corner_and_enclose_the_observer() -> None:
    # four cars around the ego, touching at corners: the observer is enclosed in a courtyard
    boxes = [(0, 0, 2, 1, 0), (0, 3, 6, 2, 0), (0, -3, 6, 2, 0), (4, 0, 2, 4, 0), (-4, 0, 2, 4, 0), (20, 0, 4, 2, 0)]
    engine, frame, o, transparent, static_transparent = engine_and_frame(boxes_table(boxes), [])
    env, _ = engine.environment(frame, o, transparent, static_transparent)
    assert env.is_valid(engine.epsilon)
    obs = engine.observe(frame, o, transparent, static_transparent)
    # the far car is entirely hidden by the ring of cars; the ring's inner faces are all visible
    assert obs.visible_angle[5] == 0.0
    assert obs.visible_angle[1:5].sum() == pytest.approx(2 * np.pi, abs=1e-9)


def test_visibility_polygon_is_star_shaped_region_around_observer() -> None:
    boxes = [(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)]
    engine, frame, o, transparent, static_transparent = engine_and_frame(boxes_table(boxes), [])
    poly = engine.visibility_polygon(frame, o, transparent, static_transparent)
    assert poly.is_valid and poly.contains(shapely.Point(o))
    assert not poly.intersects(shapely.box(18, -1, 22, 1))  # the hidden car
    assert poly.intersects(shapely.box(8, -2, 12, 2))  # the visible one's near face bounds it
