"""The counting engine (cameras and lidars) against paper answers and an independent caster of every ray."""

from __future__ import annotations

import math

import imaging_reference as ref
import numpy as np
import polars as pl
import pytest
import shapely

from omega_prime_visibility import Sensor, get_visibility_df
from omega_prime_visibility.engines.imaging.camera import camera_counts
from omega_prime_visibility.engines.imaging.lidar import lidar_counts
from omega_prime_visibility.engines.imaging.scene import sensor_axes, sensor_scene
from omega_prime_visibility.engines.imaging.solid_angle import body_solid_angles
from omega_prime_visibility.inputs.cameras import Pinhole
from omega_prime_visibility.inputs.lidars import BeamPattern, uniform
from omega_prime_visibility.inputs.sensors import camera, lidar
from omega_prime_visibility.threed.bodies import bodies_from_boxes, concatenate, prisms_from_footprints
from omega_prime_visibility.threed.boxes import contains, nearest_distance

EYE = np.array([0.0, 0.0, 1.25])


def box(x, y, z, length, width, height, roll=0.0, pitch=0.0, yaw=0.0) -> list[float]:
    return [x, y, z, length, width, height, roll, pitch, yaw]


def counted(boxes, eye=EYE, heading=0.0, pitch=0.0, image=None, pattern=None, max_range=math.inf, prisms=None):
    """The engine's counts for every box among ``boxes`` (and static ``prisms``, footprint/base/top triples)."""
    boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 9)
    bodies = bodies_from_boxes(boxes).relative_to(eye)
    if prisms:
        solid = prisms_from_footprints([shapely.Polygon(f) for f, _, _ in prisms], [t for _, _, t in prisms],
                                       [b for _, b, _ in prisms])  # fmt: skip
        bodies = concatenate(bodies, solid.relative_to(eye))
    kind = "camera" if image is not None else "lidar"
    scene = sensor_scene(bodies, np.arange(len(boxes)), sensor_axes(heading, pitch, kind), nearest_distance(boxes, eye))
    if image is not None:
        return camera_counts(scene, image, max_range)
    return lidar_counts(scene, pattern, max_range)


def cast(boxes, eye=EYE, heading=0.0, pitch=0.0, image=None, pattern=None, max_range=math.inf, prisms=()):
    if image is not None:
        rays = ref.camera_rays(image.width, image.height, image.fx, image.fy, image.cx, image.cy, heading, pitch)
    else:
        rays = ref.lidar_rays(pattern.elevations, pattern.azimuth_step, heading, pitch)
    return ref.cast(eye, rays, np.asarray(boxes, dtype=np.float64).reshape(-1, 9), prisms, max_range)


SQUARE_CAMERA = Pinhole.from_fov(100, 100, math.pi / 2)  # f = 50, principal point (50, 50)


# paper cases ----------------------------------------------------------------------------------------------------


def test_a_box_straight_ahead_covers_its_front_face_pixels() -> None:
    # front face 4 x 4 m at 10 m, centred on the axis: it spans u, v in [50 - 50 * 2 / 10, 50 + 10] = [40, 60], so
    # the pixel centres u + 0.5 = 40.5 .. 59.5 hit it: 20 x 20 pixels, columns and rows 40 to 59
    c = counted([box(11.0, 0, 1.25, 2, 4, 4)], image=SQUARE_CAMERA)
    assert c["pixels"].tolist() == [400] and c["pixels_unoccluded"].tolist() == [400]
    assert c["bbox"].tolist() == [[40, 40, 59, 59]] and c["bbox_unoccluded"].tolist() == [[40, 40, 59, 59]]
    assert c["truncation"][0] == pytest.approx(0.0, abs=1e-15)


def test_a_box_cut_by_the_image_border_in_two_mirror_halves_is_half_truncated() -> None:
    # the image's left edge is the vertical plane at 45° to the left; a box centred on it at eye height, turned
    # along it, is its own mirror image across it: half of its solid angle lies outside
    d = 20.0
    target = box(d * math.cos(math.pi / 4), d * math.sin(math.pi / 4), 1.25, 4, 2, 1.5, yaw=math.pi / 4)
    c = counted([target], image=SQUARE_CAMERA)
    assert c["truncation"][0] == pytest.approx(0.5, abs=1e-12)
    assert 0 < c["pixels"][0] == c["pixels_unoccluded"][0] and c["bbox"][0][0] == 0  # it reaches column 0


