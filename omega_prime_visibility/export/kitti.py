"""KITTI object labels and calibration files: what each camera sees, as a detector benchmark reads it.

For every frame and camera of one observer, ``<folder>/<camera>/label_2/<frame:06d>.txt`` and
``<folder>/<camera>/calib/<frame:06d>.txt``, in the object devkit's format (its readme):

- a label line per target with a pixel in the image (``bbox_unoccluded``): ``type truncated occluded alpha left
  top right bottom height width length x y z rotation_y``; ``type`` from the object's type and subtype (Car, Van,
  Truck, Pedestrian, Cyclist, Tram, Misc); ``truncated`` and ``occluded`` as :func:`..analysis.levels.kitti_levels`
  gives them; the 2D box is the full box, its first and last pixel column and row (0-based indices); dimensions
  in metres; ``x y z`` the bottom centre of the box in the camera frame (x right, y down, z forward, metres);
  ``rotation_y`` the box's heading about the camera's y axis (0 along +x, ``-π/2`` driving away along +z) and
  ``alpha = rotation_y - atan2(x, z)``, both wrapped into [-π, π);
- the calibration: ``P0`` to ``P3`` all ``K [I | 0]`` (one camera, no stereo baseline), ``R0_rect`` the identity
  (the camera frame is already "rectified"), ``Tr_velo_to_cam`` from the observer's frame (x forward, y left, z
  up, at its bounding-box centre on the ground under it; roll and pitch ignored) to the camera, and
  ``Tr_imu_to_velo`` the identity.

Projecting a label's 3D box with ``P2`` gives back its 2D box (to the pixel; the tests do it). KITTI's boxes are
upright: a box's roll and pitch are left out of ``rotation_y``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import polars as pl

from ..analysis.levels import kitti_levels
from ..engines.imaging.scene import sensor_axes
from ..inputs.roles import SUBTYPES, TYPES
from ..inputs.scene import as_lazy
from ..inputs.sensors import Sensor, sensor_poses
from ..threed.boxes import rotations

_KITTI_SUBTYPES = {
    "DELIVERY_VAN": "Van", "HEAVY_TRUCK": "Truck", "SEMITRACTOR": "Truck", "SEMITRAILER": "Truck", "TRAILER": "Misc",
    "BUS": "Misc", "BICYCLE": "Cyclist", "MOTORBIKE": "Cyclist", "TRAM": "Tram", "TRAIN": "Tram",
}  # fmt: skip
_BY_CODE = {SUBTYPES[name]: kitti for name, kitti in _KITTI_SUBTYPES.items()}


def kitti_type(kind: int | None, subtype: int | None) -> str:
    """KITTI's class of an omega-prime object ``type`` and vehicle ``subtype``.

    >>> kitti_type(2, 4), kitti_type(2, 11), kitti_type(3, None), kitti_type(2, None), kitti_type(None, None)
    ('Car', 'Cyclist', 'Pedestrian', 'Car', 'Misc')
    """
    if kind == TYPES["PEDESTRIAN"]:
        return "Pedestrian"
    if kind == TYPES["VEHICLE"]:
        return _BY_CODE.get(subtype, "Car") if subtype is not None else "Car"
    return "Misc"


def _wrap(angle: np.ndarray) -> np.ndarray:
    return (np.asarray(angle) + math.pi) % (2 * math.pi) - math.pi


def calibration_lines(sensor: Sensor, vehicle_to_camera: np.ndarray) -> str:
    """The calibration file's text for ``sensor`` (a camera) and the 3 x 4 ``Tr_velo_to_cam``."""
    k = sensor.camera.matrix()  # type: ignore[union-attr]
    projection = np.hstack([k, np.zeros((3, 1))])

    def row(name: str, values: np.ndarray) -> str:
        return f"{name}: " + " ".join(f"{v:.12e}" for v in np.asarray(values, dtype=np.float64).ravel())

    lines = [row(f"P{c}", projection) for c in range(4)]
    lines += [row("R0_rect", np.eye(3)), row("Tr_velo_to_cam", vehicle_to_camera), row("Tr_imu_to_velo", np.eye(3, 4))]
    return "\n".join(lines) + "\n"


