"""The camera picture: what it draws agrees with the table."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import polars as pl
import pytest

from omega_prime_visibility import get_visibility_df, plot_camera
from omega_prime_visibility.inputs.sensors import Sensor, camera

matplotlib.use("Agg")

NAMES = ("x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw")


def scene(boxes) -> pl.DataFrame:
    rows = np.asarray(boxes, dtype=np.float64)
    return pl.DataFrame({"frame": [0] * len(rows), "total_nanos": [0] * len(rows), "idx": list(range(len(rows))),
                         **{c: rows[:, k] for k, c in enumerate(NAMES)}})  # fmt: skip


BOXES = [[0.0, 0, 0.75, 4.5, 1.8, 1.5, 0, 0, 0], [14.0, 0.5, 0.75, 4.2, 1.8, 1.5, 0, 0, 0.2],
         [26.0, -1.0, 1.5, 10, 2.5, 3.0, 0, 0, 0], [20.0, 6.0, 0.75, 4.5, 1.8, 1.5, 0, 0, 0]]  # fmt: skip
CAM = camera("front", 640, 360, math.radians(80), x=1.5, z=1.4)


def test_the_picture_paints_the_tables_pixels() -> None:
    ax = plot_camera(scene(BOXES), 0, 0, sensors=[CAM])
    table = get_visibility_df(scene(BOXES), 0, mode="3d", sensors=[CAM], progress=False)
    painted = ax.images[0].get_array()
    assert painted.shape[:2] == (360, 640) and ax.get_xlim() == (0.0, 640.0) and ax.get_ylim() == (360.0, 0.0)
    assert int((painted[..., 3] > 0).sum()) == int(table["pixels"].sum())  # one painted pixel per first hit
    texts = [t.get_text() for t in ax.texts]
    assert any(t.startswith("1: ") for t in texts)


def test_the_picture_needs_a_camera() -> None:
    with pytest.raises(ValueError, match="camera"):
        plot_camera(scene(BOXES), 0, 0, sensors=[Sensor("radar")])
    with pytest.raises(ValueError, match="no camera named 'rear'"):
        plot_camera(scene(BOXES), 0, 0, sensors=[CAM], camera="rear")
