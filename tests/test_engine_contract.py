"""The engine contract, on every registered engine: hand-made scenes whose answers are derived on paper (in the
comments), ties and touching bodies included."""

from __future__ import annotations

import math
import warnings

import polars as pl
import pytest
import shapely
from conftest import boxes_table

from omega_prime_visibility import ENGINES, Sensor, VisibilityInputWarning, get_visibility_df

# the sweep is exact to rounding; VisiLibity joins bodies touching at a point by a 0.1 µm buffer, which moves
# visible angles by up to about that over the distance (radians)
EXACT = {"sweep": 1e-12, "visilibity": 1e-7}


def row(df: pl.DataFrame, idx: int) -> dict:
    return df.filter(pl.col("idx") == idx).row(0, named=True)


@pytest.fixture(params=sorted(ENGINES))
def engine(request) -> str:
    return request.param


def run(engine: str, boxes, statics=None, ego=0) -> pl.DataFrame:
    return get_visibility_df(boxes_table(boxes), ego, statics, engine=engine)


def test_fully_hidden_and_unobstructed(engine: str) -> None:
    df = run(engine, [(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0), (0, 30, 4, 2, 1.0)])
    assert row(df, 1)["visibility"] == 1.0 and row(df, 1)["occluder_idxs"] == []
    assert row(df, 2)["visibility"] == 0.0 and row(df, 2)["occluder_idxs"] == [1]
    assert row(df, 3)["visibility"] == 1.0 and row(df, 3)["occluder_idxs"] == []


@pytest.mark.parametrize(
    "wall",
    [shapely.Polygon([(5, -5), (5.1, -5), (5.1, 0), (5, 0)]), shapely.LineString([(5, -5), (5, 0)])],
)
def test_half_behind_a_wall(engine: str, wall) -> None:
    # a square centred at (10, 0) has an extent symmetric about +x; the wall ends on the +x axis
    df = run(engine, [(0, 0, 1, 1, 0), (10, 0, 2, 2, 0)], [wall])
    assert row(df, 1)["visibility"] == pytest.approx(0.5, abs=EXACT[engine])
    assert row(df, 1)["static_occluder_idxs"] == [0] and row(df, 1)["occluder_idxs"] == []


@pytest.mark.parametrize("angle", [math.pi, -math.pi, math.pi - 1e-3, -math.pi + 1e-9, 3 * math.pi / 4, 0.0])
def test_straddling_the_cut(engine: str, angle: float) -> None:
    # target at bearing `angle`, a thin blocker covers exactly its clockwise half
    c, s = math.cos(angle), math.sin(angle)
    boxes = [(0, 0, 1, 1, 0), (10 * c, 10 * s, 2, 2, angle), (5 * c + 2.5 * s, 5 * s - 2.5 * c, 0.2, 5, angle)]
    df = run(engine, boxes)
    assert row(df, 1)["visibility"] == pytest.approx(0.5, abs=max(1e-9, EXACT[engine]))
    assert row(df, 1)["occluder_idxs"] == [2]
    assert row(df, 2)["visibility"] == 1.0


def test_two_overlapping_targets(engine: str) -> None:
    # B (idx 2) is A (idx 1) shifted by (1, 1): the corner of A over B hides B's directions below A's upper edge
    df = run(engine, [(0, 0, 1, 1, 0), (10, 0, 2, 2, 0), (11, 1, 2, 2, 0)])
    a, b = row(df, 1), row(df, 2)
    assert a["visibility"] == 1.0 and a["occluder_idxs"] == []
    # B's extent runs from A's top edge direction... : bearings atan2(0, 12) .. atan2(2, 10); A's top corner (9, 1)
    lo, hi = math.atan2(0.0, 12.0), math.atan2(2.0, 10.0)
    hidden = math.atan2(1.0, 9.0) - lo
    assert b["visibility"] == pytest.approx(1.0 - hidden / (hi - lo), abs=EXACT[engine])
    assert b["occluder_idxs"] == [1]