def test_a_box_behind_a_larger_one_is_wholly_occluded() -> None:
    front, back = box(11.0, 0, 1.25, 2, 4, 4), box(21.0, 0, 1.25, 2, 3, 3)
    c = counted([front, back], image=SQUARE_CAMERA)
    assert c["pixels"].tolist() == [400, 0]
    # the back one's front face (3 x 3 m at 20 m): u in [50 - 3.75, 50 + 3.75] -> centres 46.5 .. 53.5, 8 x 8
    assert c["pixels_unoccluded"][1] == 64 and c["bbox_unoccluded"][1].tolist() == [46, 46, 53, 53]
    assert c["bbox"][1].tolist() == [-1, -1, -1, -1]
    assert c["hidden_by"][1].tolist() == [True, False] and not c["hidden_by"][0].any()


def test_a_box_behind_the_camera_has_no_pixel_and_is_wholly_truncated() -> None:
    c = counted([box(-10.0, 0, 1.25, 4, 2, 1.5)], image=SQUARE_CAMERA)
    assert c["pixels_met"][0] == 0 and c["truncation"][0] == 1.0


def test_a_box_beside_the_camera_reaching_behind_it_is_truncated_by_solid_angle() -> None:
    # a long box from 5 m behind to 5 m ahead, 3 m to the left: part of it is in the image (45° half fov)
    c = counted([box(0.0, 3.0, 1.25, 10, 1, 1)], image=SQUARE_CAMERA)
    assert 0.0 < c["truncation"][0] < 1.0 and c["pixels"][0] > 0 and c["bbox"][0][0] == 0


def test_a_lidar_beam_along_a_top_face_grazes_it_and_counts() -> None:
    # one beam a degree at elevation 0 from z = 1.0, a box whose top is at z = 1.0, x 10..12, |y| <= 1: the beams
    # within atan(1 / 10) = 5.71° of the heading meet it (azimuths -5° .. 5°): 11
    pattern = BeamPattern((0.0,), math.radians(1.0))
    target = [box(11.0, 0, 0.5, 2, 2, 1.0)]
    eye = np.array([0.0, 0.0, 1.0])
    assert counted(target, eye=eye, pattern=pattern)["points"].tolist() == [11]
    above = BeamPattern((1e-6,), math.radians(1.0))
    assert counted(target, eye=eye, pattern=above)["points"].tolist() == [0]


def test_a_lidar_counts_azimuths_counter_clockwise_from_its_heading() -> None:
    # a thin pole 10 m away at 90° (to the left): the beam k = 90 of a 1° pattern meets it, whatever the heading
    pattern = BeamPattern((0.0,), math.radians(1.0))
    pole = [box(0.0, 10.0, 1.25, 0.05, 0.05, 4)]
    c = counted(pole, pattern=pattern)
    assert c["points"].tolist() == [1]
    turned = counted([box(-10.0, 0.0, 1.25, 0.05, 0.05, 4)], heading=math.pi / 2, pattern=pattern)
    assert turned["points"].tolist() == [1]


def test_a_range_cuts_the_pixels_beyond_it() -> None:
    near = counted([box(11.0, 0, 1.25, 2, 4, 4)], image=SQUARE_CAMERA, max_range=9.0)
    assert near["pixels"].tolist() == [0] and near["pixels_met"].tolist() == [400]


# random scenes against the brute-force caster --------------------------------------------------------------------


def random_boxes(rng, n, tilted=False):
    out = np.column_stack([
        rng.uniform(-15, 25, n), rng.uniform(-10, 10, n), rng.uniform(0.3, 1.6, n), rng.uniform(0.5, 5, n),
        rng.uniform(0.3, 3, n), rng.uniform(0.5, 3, n), rng.uniform(-0.3, 0.3, n) * tilted,
        rng.uniform(-0.3, 0.3, n) * tilted, rng.uniform(-3.2, 3.2, n),
    ])  # fmt: skip
    return out[~contains(out, EYE)]


