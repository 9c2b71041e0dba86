"""The compiled area and geometry of a union of star-shaped polygons against shapely's union."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import shapely
from conftest import scene_table
from reference import scene_series

from omega_prime_visibility import Sensor
from omega_prime_visibility.analysis import area
from omega_prime_visibility.analysis.area import visible_area, visible_area_over_time
from omega_prime_visibility.geometry.star_union import star_union_area
from omega_prime_visibility.geometry.union_rings import star_union


def test_two_overlapping_squares() -> None:
    # squares star-shaped around their centres, all around, vertices from bearing -3π/4
    a = np.array([(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)])
    points = np.concatenate([a, a + np.array([1.0, 0.0])])
    starts = np.array([0, 4, 8])
    centers = np.array([(0.0, 0.0), (1.0, 0.0)])
    area = star_union_area(points, starts, centers, np.full(2, -0.75 * math.pi), np.full(2, 2 * math.pi))
    assert area == pytest.approx(6.0, rel=1e-12)  # two 2 m squares overlapping by 1 m x 2 m


def test_a_shared_edge_counts_once() -> None:
    # two wedges from different apexes ending on the same wall x = 10
    first = np.array([(0.0, 0.0), (10.0, -10.0), (10.0, 10.0)])
    second = np.array([(0.0, 1.0), (10.0, -9.0), (10.0, 11.0)])
    points = np.concatenate([first, second])
    centers = np.array([(0.0, 0.0), (0.0, 1.0)])
    area = star_union_area(points, np.array([0, 3, 6]), centers, np.full(2, -math.pi / 4), np.full(2, math.pi / 2))
    want = shapely.union(shapely.Polygon(first), shapely.Polygon(second)).area
    assert area == pytest.approx(want, rel=1e-12)


def _random_sensors(rng: np.random.Generator) -> list[Sensor]:
    """2-6 sensors; some share a position, a range or a wedge edge with another (shared boundaries)."""
    sensors = []
    for k in range(int(rng.integers(2, 7))):
        if sensors and rng.random() < 0.4:  # at an earlier sensor's position, often with its range
            other = sensors[int(rng.integers(len(sensors)))]
            x, y, reach = other.x, other.y, other.range if rng.random() < 0.5 else float(rng.uniform(5, 30))
            yaw = other.yaw + (other.fov / 2 if rng.random() < 0.5 else float(rng.uniform(-1, 1)))
            if abs(yaw) > 2 * math.pi:  # beyond a full turn a sensor's angle reads as degrees: wrap it
                yaw = math.remainder(yaw, 2 * math.pi)
        else:
            x, y, reach, yaw = *rng.uniform(-1.5, 1.5, 2), float(rng.uniform(5, 30)), float(rng.uniform(-3, 3))
        fov = 2 * math.pi if rng.random() < 0.25 else float(rng.uniform(0.3, 5.5))
        sensors.append(Sensor(f"s{k}", x=float(x), y=float(y), yaw=yaw, fov=fov, range=reach))
    return sensors


def _parts(geometry: shapely.Geometry) -> tuple[int, int]:
    """Number of polygons and of holes (those of more than 1e-12 of the area: shapely keeps slivers of 1e-14 m²
    that the compiled union drops as thinner than its tolerance)."""
    polygons = [g for g in shapely.get_parts(geometry) if g.geom_type == "Polygon"]
    holes = [r for g in polygons for r in g.interiors if shapely.Polygon(r).area > 1e-12 * geometry.area]
    return len(polygons), len(holes)


def _assert_same(got: shapely.Geometry | None, want: shapely.Geometry) -> None:
    assert got is not None and shapely.is_valid(got)
    assert shapely.symmetric_difference(got, want).area <= 1e-9 * want.area
    assert _parts(got) == _parts(want)


def _wedge(apex, start: float, fov: float, radius: float) -> np.ndarray:
    """A wedge's outline: its apex, then its arc (1° chords) from bearing ``start`` (radians) over ``fov``."""
    steps = math.ceil(fov / math.radians(1.0))
    t = start + fov * np.arange(steps + 1) / steps
    return np.vstack([apex, np.c_[apex[0] + radius * np.cos(t), apex[1] + radius * np.sin(t)]])


def _box(x0, y0, x1, y1) -> tuple[np.ndarray, tuple[float, float], float, float]:
    """A rectangle star-shaped around its centre, all around: corners counter-clockwise from the lower left."""
    corners = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], dtype=float)
    center = (0.5 * (x0 + x1), 0.5 * (y0 + y1))
    return corners, center, math.atan2(y0 - center[1], x0 - center[0]), 2 * math.pi