def test_touching_boxes(engine: str) -> None:
    # 1 and 2 side by side sharing an edge that points at the observer; 4 directly behind 3 sharing its back edge
    # (across the -pi/pi cut); 5 on top of 3 sharing an edge (3 hides part of it); 6 touches 5 at a corner only
    boxes = [(0, 0, 1, 1, 0), (10, 1, 2, 2, 0), (10, -1, 2, 2, 0), (-10, 0, 2, 2, 0), (-12, 0, 2, 2, 0)]
    boxes += [(-10, 2, 2, 2, 0), (-8, 4, 2, 2, 0)]
    df = run(engine, boxes)
    for i in (1, 2, 3, 6):
        assert row(df, i)["visibility"] == 1.0 and row(df, i)["occluder_idxs"] == [], i
    assert row(df, 4)["visibility"] == 0.0 and row(df, 4)["occluder_idxs"] == [3]
    # 5 spans pi - atan(3/9) .. pi - atan(1/11); box 3 hides pi - atan(1/9) .. pi - atan(1/11)
    hidden = math.atan(1 / 9) - math.atan(1 / 11)
    assert row(df, 5)["visibility"] == pytest.approx(
        1 - hidden / (math.atan(3 / 9) - math.atan(1 / 11)), abs=EXACT[engine]
    )
    assert row(df, 5)["occluder_idxs"] == [3]


def test_coincident_and_collinear_edges(engine: str) -> None:
    # two identical cars (coincident edges: neither is hit strictly before the other) in front of a third
    df = run(engine, [(0, 0, 1, 1, 0), (10, 0, 4, 2, 0), (10, 0, 4, 2, 0), (20, 0, 2, 1, 0)])
    assert row(df, 1)["visibility"] == 1.0 and row(df, 2)["visibility"] == 1.0
    assert row(df, 1)["occluder_idxs"] == [] and row(df, 2)["occluder_idxs"] == []
    assert row(df, 3)["visibility"] == 0.0 and row(df, 3)["occluder_idxs"] == [1, 2]
    # a box whose lower edge points straight at the observer, partly behind a box with such an upper edge
    df = run(engine, [(0, 0, 1, 1, 0), (11, 1, 2, 2, 0), (8, -1, 2, 2, 0)])
    assert row(df, 1)["visibility"] == 1.0 and row(df, 2)["visibility"] == 1.0


def test_courtyard_and_transparent_bodies(engine: str) -> None:
    # the observer stands in the courtyard (a hole) of a building: inside targets visible, outside ones hidden;
    # a building containing the observer is transparent
    building = shapely.Polygon(
        [(-50, -50), (50, -50), (50, 50), (-50, 50)], [[(-20, -20), (20, -20), (20, 20), (-20, 20)]]
    )
    hall = shapely.box(-200, -200, 200, 200)
    df = run(engine, [(0, 0, 1, 1, 0), (10, 0, 4, 2, 0), (70, 0, 4, 2, 0)], [building])
    assert row(df, 1)["visibility"] == 1.0 and row(df, 1)["static_occluder_idxs"] == []
    assert row(df, 2)["visibility"] == 0.0 and row(df, 2)["static_occluder_idxs"] == [0]
    with pytest.warns(VisibilityInputWarning, match=r"static occluder 0 contains observer 0 in 1 frame"):
        df = run(engine, [(0, 0, 1, 1, 0), (10, 0, 4, 2, 0)], [hall])
    assert row(df, 1)["visibility"] == 1.0 and row(df, 1)["static_occluder_idxs"] == []


def test_body_touching_the_observer_is_transparent(engine: str) -> None:
    # the observer (origin) lies on the right edge x = 0 of box 1 ([-4, 0] x [-1, 1]) and on the left edge of
    # box 3 ([0, 4] x [-1, 1]): both count as containing it, so they hide neither box 2 nor box 4 straight behind
    # them, list no occluders and are fully visible (a point-in-polygon parity test alone calls one side outside)
    boxes = [(0, 0, 1, 1, 0), (-2, 0, 4, 2, 0), (-10, 0, 2, 2, 0), (2, 0, 4, 2, 0), (10, 0, 2, 2, 0)]
    with pytest.warns(VisibilityInputWarning, match="idx 1 contains observer 0.*idx 3 contains observer 0"):
        df = run(engine, boxes)
    for i in (1, 2, 3, 4):
        assert row(df, i)["visibility"] == 1.0 and row(df, i)["occluder_idxs"] == [], i


def test_equal_distances_do_not_occlude(engine: str) -> None:
    # box 2 lies on box 1's far edge line x = 11 seen along the +x axis: the two touch along x = 11 but nothing of
    # box 1 is hit *before* box 2 except where box 1 lies in front, which is nowhere in box 2's extent
    # (box 2 = [11, 13] x [2, 4] lies beside box 1 = [9, 11] x [-1, 1] as seen from the origin)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        df = run(engine, [(0, 0, 1, 1, 0), (10, 0, 2, 2, 0), (12, 3, 2, 2, 0)])
    assert row(df, 2)["occluder_idxs"] == [] and row(df, 2)["visibility"] == 1.0


