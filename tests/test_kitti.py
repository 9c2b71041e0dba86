"""KITTI label and calibration files, read back as the object devkit defines them and projected onto their boxes."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest

from omega_prime_visibility import get_visibility_df, write_kitti
from omega_prime_visibility.export.kitti import kitti_type
from omega_prime_visibility.inputs.sensors import Sensor, camera

NAMES = ("x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw")


def scene(boxes, types=None, subtypes=None, frames=1) -> pl.DataFrame:
    rows = np.asarray(boxes, dtype=np.float64)
    n = len(rows)
    out = {"frame": np.repeat(np.arange(frames), n), "total_nanos": np.repeat(np.arange(frames) * 10**8, n),
           "idx": np.tile(np.arange(n), frames), **{c: np.tile(rows[:, k], frames) for k, c in enumerate(NAMES)},
           "type": np.tile(types or [2] * n, frames), "subtype": np.tile(subtypes or [4] * n, frames)}  # fmt: skip
    return pl.DataFrame(out)


def read_label(path) -> list[dict]:
    """The devkit's 15 fields per line."""
    out = []
    for line in path.read_text().splitlines():
        f = line.split()
        assert len(f) == 15
        values = list(map(float, f[1:]))
        out.append({"type": f[0], "truncated": values[0], "occluded": int(f[2]), "alpha": values[2],
                    "bbox": values[3:7], "hwl": values[7:10], "xyz": values[10:13], "ry": values[13]})  # fmt: skip
    return out


def read_calib(path) -> dict[str, np.ndarray]:
    out = {}
    for line in path.read_text().splitlines():
        name, numbers = line.split(":", 1)
        out[name] = np.array(numbers.split(), dtype=np.float64)
    return out


def project(label: dict, p2: np.ndarray) -> np.ndarray:
    """The devkit's ``computeBox3D``: the 8 corners of the label's box in the image, shape (8, 2)."""
    h, w, length = label["hwl"]
    x = [length / 2, length / 2, -length / 2, -length / 2, length / 2, length / 2, -length / 2, -length / 2]
    y = [0, 0, 0, 0, -h, -h, -h, -h]
    z = [w / 2, -w / 2, -w / 2, w / 2, w / 2, -w / 2, -w / 2, w / 2]
    ry = label["ry"]
    rot = np.array([[math.cos(ry), 0, math.sin(ry)], [0, 1, 0], [-math.sin(ry), 0, math.cos(ry)]])
    corners = rot @ np.array([x, y, z]) + np.array(label["xyz"])[:, None]
    image = p2.reshape(3, 4) @ np.vstack([corners, np.ones(8)])
    return (image[:2] / image[2]).T


EGO = [0.0, 0, 0.75, 4.5, 1.8, 1.5, 0, 0, 0]


def test_labels_read_back_and_their_boxes_project_onto_the_2d_boxes(tmp_path) -> None:
    targets = [
        [16.0, 2.0, 0.75, 4.2, 1.8, 1.5, 0, 0, 0.3],  # ahead, left, turned
        [30.0, -4.0, 1.6, 10.0, 2.5, 3.2, 0, 0, math.pi],  # oncoming truck
        [12.0, -3.0, 0.9, 0.6, 0.6, 1.8, 0, 0, 1.2],  # a pedestrian
    ]
    table_in = scene([EGO, *targets], types=[2, 2, 2, 3], subtypes=[4, 4, 7, -1])
    cam = camera("front", 1242, 375, math.radians(81), x=1.0, z=1.65)  # KITTI's image size and about its fov
    table = get_visibility_df(table_in, 0, mode="3d", sensors=[cam], progress=False)
    written = write_kitti(table_in, table, [cam], tmp_path / "kitti", ego_idx=0)
    label_path = tmp_path / "kitti" / "front" / "label_2" / "000000.txt"
    calib_path = tmp_path / "kitti" / "front" / "calib" / "000000.txt"
    assert written == [label_path, calib_path]
    labels = read_label(label_path)
    calib = read_calib(calib_path)
    assert set(calib) == {"P0", "P1", "P2", "P3", "R0_rect", "Tr_velo_to_cam", "Tr_imu_to_velo"}
    assert np.allclose(calib["P2"].reshape(3, 4)[:, :3], cam.camera.matrix()) and np.allclose(
        calib["R0_rect"], np.eye(3).ravel()
    )
    assert [lab["type"] for lab in labels] == ["Car", "Truck", "Pedestrian"]
    rows = table.sort("idx")
    for lab, row in zip(labels, rows.iter_rows(named=True), strict=True):
        corners = project(lab, calib["P2"])
        u0, v0, u1, v1 = lab["bbox"]
        assert [u0, v0, u1, v1] == [float(v) for v in row["bbox_unoccluded"]]
        # the pixel centres inside the projected box: its extents, to the pixel (the devkit's two decimals move a
        # corner by a few hundredths of a pixel)
        lo, hi = corners.min(axis=0), corners.max(axis=0)
        assert abs(u0 - math.ceil(lo[0] - 0.5)) <= 1 and abs(u1 - math.floor(hi[0] - 0.5)) <= 1
        assert abs(v0 - math.ceil(lo[1] - 0.5)) <= 1 and abs(v1 - math.floor(hi[1] - 0.5)) <= 1
        assert lab["truncated"] == pytest.approx(row["truncation"], abs=0.005)
    # the first car: 16 m ahead, 2 m left of the ego's centre; the camera 1 m ahead of it at 1.65 m
    car = labels[0]
    assert car["xyz"] == pytest.approx([-2.0, 1.65, 15.0], abs=0.01)  # bottom centre: right, down, forward
    assert car["ry"] == pytest.approx(-(math.pi / 2 + 0.3), abs=0.01)  # turned 0.3 rad left of driving away
    assert car["alpha"] == pytest.approx(car["ry"] - math.atan2(-2.0, 15.0), abs=0.01)
    # Tr_velo_to_cam takes the ego frame (x forward, y left, z up, on the ground) to the camera's
    tr = calib["Tr_velo_to_cam"].reshape(3, 4)
    bottom = tr @ np.array([16.0, 2.0, 0.0, 1.0])
    assert bottom == pytest.approx(car["xyz"], abs=0.01)


