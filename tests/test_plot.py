"""The frame plot draws what the table says: colours, outlines, sensors' wedges, statics, lanes, legend."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import polars as pl
import pytest
import shapely
from conftest import boxes_table
from matplotlib.colors import to_rgb
from matplotlib.patches import Circle, Wedge

import omega_prime_visibility
from omega_prime_visibility import Query
from omega_prime_visibility.plot import plot_frame
from omega_prime_visibility.plot._optional import require
from omega_prime_visibility.sensors import Sensor

CMAP = plt.get_cmap("cividis")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def by_gid(ax, gid: str) -> list:
    return [a for a in [*ax.patches, *ax.lines] if a.get_gid() == gid]


def texts(ax) -> list[str]:
    return [t.get_text() for t in ax.texts]


def test_plot_frame_colours_objects_by_visibility_and_outlines_occluders() -> None:
    # ego at the origin; idx 1 (4 m wide at x = 10) hides idx 2 (2 m wide at x = 20) completely
    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)])
    ax = plot_frame(df, 0, 0, target=2)
    (blocker,) = by_gid(ax, "object 1")
    (hidden,) = by_gid(ax, "object 2")
    (ego,) = by_gid(ax, "ego")
    assert tuple(blocker.get_facecolor()) == pytest.approx(CMAP(1.0))
    assert tuple(hidden.get_facecolor()) == pytest.approx(CMAP(0.0))
    assert blocker.get_linewidth() == 2.5 and blocker.get_edgecolor()[:3] == (0, 0, 0)  # occluder of the target
    assert by_gid(ax, "target outline")[1].get_linestyle() == "--"  # the target, dashed round
    assert ego.get_facecolor()[:3] == pytest.approx(matplotlib.colors.to_rgb("#D55E00"))
    assert {"1: 100%", "2: 0%", "ego 0"} <= set(texts(ax))
    colourbar = ax.figure.axes[-1]
    assert colourbar.get_ylim() == (0.0, 1.0) and colourbar.get_ylabel().startswith("visibility")
    legend = ax.figure.legends[0] if ax.figure.legends else ax.get_legend()
    labels = [t.get_text() for t in legend.get_texts()]
    assert "hides 2" in labels and "target 2" in labels
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    assert (x0 + x1) / 2 == pytest.approx(10.0) and (y0 + y1) / 2 == pytest.approx(0.0)  # centred on what is near
    # the window: objects reach x = 22, plus 3 m; y at least 0.3 of the default 50 m reach; then one side widened
    # to the axes' shape
    assert x1 >= 25.0 - 1e-9 and y1 >= 15.0 - 1e-9
    assert x1 == pytest.approx(25.0) or y1 == pytest.approx(15.0)


def test_plot_frame_half_hidden_target_gets_the_middle_colour() -> None:
    # a thin target across y in [-2, 2] at x ~ 20; a thin blocker across y in [0, 2] at x ~ 10 hides exactly the
    # upper half of its angular extent (both seen from the origin): visibility 0.5
    df = boxes_table([(0, 0, 1, 1, 0), (10, 1, 0.2, 2, 0), (20, 0, 0.2, 4, 0)])
    ax = plot_frame(df, 0, 0)
    (target,) = by_gid(ax, "object 2")
    face = tuple(target.get_facecolor())
    # 0.5 lies on the border of two of the colour map's 256 entries: either neighbour is right
    assert face == pytest.approx(CMAP(0.4999)) or face == pytest.approx(CMAP(0.5001))
    assert face != pytest.approx(CMAP(0.48)) and face != pytest.approx(CMAP(0.52))
    assert "2: 50%" in texts(ax)


@pytest.mark.parametrize("yaw", [0.0, math.pi / 2])
def test_plot_frame_draws_sensor_wedges_at_their_pose(yaw: float) -> None:
    df = boxes_table([(5, 5, 4, 2, yaw), (30, 5, 4, 2, 0)])
    cam = Sensor("cam", x=1.0, fov=math.radians(60), range=15.0)
    ax = plot_frame(df, 0, 0, sensors=[cam, Sensor("roof", range=40.0)])
    (wedge,) = [p for p in by_gid(ax, "sensor cam") if isinstance(p, Wedge)]
    # mounted 1 m ahead of the ego's centre, along its heading
    assert wedge.center == pytest.approx((5 + math.cos(yaw), 5 + math.sin(yaw)))
    assert (wedge.theta1, wedge.theta2) == pytest.approx((math.degrees(yaw) - 30, math.degrees(yaw) + 30))
    assert wedge.r == 15.0  # the range is the wedge's arc
    assert wedge.get_fill() is False and wedge.get_edgecolor()[:3] == pytest.approx(to_rgb("#E69F00"))  # outlined
    (circle,) = [p for p in by_gid(ax, "sensor roof") if isinstance(p, Circle)]
    assert circle.get_radius() == 40.0 and circle.center == pytest.approx((5, 5))
    assert circle.get_edgecolor()[:3] == pytest.approx(to_rgb("#0072B2"))  # the second Okabe-Ito colour
    legend = ax.figure.legends[0] if ax.figure.legends else ax.get_legend()
    assert "cam 60° 15 m" in [t.get_text() for t in legend.get_texts()]


def test_plot_frame_sensor_layouts_are_sized_to_the_ego() -> None:
    df = boxes_table([(0, 0, 5.0, 2.0, 0), (30, 0, 4, 2, 0)])
    ax = plot_frame(df, 0, 0, sensors="typical")
    (radar,) = [p for p in by_gid(ax, "sensor front_radar") if isinstance(p, Wedge)]
    assert radar.center == pytest.approx((2.5, 0.0))  # front bumper of a 5 m ego


@pytest.mark.parametrize("view_range", ["auto", 12.0])
def test_a_small_ego_keeps_its_colour_under_the_star_and_the_sensors(view_range) -> None:
    """At the sensors' reach of 80 m a 5 m ego is a few pixels across: no mount dots on it, and a star of at most
    0.4 of its size (at least 4 points); at 12 m it is large: a dot at each of the six mounts and the 10 pt star."""
    df = boxes_table([(0, 0, 5.0, 2.0, 0), (75, 0, 4, 2, 0), (-75, 0, 4, 2, 0), (0, 60, 4, 2, 0)])
    ax = plot_frame(df, 0, 0, sensors="typical", view_range=view_range)
    ego_px = float(np.ptp(ax.transData.transform(by_gid(ax, "ego")[0].get_xy()), axis=0).max())
    (star,) = by_gid(ax, "star")
    star_px = star.get_markersize() * ax.figure.dpi / 72
    if view_range == "auto":
        assert ego_px < 40 and not by_gid(ax, "mount")
        assert star_px <= max(0.4 * ego_px, 4 * ax.figure.dpi / 72) + 1e-9
    else:
        assert ego_px >= 40 and len(by_gid(ax, "mount")) == 6
        assert star.get_markersize() == 10


def test_plot_frame_statics_hatched_and_black_when_they_hide_the_target() -> None:
    df = boxes_table([(0, 0, 4, 2, 0), (20, 0, 4, 2, 0), (0, 30, 4, 2, 0)])
    wall = shapely.box(9, -3, 10, 3)  # hides idx 1
    aside = shapely.box(9, 10, 10, 12)  # hides nothing
    ax = plot_frame(df, 0, 0, [wall, aside], target=1)
    (hiding,) = by_gid(ax, "static 0")
    (idle,) = by_gid(ax, "static 1")
    assert hiding.get_hatch() == idle.get_hatch() == "///"
    assert hiding.get_edgecolor()[:3] == (0, 0, 0) and idle.get_edgecolor()[:3] != (0, 0, 0)
    assert "1: 0%" in texts(ax)


def test_plot_frame_draws_given_lanes_underneath() -> None:
    df = boxes_table([(0, 0, 4, 2, 0), (20, 0, 4, 2, 0)])
    lanes = [shapely.LineString([(-50, 1.75), (50, 1.75)]), shapely.LineString([(-50, -1.75), (50, -1.75)])]
    ax = plot_frame(df, 0, 0, lanes=lanes)
    (drawn,) = [c for c in ax.collections if c.get_gid() == "lane"]  # one collection for all centre lines
    assert drawn.get_zorder() < 0
    assert [np.asarray(p).tolist() for p in drawn.get_segments()] == [
        [[-50, 1.75], [50, 1.75]],
        [[-50, -1.75], [50, -1.75]],
    ]


def test_plot_frame_on_a_given_axes_returns_it() -> None:
    _, ax = plt.subplots()
    out = plot_frame(boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 2, 0)]), 0, 0, ax=ax, view_range=None)
    assert out is ax and ax.get_legend() is not None  # legend inside the axes of a figure without layout engine


def test_plot_frame_rejects_unknown_frame_and_absent_ego() -> None:
    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0)])
    with pytest.raises(ValueError, match="frame 3 does not occur"):
        plot_frame(df, 0, 3)
    with pytest.raises(ValueError, match=r"ego idx \[7\] never occurs"):
        plot_frame(df, 7, 0)
    with pytest.raises(ValueError, match="cmap 'sunset' is not a matplotlib colour map"):
        plot_frame(df, 0, 0, cmap="sunset")


def test_plotting_is_public_and_lazy() -> None:
    assert omega_prime_visibility.plot_frame is plot_frame
    for name in ("animate", "timeline_chart", "save_timeline", "write_report"):
        assert callable(getattr(omega_prime_visibility, name))


def test_importing_the_package_loads_no_plotting_library() -> None:
    code = (
        "import sys, omega_prime_visibility as o; o.plot_frame; "
        "print(sorted(m for m in ('matplotlib', 'altair', 'vl_convert', 'PIL', 'imageio_ffmpeg') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"  # plot_frame itself imports matplotlib only when it draws


def test_pictures_of_an_mcap_recording_do_not_import_omega_prime(tmp_path) -> None:
    # importing omega-prime (for the map's lanes) made a first picture 2.5 s slower than later ones
    code = (
        "import sys, warnings, matplotlib; matplotlib.use('Agg'); from pathlib import Path; "
        "from omega_prime_visibility import animate, plot_frame, read_recording, write_report; "
        f"out = Path({str(tmp_path)!r}); r = read_recording('highway_merge.mcap'); "
        "ax = plot_frame(r, 0, 30); ax.figure.canvas.draw(); "
        "animate(r, 0, out / 'a.gif', frames=slice(0, 3), progress=False); "
        "write_report(r, 0, out / 'r.html', progress=False); "
        "print('omega_prime' in sys.modules, sum(a.get_gid() == 'lane' for a in ax.lines + ax.collections))"
    )
    repo = Path(__file__).resolve().parent.parent
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=repo)
    imported, lanes = out.stdout.split()
    assert imported == "False" and int(lanes) > 0  # the lanes are drawn all the same


def test_missing_plotting_library_names_the_extra(monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "vl_convert", None)  # as if not installed
    with pytest.raises(ImportError, match=r"omega-prime-visibility\[plot\]"):
        require("vl_convert")


def test_the_window_holds_every_object_that_comes_within_the_view_range() -> None:
    # a north-south street: the ego at the origin facing north; a pedestrian 47 m ahead; a 12 m truck whose centre
    # is 65 m away but whose rear (at 59 m) comes within the 60 m view range; a car 70 m to the east (out of range)
    boxes = [(0, 0, 4, 2, math.pi / 2), (0, 47, 0.6, 0.5, 0), (0, -65, 12, 2.5, math.pi / 2), (70, 0, 4, 2, 0)]
    df = boxes_table(boxes)
    ax = plot_frame(df, 0, 0, view_range=60)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    # the whole truck and the pedestrian, 3 m around them: the window bounds what is near, wherever it lies
    assert y0 == pytest.approx(-71 - 3) and y1 == pytest.approx(47.25 + 3)
    assert x1 - x0 < 2 * 70  # the car out of range does not stretch the window (the axes' shape may widen it)
    assert (x0 + x1) / 2 == pytest.approx(0)  # nothing near to either side: centred across the street
    assert y1 - y0 > x1 - x0  # a tall window for a street running north-south
    (bar,) = by_gid(ax, "scale bar")
    (label,) = [t for t in ax.texts if t.get_gid() == "scale bar label"]
    (bx0, bx1), (by0, by1) = bar.get_data()
    length = float(label.get_text().removesuffix(" m"))
    assert bx1 - bx0 == pytest.approx(length) and by0 == by1  # a horizontal bar as long as its label says
    assert length in (1, 2, 5, 10, 20, 50, 100) and (x1 - x0) / 12 <= length <= (x1 - x0) / 5
    assert x0 < bx0 < bx1 < x1 and y0 < by0 < y1  # on the picture
    # by default a street's reach, 50 m: the pedestrian at 47 m is on it, the truck (rear at 59 m) is not needed
    y0, y1 = plot_frame(df, 0, 0).get_ylim()
    assert y1 >= 47.25 and y0 > -71 - 3


def test_lanes_are_simplified_merged_and_prepared_once_per_map() -> None:
    from types import SimpleNamespace

    from omega_prime_visibility.plot.lanes import prepared_lanes

    # two overlapping lanes, each outline with 2,001 vertices along a straight 100 m edge (as OpenDRIVE maps have)
    edge = np.linspace(0, 100, 2001)

    def lane(y0, y1):
        return shapely.Polygon(np.r_[np.c_[edge, np.full_like(edge, y0)], np.c_[edge[::-1], np.full_like(edge, y1)]])

    road_map = SimpleNamespace(lanes={1: SimpleNamespace(polygon=lane(0, 3.5), centerline=None),
                                      2: SimpleNamespace(polygon=lane(3.0, 6.5), centerline=None)})  # fmt: skip
    lanes = prepared_lanes(road_map)
    (ring,) = lanes.surfaces  # one road surface, shaded once where the lanes overlap
    assert shapely.Polygon(ring).area == pytest.approx(100 * 6.5) and len(ring) <= 10
    assert prepared_lanes(road_map) is lanes  # cached for this map
    # a ring road keeps its hole, running the other way round
    ring_road = shapely.box(0, 0, 50, 50).difference(shapely.box(10, 10, 40, 40))
    outer, hole = prepared_lanes([ring_road]).surfaces
    assert shapely.LinearRing(outer).is_ccw and not shapely.LinearRing(hole).is_ccw
    assert np.ptp(lanes.points[:, 0]) == pytest.approx(100) and np.diff(np.sort(lanes.points[:, 0])).max() <= 5.0


def test_labels_never_overlap_even_on_a_crowded_frame() -> None:
    # a queue of small cars nose to tail (0.2 m apart) ahead of the ego, and two beside it: their labels are wider
    # than a car, so they cannot all go above their cars
    # (a car 30 m away widens the window, so the labels are wide against the cars' spacing)
    queue = [(4 + 1.2 * k, 0, 1.0, 1, 0) for k in range(6)]
    boxes = [(0, 0, 4, 2, 0), *queue, (0, 2.5, 3, 1.5, 0), (0, -2.5, 3, 1, 0), (0, 30, 4, 2, 0)]
    ax = plot_frame(boxes_table(boxes), 0, 0, view_range=40)
    ax.figure.canvas.draw()
    renderer = ax.figure.canvas.get_renderer()
    labels = [t for t in ax.texts if t.get_gid() == "label" and t.get_visible()]
    assert "ego 0" in [t.get_text() for t in labels]  # the ego's label comes first
    extents = [t.get_window_extent(renderer) for t in labels]
    for i, a in enumerate(extents):
        for b in extents[i + 1 :]:
            assert not a.overlaps(b), "two labels overlap"


def test_a_table_of_several_observers_gives_each_its_own_numbers() -> None:
    # three cars in a row, every one an observer: seen from idx 0, car 2 is hidden; seen from idx 2, car 0 is
    import polars as pl

    from omega_prime_visibility import get_visibility_df
    from omega_prime_visibility.plot.data import FrameViewer, load_source

    cars = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 2, 0), (20, 0, 4, 2, 0)])
    table = get_visibility_df(cars, "all")
    assert "idx_ego" in table.columns
    source = load_source(cars, Query(observers=0), lanes=False)
    for ego in (0, 2):
        view = FrameViewer(source, ego, table=table).view(0)
        own = table.filter(pl.col("idx_ego") == ego)
        expected = dict(zip(own["idx"].to_list(), own["visibility"].to_list(), strict=True))
        got = {i: v for i, v in zip(view.idx.tolist(), view.visibility.tolist(), strict=True) if i != ego}
        assert got == expected and set(got.values()) == {0.0, 1.0}


@pytest.mark.parametrize("mode", ["2d", "3d"])
def test_objects_that_may_not_block_hide_nothing_in_the_picture(mode: str) -> None:
    # ego, a pedestrian (idx 1, 0.5 m) 5 m ahead, a car (idx 2) at 15 m: with only vehicles blocking, the region
    # just behind the pedestrian is seen and the car is fully visible, as in the table of that choice; by default
    # the pedestrian hides both
    import polars as pl

    from omega_prime_visibility import get_visibility_df
    from omega_prime_visibility.plot.data import load_source
    from omega_prime_visibility.plot.frame import picture_viewer

    df = boxes_table([(0, 0, 4, 2, 0), (5, 0, 0.5, 0.5, 0), (15, 0, 4, 2, 0)]).with_columns(
        type=pl.Series([2, 3, 2]),
        subtype=pl.Series([4, 0, 4]),
        z=pl.lit(0.75),
        height=pl.lit(1.5),
        roll=pl.lit(0.0),
        pitch=pl.lit(0.0),
    )
    behind = shapely.Point(6.0, 0.0)
    for occluders, car in ((None, None), ("vehicles", 1.0)):
        question = Query(observers=0, mode=mode, occluders=occluders)
        source = load_source(df, question, lanes=False)
        viewer = picture_viewer(df, source, question, np.array([0]), 80.0)
        view = viewer.view(0)
        if mode == "3d":  # no ground region in 3D (the table's numbers are seen from the eye)
            assert view.region.is_empty
        else:
            assert view.region.contains(behind) == (occluders is not None)
        table = get_visibility_df(df, 0, mode=mode, occluders=occluders)
        want = dict(zip(table["idx"].to_list(), table["visibility"].to_list(), strict=True))
        got = dict(zip(view.idx.tolist()[1:], view.visibility.tolist()[1:], strict=True))
        assert got == pytest.approx(want, abs=1e-12)
        assert car is None or got[2] == pytest.approx(car)
    ax = plot_frame(df, 0, 0, occluders="vehicles", lanes=False)
    assert ax is not None
    plt.close("all")
    with pytest.raises(ValueError, match="occluders"):
        load_source(df, Query(observers=0, occluders="walkers"), lanes=False)
    # an idx of the recording that the frames drawn do not hold is no error (as for get_visibility_df)
    later = df.with_columns(frame=pl.lit(1, pl.Int64), total_nanos=pl.lit(10**8, pl.Int64), idx=pl.col("idx") + 10)
    both = pl.concat([df, later])
    question = Query(observers=0, mode=mode, occluders=[0, 12])
    source = load_source(both, question, lanes=False)
    view = picture_viewer(both, source, question, np.array([0]), 80.0).view(0)
    assert view.region.contains(behind) or (mode == "3d" and view.region.is_empty)  # only the ego may block


def test_through_sensors_the_outlines_follow_the_number_shown() -> None:
    # ego at the origin (1 x 1 m), target 2 across y in [-1, 1] at x = 20, blocker 1 at x = 10, y in [1.5, 2.5].
    # Sensor "low" at (0, -3) passes below the blocker (its rays cross x = 10 at y in [-2, -1]): it sees all of the
    # target. Sensor "high" at (0, 3) sees it through x = 10 at y = 3 + (y - 3) / 2, so the blocker hides the part
    # y >= 0 (part of its angle). The picture shows the best sensor's 100 %, so the blocker is no "hides 2" outline.
    from omega_prime_visibility import get_visibility_df

    df = boxes_table([(0, 0, 1, 1, 0), (10, 2, 1, 1, 0), (20, 0, 1, 2, 0)])
    sensors = [Sensor("high", x=0.0, y=3.0, fov=1.0), Sensor("low", x=0.0, y=-3.0, fov=1.0)]
    table = get_visibility_df(df, 0, sensors=sensors, progress=False).filter(idx=2)
    seen = dict(zip(table["sensor"], table["visibility"], strict=True))
    assert 0.0 < seen["high"] < 1.0 and seen["low"] == 1.0
    assert table.filter(sensor="high")["occluder_idxs"].to_list() == [[1]]
    ax = plot_frame(df, 0, 0, target=2, sensors=sensors)
    (blocker,) = by_gid(ax, "object 1")
    (target,) = by_gid(ax, "object 2")
    assert tuple(target.get_facecolor()) == pytest.approx(CMAP(1.0)) and "2: 100%" in texts(ax)
    assert blocker.get_linewidth() != 2.5  # not outlined as hiding the target
    # with the low sensor alone blocked too (a second blocker below), the best is the high one's half: outlined
    df = boxes_table([(0, 0, 1, 1, 0), (10, 2, 1, 1, 0), (20, 0, 1, 2, 0), (10, -1.5, 1, 1, 0)])
    ax = plot_frame(df, 0, 0, target=2, sensors=sensors)
    assert by_gid(ax, "object 1")[0].get_linewidth() == 2.5 or by_gid(ax, "object 3")[0].get_linewidth() == 2.5


def test_a_picture_of_some_targets_draws_the_others_as_context() -> None:
    # targets=[2]: the table has a row of 2 only; 1 is drawn grey with its idx, never "1: nan%"
    from omega_prime_visibility.plot.style import visibility_colour

    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)])
    ax = plot_frame(df, 0, 0, targets=[2])
    labels = set(texts(ax))
    assert "2: 0%" in labels and "1" in labels and not any("nan" in t for t in labels)
    (context,) = by_gid(ax, "object 1")
    assert context.get_facecolor()[:3] == pytest.approx(to_rgb(visibility_colour(float("nan"))))
    # the same picture from one value of the question
    again = plot_frame(df, None, 0, query=omega_prime_visibility.Query(observers=0, targets=[2]))
    assert set(texts(again)) == labels


def test_a_picture_in_3d_takes_its_numbers_from_the_3d_table() -> None:
    # a 0.8 m rail between the ego and a car: the eye (1.25 m) sees over it in 3D; in 2D the rail is left out
    from omega_prime_visibility import Query, get_visibility_df

    df = boxes_table([(0, 0, 4, 2, 0), (20, 0, 4, 2, 0)]).with_columns(
        z=pl.lit(0.75), height=pl.lit(1.5), roll=pl.lit(0.0), pitch=pl.lit(0.0)
    )
    rail = [shapely.box(10, -5, 10.5, 5)]
    question = Query(observers=0, mode="3d", static_occluders=rail, static_heights=0.8)
    seen = get_visibility_df(df, query=question)["visibility"][0]
    assert 0.0 < seen < 1.0
    ax = plot_frame(df, None, 0, query=question)
    assert f"1: {seen:.0%}" in texts(ax)
    (car,) = by_gid(ax, "object 1")
    assert tuple(car.get_facecolor()) == pytest.approx(CMAP(seen))
    # no ground region in 3D: the 2D one would call the car, seen over the rail, "not seen"; the picture says so
    assert not by_gid(ax, "region")
    legend = ax.figure.legends[0] if ax.figure.legends else ax.get_legend()
    labels = [t.get_text() for t in legend.get_texts()]
    assert "3D: seen from the eye (no ground region)" in labels and "seen from the ego" not in labels
    assert "3D" in ax.get_title().splitlines()[-1]
    flat = plot_frame(df, 0, 0, static_occluder_polys=rail)  # in 2D the region is shaded and named
    assert by_gid(flat, "region") and "engine VisiLibity" in flat.get_title()


def test_a_small_road_user_keeps_its_fill_and_the_legend_lists_only_what_is_drawn() -> None:
    # a 0.5 m pedestrian 60 m away in a wide picture spans a few pixels: it is drawn as a marker filled with its
    # colour (its outline alone would cover its fill); a car near the ego keeps its outline. Nothing hides the
    # pedestrian, so the legend says nothing of what hides it.
    df = boxes_table([(0, 0, 4, 2, 0), (10, 6, 4, 2, 0), (60, 0, 0.5, 0.5, 0)])
    ax = plot_frame(df, 0, 0, target=2, view_range=200)
    (walker,) = by_gid(ax, "object 2")
    (marker,) = by_gid(ax, "object 2 marker")
    assert walker.get_linewidth() == 0.0
    assert to_rgb(marker.get_markerfacecolor()) == pytest.approx(CMAP(1.0)[:3])
    assert by_gid(ax, "object 1")[0].get_linewidth() > 0 and not by_gid(ax, "object 1 marker")
    legend = ax.figure.legends[0] if ax.figure.legends else ax.get_legend()
    labels = [t.get_text() for t in legend.get_texts()]
    assert "target 2" in labels and "hides 2" not in labels


def test_the_picture_grows_to_hold_a_chosen_target_within_twice_its_reach() -> None:
    # the target 80 m ahead (the default reach is 50 m): the window holds it, and what hides it is outlined
    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (80, 0, 4, 2, 0)])
    ax = plot_frame(df, 0, 0, target=2)
    assert ax.get_xlim()[1] >= 82 and not [t for t in ax.texts if t.get_gid() == "target pointer"]
    assert by_gid(ax, "object 1")[0].get_linewidth() == 2.5
    assert ax.get_xlim()[1] < 82 + 10  # no farther than it needs


def test_a_target_off_the_picture_gets_a_pointer_and_nothing_outlined_as_its_hiders() -> None:
    # the target (idx 2) 200 m ahead, hidden by idx 1 at 10 m; the default 50 m reach leaves it off the picture:
    # an arrow at the edge names it (visibility, distance), idx 1 is not outlined as what hides it, and the legend
    # says nothing of what hides it; with a reach that holds it, the outlines come back
    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (200, 0, 4, 2, 0)])
    ax = plot_frame(df, 0, 0, target=2)
    (pointer,) = [t for t in ax.texts if t.get_gid() == "target pointer"]
    assert pointer.get_text() == "target 2: 0%, 200 m"
    x0, x1 = ax.get_xlim()
    assert x0 < pointer.xy[0] < x1 and pointer.xy[0] > (x0 + x1) / 2  # on the picture, on the side of the target
    assert by_gid(ax, "object 1")[0].get_linewidth() < 2.0
    legend = ax.figure.legends[0] if ax.figure.legends else ax.get_legend()
    assert "hides 2" not in [t.get_text() for t in legend.get_texts()]
    near = plot_frame(df, 0, 0, target=2, view_range=210)
    assert not [t for t in near.texts if t.get_gid() == "target pointer"]
    assert by_gid(near, "object 1")[0].get_linewidth() == 2.5


def test_the_legend_names_only_static_occluders_on_the_picture() -> None:
    # a wall 10 m beside the ego is on the picture and in the legend; one 400 m away is in neither
    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 2, 0)])
    near, far = shapely.LineString([(-5, 10), (5, 10)]), shapely.LineString([(400, 0), (410, 0)])

    def labels(ax) -> list[str]:
        legend = ax.figure.legends[0] if ax.figure.legends else ax.get_legend()
        return [t.get_text() for t in legend.get_texts()]

    assert "wall" in labels(plot_frame(df, 0, 0, [near]))
    assert "wall" not in labels(plot_frame(df, 0, 0, [far]))
    assert "wall" in labels(plot_frame(df, 0, 0, [far], view_range=None))  # the whole frame: it is on it


def test_a_hidden_target_keeps_its_dashed_outline_on_its_dark_fill() -> None:
    # idx 2, 0 % visible, is filled dark: its dashed outline runs over a white one, so that it shows; a target too
    # small to outline (a pedestrian far out) gets a dashed ring of SMALL_RING pixels round its marker
    from matplotlib.colors import to_rgb

    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0), (45, 6, 0.4, 0.4, 0)])
    ax = plot_frame(df, 0, 0, target=2)
    under, dashes = by_gid(ax, "target outline")
    assert to_rgb(under.get_edgecolor()) == (1.0, 1.0, 1.0) and under.get_linewidth() > dashes.get_linewidth()
    assert dashes.get_linestyle() == "--"
    # round the body, not on it (a thin target keeps its fill in sight): half the white halo's width out
    body = shapely.Polygon(by_gid(ax, "object 2")[0].get_xy())
    around = shapely.Polygon(dashes.get_xy())
    metres_per_pixel = np.ptp(ax.get_xlim()) / ax.bbox.width
    half_halo = under.get_linewidth() / 2 * ax.figure.dpi / 72 * metres_per_pixel
    assert around.contains(body) and shapely.hausdorff_distance(around.exterior, body.exterior) == pytest.approx(
        half_halo * np.sqrt(2), rel=1e-6
    )  # (mitred corners: the farthest points, diagonally out)
    small = plot_frame(df, 0, 0, target=3, view_range=200)
    ring = by_gid(small, "target outline")[1].get_xy()
    radius_px = np.hypot(*(ring[0] - (45, 6))) * small.bbox.width / np.ptp(small.get_xlim())
    assert radius_px == pytest.approx(9.0, rel=0.05)


def test_in_town_labels_cover_no_other_road_user_and_the_legend_says_what_is_not_seen() -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scenarios"))
    from urban import urban_scene

    table, buildings = urban_scene(frames=61)
    ax = plot_frame(table, 0, 60, buildings, target=163)
    ax.figure.canvas.draw()
    renderer = ax.figure.canvas.get_renderer()
    bodies = [(a.get_gid().split()[1], a.get_window_extent(renderer)) for a in [*ax.patches, *ax.lines]
              if a.get_gid() and a.get_gid().startswith("object ") and a.get_visible()]  # fmt: skip
    bodies = [(idx, extent) for idx, extent in bodies if extent.width > 0]  # (a marker's patch is drawn with no line)
    labels = [t for t in ax.texts if t.get_gid() == "label" and t.get_visible()]
    assert len(labels) > 60  # most road users keep their label
    may_cover = {"ego 0", "163: 0%"}  # the ego's and the target's (nothing outlined hides it here: its shadow)
    for label in labels:
        own = label.get_text().split(":")[0].removeprefix("ego ")
        if label.get_text() in may_cover:
            continue
        # (placed before the title is set, which moves the axes by a pixel at most when the figure is drawn)
        extent = label.get_bbox_patch().get_window_extent(renderer).padded(-1.0)
        covered = [idx for idx, body in bodies if idx != own and extent.overlaps(body)]
        assert covered == [], f"label {label.get_text()!r} covers road users {covered}"
    legend = ax.figure.legends[0]
    assert "not seen (white)" in [t.get_text() for t in legend.get_texts()]


def test_a_legend_of_many_sensors_fits_a_portrait_picture() -> None:
    # a north-south street: the picture is portrait; six sensors of "typical" make the legend long
    cars = [(0, 0, 4, 2, math.pi / 2), (3, 30, 4, 2, math.pi / 2), (-3, -25, 4, 2, math.pi / 2)]
    ax = plot_frame(boxes_table(cars), 0, 0, sensors="typical", view_range=30)
    figure = ax.figure
    figure.canvas.draw()
    assert figure.bbox.width < figure.bbox.height
    legend = figure.legends[0]
    assert len(legend.get_texts()) >= 8
    extent = legend.get_window_extent(figure.canvas.get_renderer())
    assert extent.x0 >= 0 and extent.x1 <= figure.bbox.width


def test_a_picture_on_a_figure_made_without_pyplot() -> None:
    # a Figure's own canvas (FigureCanvasBase) draws nothing and has no renderer: labels and legend are laid out
    # with the one matplotlib uses for such figures
    from matplotlib.figure import Figure

    figure = Figure(layout="constrained")
    ax = plot_frame(boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 2, 0)]), 0, 0, ax=figure.add_subplot())
    assert ax.figure is figure and "1: 100%" in texts(ax)
