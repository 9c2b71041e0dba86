"""The scenes of scenarios/: the urban junction is what it says (no road user overlaps another or stands in a
building, the same table on every run) and both engines agree on it."""

from __future__ import annotations

import sys

import numpy as np
import polars as pl
import pytest
from conftest import REPO

sys.path.insert(0, str(REPO / "scenarios"))
from urban import check_no_overlap, urban_scene

from omega_prime_visibility import get_visibility_df


@pytest.fixture(scope="module")
def town():
    return urban_scene(frames=120)


def test_the_town_is_a_town(town) -> None:
    table, buildings = town
    check_no_overlap(table, buildings, every=10)
    first = table.filter(pl.col("frame") == 0)
    assert first.height > 250 and len(buildings) == 20
    assert set(first["type"].to_list()) == {2, 3} and (first["subtype"] == 12).any()  # vehicles, pedestrians, buses
    assert any(len(b.interiors) == 1 for b in buildings)  # courtyards
    again, _ = urban_scene(frames=120)
    assert again.equals(table)


def test_both_engines_agree_in_town(town) -> None:
    table, buildings = town
    some = table.filter(pl.col("frame").is_in([0, 40, 80, 119]))
    sweep = get_visibility_df(some, [0, 5], buildings, engine="sweep", progress=False)
    visilibity = get_visibility_df(some, [0, 5], buildings, engine="visilibity", progress=False)
    assert sweep.drop("visibility").equals(visilibity.drop("visibility"))
    assert np.abs(sweep["visibility"].to_numpy() - visilibity["visibility"].to_numpy()).max() < 1e-6
    hidden = sweep.filter(pl.col("visibility") == 0)
    assert hidden.height > sweep.height / 3 and hidden["static_occluder_idxs"].list.len().max() > 0


class CountingVisiLibity:
    """Stands in for the compiled module and counts the visibility polygons asked of it."""

    def __init__(self, module) -> None:
        self.module, self.polygons = module, 0

    def visibility_polygon(self, *args):
        self.polygons += 1
        return self.module.visibility_polygon(*args)

    def __getattr__(self, name: str):
        return getattr(self.module, name)


def test_the_default_engine_builds_one_polygon_a_frame_in_town(town, monkeypatch) -> None:
    # VisiLibity 1.0.10's sweep missed a body in about one frame in five here (its edge queue ordered at earlier
    # bearings); each such frame was computed again from halves of the holes, about 7 polygons. Patched
    # (native/visilibity.cpp, Edge_Queue): one polygon a frame, which the exact check accepts.
    from omega_prime_visibility.engines.visilibity import conversion

    table, buildings = town
    counting = CountingVisiLibity(conversion._visilibity1)
    monkeypatch.setattr(conversion, "_visilibity1", counting)
    frames = table.filter(pl.col("frame") < 60)
    out = get_visibility_df(frames, 0, buildings, workers=1, progress=False)
    assert out["frame"].n_unique() == 60 and counting.polygons == 60
