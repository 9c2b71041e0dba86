"""The VisiLibity engine builds a valid environment every frame, whatever overlaps the scene holds."""

from __future__ import annotations

import numpy as np
import polars as pl
import pytest
import shapely
from conftest import boxes_table, scene_table
from reference import random_scene, reference_visibility

from omega_prime_visibility import ENGINES, get_visibility_df
from omega_prime_visibility.engines.visilibity import VisiLibityEngine
from omega_prime_visibility.engines.visilibity.polygon_check import polygon_fails
from omega_prime_visibility.geometry.rings import edges
from omega_prime_visibility.inputs.scene import load_objects
from omega_prime_visibility.inputs.statics import load_static_occluders
from omega_prime_visibility.table.pipeline import viewpoints


def engine_and_frame(table, statics):
    objects = load_objects(table)
    frame = objects.frame_objects(0)
    static = load_static_occluders(statics)
    (view,) = viewpoints(frame, np.array([0]), static)
    return VisiLibityEngine(static), frame, view


@pytest.mark.parametrize("seed", range(30))
def test_environment_is_valid_on_random_overlapping_scenes(seed: int) -> None:
    rng = np.random.default_rng(seed)
    observer, objects, statics, _ = random_scene(rng, 10, overlap=True, with_statics=True, include_ego=True)
    engine, frame, view = engine_and_frame(scene_table(observer, objects, True), statics)
    env, _ = engine.environment(frame, view)
    assert env.is_valid(engine.epsilon)
    assert env.h() >= 1


def test_environment_valid_when_bodies_touch_at_a_corner_and_enclose_the_observer() -> None:
    # four cars around the ego, touching at corners: the observer is enclosed in a courtyard
    boxes = [(0, 0, 2, 1, 0), (0, 3, 6, 2, 0), (0, -3, 6, 2, 0), (4, 0, 2, 4, 0), (-4, 0, 2, 4, 0), (20, 0, 4, 2, 0)]
    engine, frame, view = engine_and_frame(boxes_table(boxes), [])
    env, _ = engine.environment(frame, view)
    assert env.is_valid(engine.epsilon)
    (obs,) = engine.observe(frame, [view])
    # the far car is entirely hidden by the ring of cars; the ring's inner faces are all visible
    assert obs.visible_angle[5] == 0.0
    assert obs.visible_angle[1:5].sum() == pytest.approx(2 * np.pi, abs=1e-9)


def test_visible_region_is_star_shaped_region_around_observer() -> None:
    boxes = [(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)]
    engine, frame, view = engine_and_frame(boxes_table(boxes), [])
    poly = engine.visible_region(frame, view)
    assert poly.is_valid and poly.contains(shapely.Point(view.position))
    assert not poly.intersects(shapely.box(18, -1, 22, 1))  # the hidden car
    assert poly.intersects(shapely.box(8, -2, 12, 2))  # the visible one's near face bounds it


# issue 12: with the long thin wall, VisiLibity's own sweep skipped target 32's right edge peeking out past object 30
SLIVER_SCENE = {
    0: "POLYGON ((0.257 2.475, 1.929 1.573, -0.257 -2.475, -1.929 -1.573, 0.257 2.475))",
    22: "POLYGON ((-35.268 -56.044, -33.773 -55.38, -31.662 -60.14, -33.158 -60.803, -35.268 -56.044))",
    30: "POLYGON ((4.785 -10.018, 6.435 -9.904, 6.709 -13.845, 5.059 -13.96, 4.785 -10.018))",
    31: "POLYGON ((22.682 -70.87, 24.397 -71.621, 22.84 -75.172, 21.126 -74.421, 22.682 -70.87))",
    32: "POLYGON ((19.284 -35.139, 17.308 -35.011, 17.645 -29.781, 19.622 -29.908, 19.284 -35.139))",
}
SLIVER_WALL = "POLYGON ((40.84 18.476, 41.373 18.268, 7.219 -69.486, 6.686 -69.279, 40.84 18.476))"


