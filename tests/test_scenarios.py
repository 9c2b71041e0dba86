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