def test_a_hidden_target_is_largely_occluded_and_one_behind_the_camera_has_no_line(tmp_path) -> None:
    boxes = [
        EGO,
        [14.0, 0, 1.5, 2, 4, 3.0, 0, 0, 0],
        [24.0, 0, 0.75, 4, 1.8, 1.5, 0, 0, 0],
        [-15.0, 0, 0.75, 4, 2, 1.5, 0, 0, 0],
    ]
    table_in = scene(boxes)
    cam = camera("front", 400, 200, math.radians(90), x=1.0)
    table = get_visibility_df(table_in, 0, mode="3d", sensors=[cam], progress=False)
    write_kitti(table_in, table, [cam], tmp_path / "k", ego_idx=0)
    labels = read_label(tmp_path / "k" / "front" / "label_2" / "000000.txt")
    assert len(labels) == 2 and [lab["occluded"] for lab in labels] == [0, 2]


def test_every_frame_gets_its_files_and_only_cameras_write(tmp_path) -> None:
    table_in = scene([EGO, [16.0, 0, 0.75, 4, 1.8, 1.5, 0, 0, 0]], frames=3)
    sensors = [camera("front", 320, 160, 1.4, x=1.0), Sensor("radar", fov=1.0)]
    table = get_visibility_df(table_in, 0, mode="3d", sensors=sensors, progress=False)
    written = write_kitti(table_in, table, sensors, tmp_path / "k", ego_idx=0)
    assert sorted(p.name for p in written) == sorted(["000000.txt", "000001.txt", "000002.txt"] * 2)
    assert not (tmp_path / "k" / "radar").exists()


def test_bad_calls_are_refused_in_words(tmp_path) -> None:
    table_in = scene([EGO, [16.0, 0, 0.75, 4, 1.8, 1.5, 0, 0, 0], [20.0, 5, 0.75, 4, 1.8, 1.5, 0, 0, 0]])
    cam = camera("front", 320, 160, 1.4, x=1.0)
    table = get_visibility_df(table_in, [0, 1], mode="3d", sensors=[cam], progress=False)
    with pytest.raises(ValueError, match="one observer's labels"):
        write_kitti(table_in, table, [cam], tmp_path / "a")
    with pytest.raises(ValueError, match="at least one camera"):
        write_kitti(table_in, table, [Sensor("radar")], tmp_path / "b")
    (tmp_path / "c").mkdir()
    (tmp_path / "c" / "x").write_text("")
    one = table.filter(pl.col("idx_ego") == 0)
    with pytest.raises(ValueError, match="new or empty folder"):
        write_kitti(table_in, one, [cam], tmp_path / "c")


def test_kitti_types_follow_the_omega_prime_classes() -> None:
    assert [kitti_type(2, s) for s in (2, 6, 7, 12, 13, 11)] == ["Car", "Van", "Truck", "Misc", "Tram", "Cyclist"]
    assert kitti_type(3, -1) == "Pedestrian" and kitti_type(4, None) == "Misc"