def sliver_table() -> pl.DataFrame:
    polys = [shapely.from_wkt(w) for w in SLIVER_SCENE.values()]
    return pl.DataFrame(
        {
            "frame": [0] * len(polys),
            "total_nanos": [0] * len(polys),
            "idx": list(SLIVER_SCENE),
            "x": [0.0] + [p.centroid.x for p in polys[1:]],
            "y": [0.0] + [p.centroid.y for p in polys[1:]],
            "polygon": pl.Series(polys, dtype=pl.Object),
        }
    )


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_sliver_past_a_car_beside_a_long_thin_wall(engine: str) -> None:
    out = get_visibility_df(sliver_table(), 0, [shapely.from_wkt(SLIVER_WALL)], engine=engine)
    row = out.filter(pl.col("idx") == 32).row(0, named=True)
    # dense rays over the sliver between bearings -56.99° (object 30's corner) and -56.72° (target 32's corner)
    observer = np.zeros(2)
    polys = list(sliver_table()["polygon"])
    ref = reference_visibility(observer, polys, [shapely.from_wkt(SLIVER_WALL)], np.arange(5) == 0, n_rays=200_000)
    assert row["visibility"] == pytest.approx(ref.visibility[4], abs=2e-4)
    assert row["visibility"] == pytest.approx(0.03659, abs=1e-5)
    assert row["occluder_idxs"] == [30]
    assert out.filter(pl.col("idx") == 31)["static_occluder_idxs"].to_list() == [[0]]


def skipping_target_32(visibility_polygon_coords, calls: int = 1):
    """``visibility_polygon_coords`` that, for its first ``calls`` calls, leaves out the polygon's vertices on
    target 32 of the sliver scene (observer at the origin, so its grid origin is 0): a polygon running past the
    sliver, as VisiLibity 1.0.10's sweep gave it before its edge queue was patched."""
    ring = shapely.from_wkt(SLIVER_SCENE[32]).exterior
    left = [calls]

    def planted(*args):
        polygon = visibility_polygon_coords(*args)
        if left[0] <= 0:
            return polygon
        left[0] -= 1
        on_target = shapely.distance(shapely.points(polygon), ring) < 1e-6
        assert on_target.any()
        return np.ascontiguousarray(polygon[~on_target])

    return planted


def test_visilibity_polygon_that_skips_a_body_is_caught(monkeypatch) -> None:
    from omega_prime_visibility.engines.visilibity import engine as engine_module

    engine, frame, view = engine_and_frame(sliver_table(), [shapely.from_wkt(SLIVER_WALL)])
    env, origin = engine.environment(frame, view)
    o = view.position
    a, b = edges(frame.rings)
    wall, _ = engine._source_edges
    seg = np.ascontiguousarray(np.concatenate([np.stack([a, b], axis=1), wall]) - o)
    blocking = np.concatenate([~np.repeat(view.transparent, 4), np.ones(len(wall), dtype=bool)])
    # VisiLibity's own polygon (patched sweep) holds the sliver of target 32 and passes the exact check
    raw = engine._polygon_points(env, o - origin) - (o - origin)
    assert not polygon_fails(np.ascontiguousarray(raw), seg, blocking, 1e-7, 1e-9, 1e-6)
    # one that runs past it along the wall (1.0.10's) fails it, and the engine computes the region from halves
    planted = skipping_target_32(engine_module.visibility_polygon_coords)
    skipped = planted(env, *(o - origin), engine.epsilon) - (o - origin)
    assert polygon_fails(np.ascontiguousarray(skipped), seg, blocking, 1e-7, 1e-9, 1e-6)
    monkeypatch.setattr(
        engine_module, "visibility_polygon_coords", skipping_target_32(engine_module.visibility_polygon_coords)
    )
    fixed = np.asarray(engine.visible_region(frame, view).exterior.coords)[:-1] - o
    assert not polygon_fails(np.ascontiguousarray(fixed), seg, blocking, 1e-7, 1e-9, 1e-6)
    # the corrected polygon holds target 32's corner at bearing -56.72° on its boundary
    corner = shapely.Point(19.622, -29.908)
    assert engine.visible_region(frame, view).boundary.distance(corner) < 1e-6