def random_prisms(rng, k):
    out = []
    for _ in range(k):
        centre = rng.uniform([-20, -15], [30, 15])
        angles = np.sort(rng.uniform(0, 2 * math.pi, rng.integers(3, 7)))
        radius = rng.uniform(0.5, 4)
        ring = centre + radius * np.column_stack([np.cos(angles), np.sin(angles)])
        if shapely.Polygon(ring).buffer(0.1).contains(shapely.Point(0, 0)):
            continue
        out.append((ring, 0.0, float(rng.uniform(0.5, 8))))
    return out


def same(engine: dict, reference: ref.Counts, camera_too: bool) -> None:
    names = (
        ("pixels", "pixels_unoccluded", "pixels_met") if camera_too else ("points", "points_unoccluded", "points_met")
    )
    assert engine[names[0]].tolist() == reference.first.tolist()
    assert engine[names[1]].tolist() == reference.unoccluded.tolist()
    assert engine[names[2]].tolist() == reference.met.tolist()
    if camera_too:
        assert engine["bbox"].tolist() == reference.first_box.tolist()
        assert engine["bbox_unoccluded"].tolist() == reference.unoccluded_box.tolist()
    hidden = [set(np.flatnonzero(row).tolist()) for row in engine["hidden_by"]]
    assert hidden == reference.hidden_by


@pytest.mark.parametrize("seed", range(12))
def test_random_cameras_count_every_pixel_as_the_caster(seed) -> None:
    rng = np.random.default_rng(seed)
    boxes = random_boxes(rng, int(rng.integers(1, 9)), tilted=seed % 2 == 1)
    prisms = random_prisms(rng, int(rng.integers(0, 4)))
    width, height = int(rng.integers(16, 160)), int(rng.integers(8, 100))
    fx, fy, cx, cy = *rng.uniform(20, 90, 2), width * rng.uniform(0.3, 0.7), height * rng.uniform(0.3, 0.7)
    image = Pinhole(width, height, fx, fy, cx, cy)
    heading, pitch = rng.uniform(-math.pi, math.pi), rng.uniform(-0.4, 0.4)
    max_range = [math.inf, 18.0][seed % 2]
    args = dict(heading=heading, pitch=pitch, image=image, max_range=max_range)
    same(counted(boxes, prisms=prisms, **args), cast(boxes, prisms=prisms, **args), camera_too=True)


@pytest.mark.parametrize("seed", range(12))
def test_random_lidars_count_every_beam_as_the_caster(seed) -> None:
    rng = np.random.default_rng(100 + seed)
    boxes = random_boxes(rng, int(rng.integers(1, 9)), tilted=seed % 2 == 1)
    prisms = random_prisms(rng, int(rng.integers(0, 4)))
    pattern = BeamPattern(tuple(np.sort(rng.uniform(-0.6, 0.4, int(rng.integers(1, 24))))), rng.uniform(0.005, 0.1))
    heading, pitch = rng.uniform(-math.pi, math.pi), rng.uniform(-0.2, 0.2)
    max_range = [math.inf, 15.0][seed % 2]
    args = dict(heading=heading, pitch=pitch, pattern=pattern, max_range=max_range)
    same(counted(boxes, prisms=prisms, **args), cast(boxes, prisms=prisms, **args), camera_too=False)


def test_overlapping_boxes_are_ordered_ray_by_ray() -> None:
    # a double detection: two boxes crossing like an X; each is in front along some pixels
    boxes = [box(15.0, 0, 1.25, 6, 1, 2, yaw=0.6), box(15.0, 0, 1.25, 6, 1, 2, yaw=-0.6)]
    image = Pinhole.from_fov(200, 100, math.radians(60))
    c, r = counted(boxes, image=image), cast(boxes, image=image)
    same(c, r, camera_too=True)
    assert (0 < c["pixels"]).all() and (c["pixels"] < c["pixels_unoccluded"]).all()


