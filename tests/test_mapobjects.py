"""OpenDRIVE road objects as static occluders: placement on the reference line, repeats, heights, the 2D rule."""

from __future__ import annotations

import math
import warnings

import numpy as np
import polars as pl
import pytest

from omega_prime_visibility import get_visibility_df
from omega_prime_visibility.threed.mapobjects import read_map_objects

XODR = """<?xml version="1.0"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="6"/>
  <road name="r" length="200" id="7" junction="-1">
    <planView>
      <geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>
      <geometry s="100" x="100" y="0" hdg="0" length="100"><arc curvature="0.01"/></geometry>
    </planView>
    <elevationProfile><elevation s="0" a="0.5" b="0" c="0" d="0"/></elevationProfile>
    <objects>
      <object id="1" type="barrier" name="box" s="20" t="-5" zOffset="0" hdg="0" length="4" width="1" height="2.5"/>
      <object id="2" type="railing" name="rail" s="0" t="4" zOffset="0.3" height="0.5">
        <repeat s="10" length="30" distance="0" tStart="4" tEnd="4" heightStart="0.5" heightEnd="0.5"
                zOffsetStart="0.3" zOffsetEnd="0.3"/>
      </object>
      <object id="3" type="pole" name="post" s="0" t="6" height="1.0" radius="0.1">
        <repeat s="0" length="20" distance="10"/>
      </object>
      <object id="4" type="building" name="house" s="150" t="10" height="8">
        <outline><cornerLocal u="0" v="0" z="0" height="8"/><cornerLocal u="5" v="0" z="0" height="8"/>
                 <cornerLocal u="5" v="5" z="0" height="8"/><cornerLocal u="0" v="5" z="0" height="8"/></outline>
      </object>
      <object id="5" type="pole" name="no size" s="5" t="2" height="1.0"/>
    </objects>
  </road>
</OpenDRIVE>
"""


@pytest.fixture
def xodr(tmp_path):
    path = tmp_path / "objects.xodr"
    path.write_text(XODR)
    return path


def test_objects_are_placed_on_the_reference_line(xodr) -> None:
    objs = read_map_objects(xodr)
    assert [o.id for o in objs] == ["1", "2", "3", "3", "3", "4"]  # the sizeless pole is left out
    box = objs[0]
    assert box.footprint.bounds == pytest.approx((18.0, -5.5, 22.0, -4.5))
    assert (box.base, box.top, box.height_above_road) == pytest.approx((0.5, 3.0, 2.5))
    rail = objs[1]
    assert rail.footprint.geom_type == "LineString" and rail.footprint.bounds == pytest.approx((10, 4, 40, 4))
    assert rail.top == pytest.approx(0.5 + 0.3 + 0.5) and rail.height_above_road == pytest.approx(0.8)
    posts = [o.footprint.centroid for o in objs[2:5]]
    assert [(round(p.x, 6), round(p.y, 6)) for p in posts] == [(0, 6), (10, 6), (20, 6)]
    # on the arc (curvature 0.01 from s = 100): 50 m on, the heading has turned by 0.5 rad
    house = objs[5]
    x0, y0 = 100 + math.sin(0.5) / 0.01, (1 - math.cos(0.5)) / 0.01
    px, py = x0 - 10 * math.sin(0.5), y0 + 10 * math.cos(0.5)
    corner = np.asarray(house.footprint.exterior.coords)
    assert np.min(np.hypot(corner[:, 0] - px, corner[:, 1] - py)) == pytest.approx(0.0, abs=1e-9)
    assert house.footprint.area == pytest.approx(25.0)


def test_bad_maps_are_named(tmp_path) -> None:
    with pytest.raises(ValueError, match=r"nothing\.xodr"):
        read_map_objects(tmp_path / "nothing.xodr")
    (tmp_path / "x.xodr").write_text("<notdrive/>")
    with pytest.raises(ValueError, match="not <OpenDRIVE>"):
        read_map_objects(tmp_path / "x.xodr")


def test_e6mini_railings(shared_data) -> None:
    objs = read_map_objects(shared_data / "e6mini.xodr")
    assert [o.type for o in objs] == ["railing", "railing"]
    assert all(o.height_above_road == pytest.approx(0.55) and o.footprint.length > 1400 for o in objs)


def cars(*xy) -> pl.DataFrame:
    n = len(xy)
    return pl.DataFrame(
        {
            "frame": [0] * n,
            "total_nanos": [0] * n,
            "idx": list(range(n)),
            "x": [p[0] for p in xy],
            "y": [p[1] for p in xy],
            "z": [0.75 + 0.5] * n,
            "length": [4.5] * n,
            "width": [1.8] * n,
            "height": [1.5] * n,
            "roll": [0.0] * n,
            "pitch": [0.0] * n,
            "yaw": [0.0] * n,
        }
    )


def test_map_occluders_and_the_2d_height_rule(xodr) -> None:
    # the ego at the road's start, a car behind the 0.8 m railing, another behind the 2.5 m barrier
    df = cars((0.0, 0.0), (25.0, 8.0), (40.0, -10.0))
    flat = get_visibility_df(df, 0, map_occluders=xodr).sort("idx")
    assert flat["visibility"].to_list()[0] == 1.0  # the railing is lower than a driver's eye: left out in 2D
    assert flat["visibility"].to_list()[1] == 0.0 and flat["static_occluder_idxs"].to_list()[1] == [0]
    solid = get_visibility_df(df, 0, map_occluders=xodr, mode="3d").sort("idx")
    railing_hides = solid.filter(pl.col("idx") == 1)
    assert 0.0 < railing_hides["visibility"].item() < 1.0 and railing_hides["static_occluder_idxs"].to_list() == [
        [1, 4]
    ]  # and the post at (20, 6)
    assert solid.filter(pl.col("idx") == 2)["visibility"].item() < 0.1


def test_a_map_that_adds_no_occluder_is_told(xodr, tmp_path) -> None:
    from omega_prime_visibility import VisibilityInputWarning

    df = cars((0.0, 0.0), (25.0, 8.0))
    bare = tmp_path / "bare.xodr"  # the same road without its objects
    bare.write_text(XODR[: XODR.index("<objects>")] + XODR[XODR.index("</objects>") + len("</objects>") :])
    with pytest.warns(VisibilityInputWarning, match=r"bare.xodr holds no road object .* adds no static occluder"):
        get_visibility_df(df, 0, map_occluders=bare)
    low = tmp_path / "low.xodr"  # only the 0.5 m railing: in 3D it blocks, in 2D it is below the eye
    objects = XODR[XODR.index("<objects>") : XODR.index("</objects>")]
    rail = objects[objects.index('<object id="2"') : objects.index('<object id="3"')]
    low.write_text(XODR.replace(objects, "<objects>" + rail))
    with pytest.warns(VisibilityInputWarning, match=r"none of the 1 road objects of the map .*low.xodr reaches"):
        get_visibility_df(df, 0, map_occluders=low)
    with warnings.catch_warnings():
        warnings.simplefilter("error", VisibilityInputWarning)
        get_visibility_df(df, 0, map_occluders=low, mode="3d")  # in 3D the railing blocks: nothing to tell
        get_visibility_df(df, 0, map_occluders=xodr)  # the barrier and the house block in 2D
