"""The roads of an OpenDRIVE map (reference lines, widths, points along them) and the check that a map given for
a trace fits its moving objects."""

from __future__ import annotations

import json
import math
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import polars as pl
import pytest

from omega_prime_visibility.inputs.io import RecordingReadError, read_recording
from omega_prime_visibility.inputs.roads import (
    ROAD_WIDTH,
    MapNotice,
    ReferenceLine,
    check_map_fits,
    road_points,
    road_widths,
)

# a road along y = 0 from x = 0 to 100, then an arc of radius 100 bending left (centre (100, 100)); two lanes of
# 3.5 m on its right, one of 3 m on its left
ROAD = """<OpenDRIVE><header revMajor="1" revMinor="6"/>
  <road name="r" length="200" id="7" junction="-1">
    <planView>
      <geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>
      <geometry s="100" x="100" y="0" hdg="0" length="100"><arc curvature="0.01"/></geometry>
    </planView>
    <lanes><laneSection s="0">
      <left><lane id="1"><width sOffset="0" a="3" b="0" c="0" d="0"/></lane></left>
      <right><lane id="-1"><width sOffset="0" a="3.5"/></lane><lane id="-2"><width sOffset="0" a="3.5"/></lane></right>
    </laneSection></lanes>
  </road>
</OpenDRIVE>"""


def test_widths_per_side_with_sections_and_cubic_widths() -> None:
    road = ET.fromstring(
        '<road length="100"><lanes><laneSection s="0"><left><lane id="1"><width sOffset="0" a="3"/></lane></left>'
        '<right><lane id="-1"><width sOffset="0" a="3"/></lane></right></laneSection>'
        '<laneSection s="50"><right><lane id="-1"><width sOffset="0" a="3" b="0.02"/></lane>'  # 3 m to 4 m
        '<lane id="-2"><width sOffset="0" a="2"/></lane></right></laneSection></lanes></road>'
    )
    assert road_widths(road) == (3.0, 6.0)  # the right side at its widest: 4 m + 2 m at the section's end
    assert road_widths(ET.fromstring('<road length="10"/>')) == (ROAD_WIDTH, ROAD_WIDTH)


def test_points_follow_lines_and_arcs_exactly() -> None:
    points, heading, widths = road_points(ET.fromstring(ROAD), spacing=2.0)
    line, arc = points[:, 0] <= 100, points[:, 0] > 100
    assert np.allclose(points[line, 1], 0.0) and np.allclose(heading[line], 0.0)
    assert np.allclose(np.hypot(points[arc, 0] - 100, points[arc, 1] - 100), 100.0, atol=1e-9)
    s = np.hypot(np.diff(points[:, 0]), np.diff(points[:, 1]))
    assert s.max() <= 2.0 + 1e-9 and len(points) == 101  # every 2 m over 200 m
    assert heading[-1] == pytest.approx(1.0)  # 100 m of curvature 0.01
    assert (widths == [3.0, 7.0]).all()
    x, y, h, _ = ReferenceLine(ET.fromstring(ROAD).find("road")).pose(np.array([150.0]))
    assert (x[0], y[0], h[0]) == pytest.approx((100 + 100 * math.sin(0.5), 100 - 100 * math.cos(0.5), 0.5))


class _Map:
    def __init__(self, xml: str) -> None:
        self.odr_xml = xml


class _Recording:
    """Objects each at ``positions`` (x, y, yaw) of their own, with a type (2 vehicle, 3 pedestrian)."""

    def __init__(self, objects: list[tuple[int, list[tuple[float, float, float]]]]) -> None:
        rows = [(k, t, x, y, yaw) for k, (t, track) in enumerate(objects) for x, y, yaw in track]
        self.map = _Map(ROAD)
        self._df = pl.DataFrame(rows, schema=["idx", "type", "x", "y", "yaw"], orient="row")


def along(y: float, yaw: float = 0.0, x0: float = 10.0, x1: float = 90.0) -> list[tuple[float, float, float]]:
    return [(x, y, yaw) for x in np.linspace(x0, x1, 30)]


def told(recording: _Recording) -> str | None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_map_fits(recording, Path("road.xodr"))
    notes = [str(w.message) for w in caught if issubclass(w.category, MapNotice)]
    return notes[0] if notes else None