def test_components_label_each_node_with_the_smallest_node_of_its_component() -> None:
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from omega_prime_visibility.engines.visilibity.conversion import components

    rng = np.random.default_rng(5)
    for n, m in [(1, 0), (6, 0), (30, 12), (60, 45), (40, 200)]:
        first, second = rng.integers(0, n, m), rng.integers(0, n, m)
        label = components(n, first, second)
        reference = connected_components(coo_matrix((np.ones(m), (first, second)), shape=(n, n)), directed=False)[1]
        for c in np.unique(reference):  # the same partition, each labelled by its smallest member
            members = np.flatnonzero(reference == c)
            assert np.all(label[members] == members.min())
        assert len(np.unique(label)) == len(np.unique(reference))


def test_the_chunk_path_takes_each_environment_and_recomputes_polygons_that_skip_a_body(monkeypatch) -> None:
    from test_pipeline import assert_same_columns, frame_by_frame, moving_scene

    from omega_prime_visibility.engines.visilibity import chunk
    from omega_prime_visibility.table.pipeline import run_chunk

    calls = {"plain": 0, "general": 0, "recomputed": 0}

    def counted(name, function):
        def call(*args, **kwargs):
            calls[name] += 1
            return function(*args, **kwargs)

        return call

    plain_environments = chunk.plain_environments

    def plain_where_it_applies(*args):
        answer = plain_environments(*args)
        calls["plain"] += int(answer[0].sum())
        return answer

    monkeypatch.setattr(chunk, "plain_environments", plain_where_it_applies)
    monkeypatch.setattr(VisiLibityEngine, "_build_environment", counted("general", VisiLibityEngine._build_environment))
    monkeypatch.setattr(chunk, "_frame_observation", counted("recomputed", chunk._frame_observation))
    # a car passes another and runs over a wall: plain environments, and general ones while bodies meet
    objects = load_objects(moving_scene(12))
    statics = load_static_occluders([shapely.LineString([(15, -3), (15, -1)])])
    egos = np.array([0, 3])
    columns, _ = run_chunk(objects, statics, egos, "visilibity")
    assert calls["plain"] > 0 and calls["general"] > 0 and calls["recomputed"] == 0
    plain, general = calls["plain"], calls["general"]
    assert_same_columns(columns, frame_by_frame(objects, statics, egos, None, "visilibity")[0])
    assert calls["plain"] == plain and calls["general"] > general  # the frame path builds every environment itself
    # the sliver scene: VisiLibity's polygon made to skip target 32's sliver (as 1.0.10's did): the viewpoint is
    # observed again, frame by frame, and gives the same columns
    objects = load_objects(sliver_table())
    statics = load_static_occluders([shapely.from_wkt(SLIVER_WALL)])
    columns, _ = run_chunk(objects, statics, np.array([0]), "visilibity")
    assert calls["recomputed"] == 0  # VisiLibity's own polygon passes the check
    for name in ("visibility_polygon_coords", "visibility_polygon_flat"):  # the general and the plain path
        monkeypatch.setattr(chunk, name, skipping_target_32(getattr(chunk, name)))
    columns, _ = run_chunk(objects, statics, np.array([0]), "visilibity")
    assert calls["recomputed"] == 1
    assert_same_columns(columns, frame_by_frame(objects, statics, np.array([0]), None, "visilibity")[0])