def camera_pose(sensor: Sensor, ego: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The eye (metres, world), the camera's axes (rows, world) and ``Tr_velo_to_cam`` of ``sensor`` on the
    observer row ``ego`` (``x, y, z, height, yaw``)."""
    position, heading = sensor_poses(sensor, np.array([[ego["x"], ego["y"]]]), np.array([ego["yaw"]]))
    ground = ego["z"] - ego["height"] / 2
    eye = np.array([position[0, 0], position[0, 1], ground + sensor.z])
    axes = sensor_axes(float(heading[0]), sensor.pitch, "camera")
    c, s = math.cos(ego["yaw"]), math.sin(ego["yaw"])
    vehicle = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])  # columns: the observer's axes in the world
    origin = np.array([ego["x"], ego["y"], ground])
    to_camera = np.hstack([axes @ vehicle, (axes @ (origin - eye))[:, None]])
    return eye, axes, to_camera


def label_lines(rows: pl.DataFrame, objects: pl.DataFrame, eye: np.ndarray, axes: np.ndarray) -> str:
    """The label file's text: one line per row of ``rows`` (a table's rows of one frame and camera, with
    :func:`..analysis.levels.kitti_levels`' columns) whose target has a pixel in the image; ``objects`` holds
    their boxes (``idx, x, y, z, length, width, height, roll, pitch, yaw, type, subtype``)."""
    rows = rows.filter(pl.col("bbox_unoccluded").is_not_null()).join(objects, on="idx", how="left")
    if rows.is_empty():
        return ""
    centre = rows.select("x", "y", "z").to_numpy().astype(np.float64)
    height = rows["height"].to_numpy().astype(np.float64)
    turn = rotations(*(rows[c].fill_null(0.0).to_numpy().astype(np.float64) for c in ("roll", "pitch", "yaw")))
    bottom = centre - turn[:, :, 2] * (height[:, None] / 2)
    location = (bottom - eye) @ axes.T
    forward = turn[:, :, 0] @ axes.T
    rotation_y = _wrap(-np.arctan2(forward[:, 2], forward[:, 0]))
    alpha = _wrap(rotation_y - np.arctan2(location[:, 0], location[:, 2]))
    boxes = np.stack(rows["bbox_unoccluded"].to_numpy()).astype(np.float64)
    kinds = rows["type"].to_list() if "type" in rows.columns else [None] * rows.height
    subtypes = rows["subtype"].to_list() if "subtype" in rows.columns else [None] * rows.height
    lines = []
    for k in range(rows.height):
        kind = kitti_type(kinds[k], subtypes[k])
        numbers = [
            *boxes[k], height[k], rows["width"][k], rows["length"][k], *location[k], rotation_y[k],
        ]  # fmt: skip
        truncated = min(max(float(rows["kitti_truncated"][k]), 0.0), 1.0)
        lines.append(
            f"{kind} {truncated:.2f} {int(rows['kitti_occluded'][k])} {alpha[k]:.2f} "
            + " ".join(f"{float(v):.2f}" for v in numbers)
        )
    return "\n".join(lines) + "\n"


def write_kitti(
    recording: Any,
    table: pl.DataFrame,
    sensors: list[Sensor] | tuple[Sensor, ...],
    folder: str | os.PathLike,
    ego_idx: int | None = None,
    occluded_bounds: tuple[float, float] = (0.0, 0.5),
) -> list[Path]:
    """Write KITTI label and calibration files (see the module docstring) for the cameras among ``sensors`` from
    ``table`` (:func:`~omega_prime_visibility.get_visibility_df` with those sensors, ``mode="3d"``) of
    ``recording`` (what the table was computed from); the paths written, label files first.

    ``ego_idx`` names the observer where the table has no ``idx_ego`` column; a table of several observers is
    refused (write one at a time). ``folder`` must not exist yet or be empty; files are written whole.
    """
    cameras = [s for s in sensors if isinstance(s, Sensor) and s.camera is not None]
    if not cameras:
        raise ValueError("write_kitti needs at least one camera among the sensors (inputs.sensors.camera)")
    names = table.columns
    for needed in ("frame", "idx", "sensor", "bbox_unoccluded"):
        if needed not in names:
            raise ValueError(f"write_kitti needs a table computed with the cameras (mode='3d'): no {needed!r} column")
    if "idx_ego" in names:
        egos = table["idx_ego"].unique().to_list()
        if len(egos) > 1:
            raise ValueError(f"write_kitti writes one observer's labels; the table has {len(egos)}: filter it first")
        ego_idx = egos[0] if egos else ego_idx
    if ego_idx is None:
        raise ValueError("write_kitti needs ego_idx: the table has no idx_ego column")
    folder = Path(folder)
    if folder.exists() and (not folder.is_dir() or any(folder.iterdir())):
        raise ValueError(f"write_kitti writes into a new or empty folder; {folder} is not one")
    columns = ["frame", "idx", "x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw", "type", "subtype"]
    lazy = as_lazy(recording)
    present = [c for c in columns if c in lazy.collect_schema().names()]
    objects = lazy.select(present).collect()
    for c in ("roll", "pitch"):
        if c not in objects.columns:
            objects = objects.with_columns(pl.lit(0.0).alias(c))
    labelled = kitti_levels(table, occluded_bounds)
    written_labels, written_calib = [], []
    for sensor in cameras:
        mine = labelled.filter(pl.col("sensor") == sensor.name)
        (folder / sensor.name / "label_2").mkdir(parents=True, exist_ok=True)
        (folder / sensor.name / "calib").mkdir(parents=True, exist_ok=True)
        for frame in sorted(mine["frame"].unique().to_list()):
            here = objects.filter(pl.col("frame") == frame).drop("frame")
            ego = here.filter(pl.col("idx") == ego_idx)
            if ego.is_empty():
                continue
            eye, axes, to_camera = camera_pose(sensor, ego.row(0, named=True))
            rows = mine.filter(pl.col("frame") == frame)
            label = folder / sensor.name / "label_2" / f"{frame:06d}.txt"
            calib = folder / sensor.name / "calib" / f"{frame:06d}.txt"
            _write_whole(label, label_lines(rows, here, eye, axes))
            _write_whole(calib, calibration_lines(sensor, to_camera))
            written_labels.append(label)
            written_calib.append(calib)
    return written_labels + written_calib


def _write_whole(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary name, so that no half-written file is left."""
    temporary = path.with_name(path.name + ".part")
    temporary.write_text(text)
    temporary.replace(path)