def test_objects_on_the_lanes_fit_the_map() -> None:
    # in the right lanes (y -7 .. 0) either way, in the left lane, round the bend, a pedestrian crossing
    bend = [(100 + 100 * math.sin(a) + 3 * math.sin(a), 100 - 100 * math.cos(a) - 3 * math.cos(a), a)
            for a in np.linspace(0.05, 0.95, 20)]  # fmt: skip
    crossing = [(50.0, y, 1.57) for y in (-8, -3, 2, 4)]
    recording = _Recording([(2, along(-1.7)), (2, along(-5.2, math.pi)), (2, along(1.5)), (2, bend), (3, crossing)])
    assert told(recording) is None


@pytest.mark.parametrize(
    "objects",
    [
        [(2, along(-10.0)), (2, along(-11.0))],  # 3 to 4 m beyond the right lanes (2 m are allowed)
        [(2, along(6.0)), (2, along(-1.7))],  # one car beside the left lane: half the positions are off
        [(2, along(-1.7, math.pi / 2)), (2, along(-3.0, -math.pi / 2))],  # vehicles driving across the road
        [(2, [(x, y, 0.0) for x, y in ((5000.0, 3000.0), (-400.0, 20.0))])],  # far from every road
    ],
)
def test_objects_off_the_lanes_or_across_them_are_told(objects) -> None:
    note = told(_Recording(objects))
    assert note is not None and note.startswith("the map road.xodr does not fit the recording: ")
    assert "is it this trace's map?" in note


def test_headings_unknown_are_not_held_against_a_vehicle() -> None:
    # NaN or null yaw, or no yaw column at all: the heading test is left out, the position decides
    recording = _Recording([(2, along(-1.7)), (2, along(-5.2))])
    assert told(recording) is None
    for yaw in (pl.lit(float("nan")), pl.lit(None, dtype=pl.Float64)):
        recording._df = recording._df.with_columns(yaw=yaw)
        assert told(recording) is None
    recording._df = recording._df.drop("yaw")
    assert told(recording) is None
    across = _Recording([(2, along(-1.7, math.pi / 2)), (2, along(-3.0, math.pi / 2))])
    assert told(across) is not None  # (the heading test itself still applies where known)


def test_a_few_positions_off_the_map_are_not_told() -> None:
    # one car of six parks off the road (under a fifth of the positions): real traces have such
    objects = [(2, along(-1.7)) for _ in range(5)] + [(2, along(-20.0))]
    assert told(_Recording(objects)) is None


def test_the_shared_traces_and_their_maps(shared_data) -> None:
    # every trace with its own map (mapping.json) reads without a word; the wrong maps of the issue are told
    pairs = json.loads((shared_data / "mapping.json").read_text())
    for trace, map_name in pairs:
        if (shared_data / trace).is_file():
            with warnings.catch_warnings():
                warnings.simplefilter("error", MapNotice)
                warnings.filterwarnings("ignore", "is read with the map", MapNotice)
                read_recording(shared_data / trace, shared_data / map_name)
    for trace, map_name in (("pedestrian.osi", "straight_500m.xodr"), ("highway_merge.osi", "e6mini.xodr"),
                            ("acc-test.osi", "fabriksgatan.xodr"), ("pedestrian.osi", "soderleden.xodr")):  # fmt: skip
        with pytest.warns(MapNotice, match=rf"the map {map_name} does not fit the recording"):
            read_recording(shared_data / trace, shared_data / map_name)
    with pytest.raises(RecordingReadError, match=r"highway_merge\.mcap is a recording, not a map"):
        read_recording(shared_data / "acc-test.osi", shared_data / "highway_merge.mcap")


def test_the_shell_says_a_map_does_not_fit(shared_data) -> None:
    import subprocess
    import sys

    out = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility", "run", str(shared_data / "pedestrian.osi"), "--ego", "0",
         "--map", str(shared_data / "straight_500m.xodr"), "--rows", "1", "--no-progress"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert out.returncode == 0
    assert "warning: the map straight_500m.xodr does not fit the recording" in out.stderr
    out = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility", "run", str(shared_data / "acc-test.osi"), "--ego", "0",
         "--map", str(shared_data / "highway_merge.mcap")],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert out.returncode == 2 and out.stderr.count("\n") == 1 and "is a recording, not a map" in out.stderr