@pytest.mark.parametrize("seed", range(5))
def test_chunk_angular_extents_are_those_of_angular_extent_to_the_bit(seed: int) -> None:
    from omega_prime_visibility.engines.visilibity.chunk_geometry import angular_extents
    from omega_prime_visibility.engines.visilibity.conversion import grid_origin
    from omega_prime_visibility.geometry.rings import Rings, angular_extent

    # frames of random rings (3 to 9 vertices, any orientation) far from the origin, 0 to 3 viewpoints each
    rng = np.random.default_rng(seed)
    far = np.array([3.0e5, -5.1e6])
    sizes, frame_sizes, views = [], [], []
    for _ in range(6):
        n = int(rng.integers(1, 7))
        frame_sizes.append(n)
        sizes += rng.integers(3, 10, n).tolist()
        views.append(rng.uniform(-20, 20, (int(rng.integers(0, 4)), 2)) + far)
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    coords = rng.uniform(-30, 30, (offsets[-1], 2)) + far
    frame_starts = np.concatenate([[0], np.cumsum(frame_sizes)]).astype(np.int64)
    view_starts = np.concatenate([[0], np.cumsum([len(v) for v in views])]).astype(np.int64)
    positions = np.concatenate(views)
    frame_of_view = np.repeat(np.arange(6), np.diff(view_starts))
    n_targets = np.array(frame_sizes)[frame_of_view]
    target_offsets = np.concatenate([[0], np.cumsum(n_targets)]).astype(np.int64)
    origins = grid_origin(positions)
    start, width = angular_extents(
        coords, offsets, frame_starts, view_starts, target_offsets, origins, positions - origins
    )
    for v, f in enumerate(frame_of_view.tolist()):
        rings = Rings(coords, offsets).slice(int(frame_starts[f]), int(frame_starts[f + 1]))
        want_start, want_width, _ = angular_extent(
            positions[v] - origins[v], Rings(rings.coords - origins[v], rings.offsets)
        )
        t0, t1 = target_offsets[v], target_offsets[v + 1]
        assert np.array_equal(start[t0:t1], want_start) and np.array_equal(width[t0:t1], want_width)


def test_results_do_not_depend_on_the_side_of_zero_an_earlier_viewpoint_was_on() -> None:
    from test_pipeline import assert_same_columns, frame_by_frame

    from omega_prime_visibility.table.pipeline import run_chunk

    # observer 0 lies left of and below x = y = 0 (np.round gives its grid origin as -0.0), observer 1 right of
    # and above; objects 3 and 4 have vertices at exactly -0.0, which minus a -0.0 origin would become +0.0
    outlines = {
        0: (-1.5, -4.5, [[-19.0, -20.0], [-19.0, -19.0], [-20.0, -19.0], [-20.0, -20.0]]),
        1: (0.0, 2.0, [[20.0, 19.0], [20.0, 20.0], [19.0, 20.0], [19.0, 19.0]]),
        3: (1.0, -0.0, [[3.0, -2.0], [-0.0, -1.0], [-0.0, 3.0]]),
        4: (-0.0, -4 / 3, [[1.0, -2.0], [-6.0, -1.0], [5.0, -1.0]]),
        7: (-3.0, 1 / 3, [[-5.0, -6.0], [-6.0, 4.0], [2.0, 3.0]]),
    }
    table = pl.DataFrame(
        [
            {"frame": 0, "total_nanos": 0, "idx": i, "x": x, "y": y, "polygon": shapely.Polygon(c)}
            for i, (x, y, c) in outlines.items()
        ],
        schema_overrides={"polygon": pl.Object},
    )
    objects = load_objects(table)
    statics = load_static_occluders([])
    frame = objects.frame_objects(0)
    first, second = viewpoints(frame, np.array([0, 1]), statics)
    alone = VisiLibityEngine(statics).observe(frame, [second])[0]
    engine = VisiLibityEngine(statics)
    engine.observe(frame, [first])
    after = engine.observe(frame, [second])[0]
    for name in ("visible_angle", "angular_extent"):
        assert np.array_equal(getattr(alone, name).view(np.int64), getattr(after, name).view(np.int64)), name
    for egos in ([0, 1], [1]):
        expected, _ = frame_by_frame(objects, statics, np.array(egos), None, "visilibity")
        assert_same_columns(run_chunk(objects, statics, np.array(egos), "visilibity")[0], expected)