def test_map_coordinates_count_as_small_ones() -> None:
    rng = np.random.default_rng(7)
    boxes = random_boxes(rng, 8)
    shift = np.array([512_345.0, 5_712_345.0, 0.0])
    far = boxes.copy()
    far[:, :3] += shift
    image = Pinhole.from_fov(320, 200, math.radians(100))
    small = counted(boxes, image=image, heading=0.3)
    large = counted(far, eye=EYE + shift, image=image, heading=0.3)
    for name in ("pixels", "pixels_unoccluded", "bbox"):
        assert np.array_equal(small[name], large[name])
    assert np.allclose(small["truncation"], large["truncation"], atol=1e-9)


# truncation by the frustum's planes -----------------------------------------------------------------------------


def monte_carlo_inside(target, image, rng, n=400_000):
    """Share of the target's directions inside the image, by sampling directions uniformly on the sphere."""
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    forward, left, up = ref.world_axes(0.0, 0.0)
    t = ref.box_entries(EYE, d, target)
    hit = np.isfinite(t)
    cam = np.column_stack([d @ -left, d @ -up, d @ forward])
    with np.errstate(divide="ignore", invalid="ignore"):
        u = image.fx * cam[:, 0] / cam[:, 2] + image.cx
        v = image.fy * cam[:, 1] / cam[:, 2] + image.cy
    inside = (cam[:, 2] > 0) & (u >= 0) & (u <= image.width) & (v >= 0) & (v <= image.height)
    return (hit & inside).sum() / max(hit.sum(), 1), hit.sum()


def test_truncation_is_by_the_image_corners_planes_not_by_an_elevation_band() -> None:
    # a wide image: its top edge plane dips towards the corners, where an elevation band would not; a box over the
    # top-left corner is cut by the plane
    image = Pinhole.from_fov(400, 100, math.radians(120))
    target = box(3.0, 4.5, 2.6, 1.2, 1.2, 1.2)
    c = counted([target], image=image)
    share, hits = monte_carlo_inside(np.array(target), image, np.random.default_rng(3), n=1_000_000)
    assert hits > 5000 and 0.2 < share < 0.8  # the plane cuts it (the band of +-23.4 degrees would not)
    assert 1 - c["truncation"][0] == pytest.approx(share, abs=4 * math.sqrt(share * (1 - share) / hits))


def test_solid_angle_of_a_face_on_square_is_the_closed_form() -> None:
    cube = bodies_from_boxes(np.array([box(0.0, 0, 10, 2, 2, 2)]))
    whole, inside = body_solid_angles(cube.vertices, np.array([0, 8]), cube.normals, cube.offsets, np.zeros((0, 3)))
    assert whole[0] == pytest.approx(4 * math.asin(1 / 82), rel=1e-13) and inside[0] == whole[0]


# the front ends ---------------------------------------------------------------------------------------------------


def one_frame(boxes) -> pl.DataFrame:
    rows = np.asarray(boxes, dtype=np.float64)
    names = ("x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw")
    return pl.DataFrame({"frame": [0] * len(rows), "total_nanos": [0] * len(rows), "idx": list(range(len(rows))),
                         **{c: rows[:, k] for k, c in enumerate(names)}})  # fmt: skip


EGO = box(0.0, 0, 0.75, 4.5, 1.8, 1.5)


def test_the_table_of_a_camera_a_lidar_and_a_radar() -> None:
    scene = one_frame([EGO, box(14.0, 0, 1.25, 2, 4, 4), box(24.0, 0, 1.25, 2, 3, 3), box(-12.0, 0, 0.75, 4, 2, 1.5)])
    sensors = [camera("cam", 100, 100, math.pi / 2, x=2.25, z=1.25), lidar("roof", "vlp16", z=2.0), Sensor("radar")]
    table = get_visibility_df(scene, 0, mode="3d", sensors=sensors, progress=False)
    cam = table.filter(pl.col("sensor") == "cam").sort("idx")
    # the eye at x = 2.25: the front face at 10.75 m... the same 4 m face at x = 13 is 10.75 m away
    assert cam["pixels"].to_list()[1] == 0 and cam["occlusion"].to_list()[1] == 1.0
    assert cam["status"].to_list() == ["visible", "occluded", "out_of_fov"]
    assert cam["occluder_idxs"].to_list() == [[], [1], []]
    assert cam["bbox"].to_list()[2] is None and cam["occlusion"].to_list()[2] is None
    assert cam["truncation"].to_list()[2] == 1.0 and cam["visibility"].to_list()[0] == 1.0
    radar = table.filter(pl.col("sensor") == "radar")
    assert radar["pixels"].null_count() == 3 and radar["points"].null_count() == 3
    roof = table.filter(pl.col("sensor") == "roof").sort("idx")
    assert roof["pixels"].null_count() == 3 and (roof["points_unoccluded"] > 0).all()
    assert roof["points"].to_list()[1] == 0 and roof["status"].to_list()[1] == "occluded"