def _union(parts) -> tuple[shapely.Geometry | None, float, shapely.Geometry]:
    """The compiled union of ``parts`` (outline, centre, base, fov), its area, and shapely's union."""
    points = np.concatenate([p[0] for p in parts])
    starts = np.cumsum([0] + [len(p[0]) for p in parts])
    centers = np.array([p[1] for p in parts], dtype=float)
    bases = np.array([p[2] for p in parts], dtype=float)
    fovs = np.array([p[3] for p in parts], dtype=float)
    geometry, area = star_union(points, starts, centers, bases, fovs)
    return geometry, area, shapely.union_all([shapely.Polygon(p[0]) for p in parts])


def _wedge_part(apex, start, fov, radius):
    return _wedge(np.asarray(apex, dtype=float), start, fov, radius), apex, start, fov


def _pinwheel() -> list:
    """Four thin wedges, each from near a corner of a square along its side past the next corner: a hole in the
    middle."""
    parts = []
    for k in range(4):
        c, s = math.cos(k * math.pi / 2), math.sin(k * math.pi / 2)
        parts.append(_wedge_part((-2.5 * c + 2.0 * s, -2.5 * s - 2.0 * c), k * math.pi / 2 - 0.1, 0.3, 5.1))
    return parts


def _pinched() -> list:
    """Two wedges from one apex with gaps between them, one gap closed farther out by a box: a hole touching the
    outline at the apex (shapely: a shell and a hole meeting at a point)."""
    return [_wedge_part((0, 0), 0.5, 2.5, 10), _wedge_part((0, 0), 3.5, 2.3, 10), _box(-9, -3.5, -5, 2)]


@pytest.mark.parametrize(
    "case, parts, holes",
    [
        ("overlapping squares", [_box(-1, -1, 1, 1), _box(0, -1, 2, 1)], (1, 0)),
        ("a square inside another", [_box(-2, -2, 2, 2), _box(-1, -0.5, 1, 1.5)], (1, 0)),
        ("the inner square first", [_box(-1, -0.5, 1, 1.5), _box(-2, -2, 2, 2)], (1, 0)),
        ("an edge shared, opposite directions", [_box(0, 0, 1, 1), _box(1, 0, 2, 1)], (1, 0)),
        ("squares touching at a corner", [_box(0, 0, 1, 1), _box(1, 1, 2, 2)], (2, 0)),
        (
            "a frame of four boxes",
            [_box(-2, 1, 2, 2), _box(-2, -2, 2, -1), _box(-2, -2, -1, 2), _box(1, -2, 2, 2)],
            (1, 1),
        ),
        ("a pinwheel of four wedges", _pinwheel(), (1, 1)),
        ("a wedge touching itself around a hole", _pinched(), (1, 1)),
        ("wedges touching at their apex", [_wedge_part((0, 0), 0.5, 1.0, 5), _wedge_part((0, 0), 3.0, 1.0, 5)], (2, 0)),
        ("three wedges touching at their apex", [_wedge_part((0, 0), 2 * k, 1.0, 5) for k in range(3)], (3, 0)),
        ("one wedge", [_wedge_part((1, 2), 2.0, 4.0, 5)], (1, 0)),
    ],
)
def test_hand_made_unions(case, parts, holes) -> None:
    geometry, area, want = _union(parts)
    _assert_same(geometry, want)
    assert _parts(want) == holes, case  # the case is what it says
    assert area == pytest.approx(want.area, rel=1e-12)


@pytest.mark.parametrize("seed", [3, 4, 5, 6, 7, 8, 300, 1098])  # 300, 1098: points on radial edges' rays
def test_the_union_matches_shapelys_on_random_scenes(seed, monkeypatch) -> None:
    # visible_area and the road path of visible_area_over_time build the union from star_union's pieces, the
    # area alone comes from star_union_area; the reference is shapely's union (the fallback, forced)
    rng = np.random.default_rng(seed)
    road = shapely.box(-40, -5, 40, 5)
    for include_ego, scene in scene_series(rng, 12, True, 8):
        observer, objects, statics, _ = scene
        table = scene_table(observer, objects, include_ego).with_columns(yaw=0.0)
        sensors = _random_sensors(rng)
        fallbacks = area.UNION_FALLBACKS["shapely"]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            got = visible_area(table, 0, 0, sensors, statics)
            fast = visible_area_over_time(table, 0, sensors, statics)["visible_area"][0]
            hidden = visible_area_over_time(table, 0, sensors, statics, road=road)["hidden_road_area"][0]
            assert area.UNION_FALLBACKS["shapely"] == fallbacks  # built from the pieces, not by shapely
            with monkeypatch.context() as patch:
                patch.setattr(area, "star_union", lambda *args, **kwargs: (None, 0.0))
                want = visible_area(table, 0, 0, sensors, statics)
        _assert_same(got, want)
        assert fast == pytest.approx(want.area, rel=1e-9, abs=1e-9)
        assert hidden == pytest.approx(shapely.difference(road, want).area, rel=1e-9, abs=1e-9)