def test_a_wall_through_the_viewpoint_up_to_rounding_is_transparent(engine: str) -> None:
    # a wall 0.5 nm above the observer (origin) passes within the touch tolerance (1 nm): the observer stands on
    # it, so it hides neither the box above (2 = [-1, 1] x [9, 11]) nor the one below (3), and occludes nothing
    boxes = [(0, 0, 1, 1, 0), (0, 10, 2, 2, 0), (0, -10, 2, 2, 0)]
    with pytest.warns(VisibilityInputWarning, match=r"static occluder 0 contains observer 0"):
        df = run(engine, boxes, [shapely.LineString([(-5, 5e-10), (5, 5e-10)])])
    for i in (1, 2):
        assert row(df, i)["visibility"] == 1.0 and row(df, i)["static_occluder_idxs"] == [], i
    # 2 nm above it the wall is a wall: the box above lies wholly behind it (its extent, 2 * atan(1 / 9), is inside
    # the wall's, half a turn less 4e-10 rad); VisiLibity cannot place the observer outside its 20 nm thick walls
    # and hands the frame to the sweep, saying so
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        df = run(engine, boxes, [shapely.LineString([(-5, 2e-9), (5, 2e-9)])])
    assert row(df, 1)["visibility"] == 0.0 and row(df, 1)["static_occluder_idxs"] == [0]
    assert row(df, 2)["visibility"] == 1.0 and row(df, 2)["static_occluder_idxs"] == []
    handed_over = [w for w in caught if "computed with engine='sweep'" in str(w.message)]
    assert len(handed_over) == (engine == "visilibity")


def test_a_sliver_thinner_than_the_tolerance_is_credited_once(engine: str) -> None:
    # a triangle 2 m long and 20 µm deep at 48 m, its front edge on x = 48 from y = -1 to 1: both of its sides lie
    # on the same edge of the visibility polygon within the attribution's tolerance (1e-6 x 48 m). Box 2 at
    # x = 10..11, y = 0..0.5 covers bearings 0 to 2.9 degrees, the sliver's upper half (0 to atan(1 / 48)), so
    # half of it is seen
    sliver = shapely.Polygon([(48, -1), (48 + 2e-5, 0), (48, 1)])
    polys = [shapely.box(-0.5, -0.5, 0.5, 0.5), sliver, shapely.box(10, 0, 11, 0.5)]
    table = pl.DataFrame(
        {
            "frame": [0] * 3,
            "total_nanos": [0] * 3,
            "idx": [0, 1, 2],
            "x": [0.0, 48.0, 10.5],
            "y": [0.0, 0.0, 0.25],
            "polygon": pl.Series(polys, dtype=pl.Object),
        }
    )
    df = get_visibility_df(table, 0, engine=engine)
    assert row(df, 1)["visibility"] == pytest.approx(0.5, abs=1e-12) and row(df, 1)["occluder_idxs"] == [2]


@pytest.mark.parametrize("second", [(10, 0, 4, 2, 0), (9, 0, 2, 2, 0)], ids=["duplicate", "nested"])
def test_coincident_edges_behind_a_wall_are_each_seen_where_they_are_seen(engine: str, second) -> None:
    # box 1 = [8, 12] x [-1, 1] and box 2, the same box again (a double detection) or [8, 10] x [-1, 1] inside it:
    # both front edges lie on x = 8, y in [-1, 1] (bearings +-atan(1 / 8)). The wall from (5, 0) to (5, 3) covers
    # bearings 0 to 31 degrees, the upper half; along the lower half both are hit first, neither before the other
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (box 2 inside box 1 overlaps it)
        df = run(engine, [(0, 0, 1, 1, 0), (10, 0, 4, 2, 0), second], [shapely.LineString([(5, 0), (5, 3)])])
    for i in (1, 2):
        assert row(df, i)["visibility"] == pytest.approx(0.5, abs=1e-12), i
        assert row(df, i)["occluder_idxs"] == [] and row(df, i)["static_occluder_idxs"] == [0], i