def test_an_edge_seen_at_grazing_incidence_is_credited_despite_the_joining_gap() -> None:
    # found by fuzzing: a lattice of boxes touching at corners inside a courtyard (VisiLibity's environment is the
    # free space, joined by a 0.1 µm buffer), the viewpoint 2.4 mm left of box 6 = [4, 6] x [1, 2], whose left
    # edge it sees almost end-on up to a wall: along that grazing ray the 0.1 µm offset of the polygon looked
    # like 12 µm and the edge went uncredited (visibility 0 instead of 0.998, the reference's and the sweep's)
    boxes = {
        0: (5, 5, 7, 7),
        1: (3, -3, 4, -2),
        2: (4, -2, 6, -1),
        3: (-4, -4, -3, -2),
        5: (1, 5, 3, 6),
        6: (4, 1, 6, 2),
    }
    boxes[8] = (5, -3, 7, -2)
    polys = {i: shapely.box(*b) for i, b in boxes.items()}
    polys[4] = shapely.box(-0.001, -0.001, 0.001, 0.001)  # the observer, at the viewpoint
    polys[7] = shapely.Polygon(
        [(0.5634104584673589, 3.618250996852551), (5.436589541532641, 3.618250996852551),
         (5.436589541532641, 4.381749003147449), (0.5634104584673589, 4.381749003147449)]
    )  # fmt: skip
    viewpoint = (3.9975940006365924, 1.0141636614889045)
    order = sorted(polys)
    table = pl.DataFrame(
        {
            "frame": [0] * len(order),
            "total_nanos": [0] * len(order),
            "idx": order,
            "x": [viewpoint[0] if i == 4 else polys[i].centroid.x for i in order],
            "y": [viewpoint[1] if i == 4 else polys[i].centroid.y for i in order],
            "polygon": pl.Series(
                [shapely.affinity.translate(polys[i], *viewpoint) if i == 4 else polys[i] for i in order],
                dtype=pl.Object,
            ),
        }
    )
    statics = [
        shapely.box(-2.862974028594433, 5.8677402687465126, -1.6123510492277289, 6.555308930080902),
        shapely.box(-0.2297401811445474, -5.001505680469389, 8.992541695693712, 4.22077619636887).difference(
            shapely.box(0.7702598188554526, -4.001505680469389, 7.992541695693712, 3.22077619636887)
        ),
        shapely.LineString([(-1.5995423268295577, -3.8163261476068144), (14.40115457749291, 10.78576486147209)]),
        shapely.MultiPolygon(
            [shapely.box(-2.2429670374807027, 4.372625441698391, -0.2429670374807027, 6.372625441698391),
             shapely.box(-0.2429670374807027, 6.372625441698391, 1.7570329625192973, 8.372625441698391)]
        ),
    ]  # fmt: skip
    out = {e: get_visibility_df(table, 4, statics, engine=e) for e in ENGINES}
    seen = {e: out[e].filter(pl.col("idx") == 6)["visibility"].item() for e in ENGINES}
    assert seen["sweep"] == pytest.approx(0.997925, abs=2e-6)  # the 200,000-ray reference: 0.997925
    assert seen["visilibity"] == pytest.approx(seen["sweep"], abs=1e-6)


@pytest.mark.parametrize(("chord", "fails"), [(1e-5, True), (1e-4, True), (1e-7, False)])
def test_a_polygon_that_cuts_a_body_corner_by_a_hair_is_caught(chord: float, fails: bool) -> None:
    # The observer at the origin inside a closed 2 m cabin (walls along [-1, 1]^2, checked as bodies). A polygon
    # that cuts the corner (1, 1) with a chord of length `chord` runs along no wall there: nearer than the bodies
    # (by up to chord / 2), so the check must reject it, and the engine take its fallback, once the stretch is
    # longer than the tolerance UNCOVERED = 1e-6 m (within 1e-6 of the distance a polygon edge still counts as
    # running along a wall, which covers the chord's ends); a 1e-7 m chord is VisiLibity's rounding and passes.
    # A tolerance raised to 1e-3 m would let a gap of 10 um in a body's outline pass as seen.
    a = chord / np.sqrt(2.0)
    cut = np.array([[1.0, -1.0], [1.0, 1.0 - a], [1.0 - a, 1.0], [-1.0, 1.0], [-1.0, -1.0]])
    walls = np.array(
        [[[1.0, -1.0], [1.0, 1.0]], [[1.0, 1.0], [-1.0, 1.0]], [[-1.0, 1.0], [-1.0, -1.0]], [[-1.0, -1.0], [1.0, -1.0]]]
    )
    check = np.ones(len(walls), dtype=bool)
    assert bool(polygon_fails(np.ascontiguousarray(cut), walls, check, 1e-7, 1e-9, 1e-6)) is fails
    whole = np.array([[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]])
    assert not polygon_fails(whole, walls, check, 1e-7, 1e-9, 1e-6)
