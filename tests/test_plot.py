"""The frame plot draws what the table says."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import pytest
import shapely
from conftest import boxes_table

from omega_prime_visibility.plot import plot_frame


def test_plot_frame_colours_objects_by_visibility() -> None:
    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)])
    wall = shapely.LineString([(5, -8), (5, -4)])
    ax = plot_frame(df, 0, 0, [wall], target=2)
    cmap = plt.get_cmap("RdYlGn")
    faces = [tuple(p.get_facecolor()) for p in ax.patches]
    assert len(ax.patches) == 4  # visible region + 3 objects
    assert faces[2] == pytest.approx(cmap(1.0))  # idx 1, fully visible
    assert faces[3] == pytest.approx(cmap(0.0))  # idx 2, hidden
    assert ax.patches[2].get_linewidth() == 2.5  # occluder of the chosen target, outlined
    assert ax.figure.axes[-1].get_ylabel() == "visibility"
    plt.close(ax.figure)


def test_plot_frame_rejects_unknown_frame() -> None:
    with pytest.raises(ValueError, match="frame 3 does not occur"):
        plot_frame(boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0)]), 0, 3)