def test_the_streamed_table_equals_the_one_in_memory(tmp_path) -> None:
    scene = one_frame([EGO, box(14.0, 0, 1.25, 2, 4, 4), box(24.0, 3, 1.25, 2, 3, 3)])
    sensors = [camera("cam", 64, 48, 1.2, x=2.25), lidar("roof", "vlp16"), Sensor("radar", fov=1.0)]
    memory = get_visibility_df(scene, 0, mode="3d", sensors=sensors, progress=False)
    streamed = get_visibility_df(scene, 0, mode="3d", sensors=sensors, progress=False, output=tmp_path / "t.parquet")
    assert streamed.collect().equals(memory)


@pytest.mark.parametrize("engine", ["silhouette3d", "raycast3d"])
def test_the_counts_are_the_same_whatever_the_3d_engine(engine) -> None:
    scene = one_frame([EGO, box(14.0, 0.5, 1.25, 2, 4, 4), box(24.0, -2, 1.25, 2, 3, 3), box(30, 3, 1, 4, 2, 2)])
    sensors = [camera("cam", 64, 48, 1.2, x=2.25), lidar("roof", "vlp16")]
    default = get_visibility_df(scene, 0, mode="3d", sensors=sensors, progress=False)
    other = get_visibility_df(scene, 0, mode="3d", sensors=sensors, progress=False, engine=engine)
    assert other.equals(default)


def test_cameras_and_lidars_need_the_3d_mode() -> None:
    scene = one_frame([EGO, box(14.0, 0, 1.25, 2, 4, 4)])
    with pytest.raises(ValueError, match=r"cameras and lidars count .* pass mode='3d'"):
        get_visibility_df(scene, 0, sensors=[camera("cam")])


def test_a_camera_checks_its_image_and_a_lidar_its_beams() -> None:
    with pytest.raises(ValueError, match="looks like degrees"):
        camera("cam", fov=90)
    with pytest.raises(ValueError, match="positive whole number of pixels"):
        camera("cam", width=0)
    with pytest.raises(ValueError, match="looks like degrees"):
        BeamPattern((-15.0, 15.0), 0.01)
    with pytest.raises(ValueError, match="unknown lidar pattern"):
        lidar("l", "hdl-65")
    with pytest.raises(ValueError, match="camera or a lidar, not both"):
        Sensor("x", camera=SQUARE_CAMERA, lidar=uniform(2, -1, 1, 10))
    with pytest.raises(ValueError, match="leave fov out"):
        Sensor("x", fov=1.0, camera=SQUARE_CAMERA)


@pytest.mark.parametrize("seed", range(4))
def test_the_label_image_holds_each_targets_first_hit_pixels(seed) -> None:
    rng = np.random.default_rng(200 + seed)
    boxes = random_boxes(rng, 8, tilted=seed % 2 == 1)
    image = Pinhole.from_fov(120, 80, 1.6)
    bodies = bodies_from_boxes(boxes).relative_to(EYE)
    scene = sensor_scene(bodies, np.arange(len(boxes)), sensor_axes(0.4, 0.1, "camera"), nearest_distance(boxes, EYE))
    c = camera_counts(scene, image, math.inf, labels=True)
    assert c["labels"].shape == (80, 120)
    assert np.bincount(c["labels"][c["labels"] >= 0], minlength=len(boxes)).tolist() == c["pixels"].tolist()