def test_an_edge_micrometres_behind_a_nearer_one_is_hidden(engine: str) -> None:
    # overlapping cars as trackers deliver them: 2's near edge (y = 10 + 5 µm, x in [-1, 3]) runs 5 µm behind 1's
    # (y = 10, x in [-2, 2]); 1 hides it up to its corner (2, 10), beyond which 2 is seen up to its corner (3, y2).
    # (VisiLibity joins the two edges; crediting 2 the joined edge gave it nearly 1.)
    y2 = 10 + 5e-6
    df = run(engine, [(0, 0, 1, 1, 0), (0, 11, 4, 2, 0), (1, y2 + 0.5, 4, 1, 0)])
    extent = math.atan2(y2, -1.0) - math.atan2(y2, 3.0)
    seen = math.atan2(10.0, 2.0) - math.atan2(y2, 3.0)
    assert row(df, 2)["visibility"] == pytest.approx(seen / extent, abs=max(1e-9, EXACT[engine]))
    assert row(df, 2)["occluder_idxs"] == [1]
    assert row(df, 1)["visibility"] == 1.0 and row(df, 1)["occluder_idxs"] == []


def test_edges_a_nanoradian_apart_tie(engine: str) -> None:
    # 2 (x in [2, 8]) lies on 1's near edge y = 10 (x in [-5, 5]), turned by 1e-9 rad about (5, 10): along
    # x in [2, 5] the two edges are under 3 nm apart, within the occlusion test's tolerance (1e-9 of 10 m): a
    # tie, so 2 hides nothing of 1 there. 3, a post x in [-2, -1], y in [4.9, 5.1], hides the bearings from its
    # corner (-1, 5.1) to its corner (-2, 4.9) of 1, whose extent runs from atan2(10, 5) to atan2(10, -5).
    angle = 1e-9
    centre = (5 - 0.25 * math.sin(angle), 10 + 0.25 * math.cos(angle))
    df = run(engine, [(0, 0, 1, 1, 0), (0, 11, 10, 2, 0), (*centre, 6, 0.5, angle), (-1.5, 5, 1, 0.2, 0)])
    extent = math.atan2(10, -5) - math.atan2(10, 5)
    hidden = math.atan2(4.9, -2) - math.atan2(5.1, -1)
    assert row(df, 1)["visibility"] == pytest.approx(1 - hidden / extent, abs=max(1e-9, EXACT[engine]))
    assert row(df, 1)["occluder_idxs"] == [3]


@pytest.mark.parametrize("beyond", [False, True])
def test_a_target_seen_only_along_a_line_through_wall_corners_is_occluded(engine: str, beyond: bool) -> None:
    # walls [1, 2] x [0, 1] (below y = x), [0, 2] x [2, 3] (above it) and [3, 4] x [2, 3] (below it) have their
    # corners (1, 1), (2, 2), (3, 3) on the diagonal from the viewpoint: any ray off it hits a wall, so the car on
    # the diagonal at (10, 10) is seen along no direction of positive measure (also with a wall across the
    # diagonal beyond the corners): visibility 0, status occluded
    walls = [shapely.box(1, 0, 2, 1), shapely.box(0, 2, 2, 3), shapely.box(3, 2, 4, 3)]
    walls += [shapely.LineString([(6, 4), (4, 6)])] if beyond else []
    table = boxes_table([(0, 0, 0.2, 0.2, 0), (10, 10, 2, 2, math.pi / 4)])
    df = get_visibility_df(table, 0, walls, engine=engine, sensors=[Sensor("all_round")])
    assert row(df, 1)["visibility"] == 0.0 and row(df, 1)["status"] == "occluded"
    assert row(df, 1)["static_occluder_idxs"] == ([0, 1, 2, 3] if beyond else [0, 1, 2])


def test_every_registered_engine_declares_the_contract() -> None:
    # the contract is explicit: every engine says its name, measure, whether it measures passive targets itself and
    # whether it offers observe_chunk (the pipeline asks these, never probes with hasattr)
    from omega_prime_visibility.engines.registry import ENGINES, ENGINES_3D, ENGINES_AREA, get_engine

    for name in [*ENGINES, *ENGINES_3D, *ENGINES_AREA]:
        engine = get_engine(name)
        for attribute in ("name", "measure", "passive_targets", "chunked"):
            assert attribute in {k for c in engine.__mro__ for k in vars(c)}, (name, attribute)
        assert engine.chunked == callable(getattr(engine, "observe_chunk", None)), name
        assert isinstance(engine.passive_targets, bool) and isinstance(engine.chunked, bool)
