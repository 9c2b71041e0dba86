"""Pictures of real scenes: every object near the ego is on the frame plot, the animation and the report's scene
(the esmini traces in ../shared/data with their maps, and the bundled recording), and with sensors the colours are
what ``seen_by_any`` says."""

from __future__ import annotations

import json
import re
import warnings

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import polars as pl
import pytest
import shapely
from conftest import REPO

from omega_prime_visibility import get_visibility_df, seen_by_any
from omega_prime_visibility.inputs.io import read_recording
from omega_prime_visibility.plot import animate, plot_frame, write_report
from omega_prime_visibility.plot import frame as frame_module
from omega_prime_visibility.plot.style import visibility_colour

RANGE = 60.0
TRACES = ["pedestrian.osi", "highway_merge.osi", "acc-test.osi", "alks_cut-in.osi"]
RAIL = [shapely.LineString([(60, -5.4), (140, -5.4)])]


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def load(name: str, shared_data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if name == "bundled":
            return read_recording(REPO / "highway_merge.mcap")
        maps = dict(json.loads((shared_data / "mapping.json").read_text()))
        return read_recording(shared_data / name, shared_data / maps[name])


def near_outlines(recording, frame: int, ego: int = 0) -> list[np.ndarray]:
    """Outlines (corners, metres) of the objects whose centre is within RANGE of the ego's in ``frame``."""
    rows = recording._df.filter(pl.col("frame") == frame)
    e = rows.filter(pl.col("idx") == ego).row(0, named=True)
    out = []
    for r in rows.iter_rows(named=True):
        if np.hypot(r["x"] - e["x"], r["y"] - e["y"]) <= RANGE:
            c, s = np.cos(r["yaw"]), np.sin(r["yaw"])
            corners = np.array([[1, 1], [1, -1], [-1, -1], [-1, 1]]) * [r["length"] / 2, r["width"] / 2]
            out.append(corners @ [[c, s], [-s, c]] + [r["x"], r["y"]])
    return out


def assert_on_picture(outlines: list[np.ndarray], limits, where: str) -> None:
    x0, x1, y0, y1 = limits
    for o in outlines:
        inside = (o[:, 0] >= x0) & (o[:, 0] <= x1) & (o[:, 1] >= y0) & (o[:, 1] <= y1)
        assert inside.all(), f"{where}: an object at {o.mean(axis=0)} is off the picture {limits}"


def sample_frames(recording, n: int = 5) -> list[int]:
    frames = np.unique(recording._df["frame"].to_numpy())
    return frames[np.linspace(0, len(frames) - 1, n).round().astype(int)].tolist()


@pytest.mark.parametrize("name", [*TRACES, "bundled"])
def test_every_object_near_the_ego_is_on_every_picture(name, shared_data, tmp_path, monkeypatch) -> None:
    r = load(name, shared_data)
    frames = sample_frames(r)
    assert sum(len(near_outlines(r, f)) for f in frames) > len(frames)  # someone besides the ego to check
    for f in frames:
        ax = plot_frame(r, 0, f, view_range=RANGE)
        assert_on_picture(near_outlines(r, f), (*ax.get_xlim(), *ax.get_ylim()), f"plot_frame, frame {f}")
        plt.close("all")
    # the animation: the limits of each frame it draws
    seen: dict[int, tuple] = {}
    draw = frame_module.FramePainter.draw

    def recording_draw(self, view, limits=None, title=""):
        draw(self, view, limits, title)
        seen[view.frame] = (*self.ax.get_xlim(), *self.ax.get_ylim())

    monkeypatch.setattr(frame_module.FramePainter, "draw", recording_draw)
    animate(r, 0, tmp_path / "a.gif", frames=frames, view_range=RANGE, dpi=30, progress=False)
    assert sorted(seen) == frames
    for f in frames:
        assert_on_picture(near_outlines(r, f), seen[f], f"animation, frame {f}")
    # the report's scene: the window around the ego of each frame
    page = write_report(r, 0, tmp_path / "r.html", frames=frames, view_range=RANGE, progress=False).read_text()
    scene = json.loads(re.search(r'<script id="scene-data" type="application/json">(.*?)</script>', page, re.S)[1])
    hw, hh, dx, dy = scene["window"]
    for f in scene["frames"]:
        ex, ey = f["ego"][0] + dx, f["ego"][1] + dy  # the window's centre
        assert_on_picture(near_outlines(r, f["frame"]), (ex - hw, ex + hw, ey - hh, ey + hh), f"report {f['frame']}")


def test_the_pedestrian_ahead_is_on_the_first_picture(shared_data) -> None:
    # pedestrian.osi: a north-south street, the pedestrian 47 m ahead of the car at frame 0 (the example)
    r = load("pedestrian.osi", shared_data)
    ax = plot_frame(r, 0, 0)
    y0, y1 = ax.get_ylim()
    assert y0 < -69.9 - 2 and -69.9 + 47 + 0.5 < y1  # the car and the pedestrian ahead, whole
    assert "1: 100%" in [t.get_text() for t in ax.texts]


def face_of(ax, idx: int):
    (patch,) = [p for p in ax.patches if p.get_gid() == f"object {idx}"]
    return tuple(patch.get_facecolor())


def test_with_sensors_the_colours_are_seen_by_any(tmp_path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(REPO / "highway_merge.mcap")
    table = get_visibility_df(r, 0, RAIL, sensors="typical", progress=False)
    best = seen_by_any(table.filter(pl.col("frame") == 30))
    ax = plot_frame(r, 0, 30, RAIL, sensors="typical")
    cmap = plt.get_cmap("cividis")
    all_round = get_visibility_df(r, 0, RAIL, progress=False).filter(pl.col("frame") == 30)
    differs = 0
    for idx, vis in best.select("idx", "visibility").rows():
        assert face_of(ax, idx) == pytest.approx(cmap(vis)), f"idx {idx}"
        label = [t.get_text() for t in ax.texts if t.get_text().startswith(f"{idx}: ")]
        assert label in ([], [f"{idx}: {vis:.0%}"])
        differs += all_round.filter(pl.col("idx") == idx)["visibility"].item() != pytest.approx(vis, abs=0.01)
    assert differs > 0  # the sensors' view differs from the all-round one somewhere, so the test can tell them apart
    # the report's scene shows the same numbers, and the timeline has the combined band
    page = write_report(r, 0, tmp_path / "s.html", RAIL, frames=[30], sensors="typical", progress=False).read_text()
    scene = json.loads(re.search(r'<script id="scene-data" type="application/json">(.*?)</script>', page, re.S)[1])
    got = {o["idx"]: o["vis"] for o in scene["frames"][0]["objects"] if not o["ego"]}
    assert got == pytest.approx(dict(best.select("idx", "visibility").rows()), abs=1e-4)
    assert all(o["fill"] == visibility_colour(o["vis"]) for o in scene["frames"][0]["objects"] if not o["ego"])
    assert [s["name"] for s in scene["sensors"]][:2] == ["front_camera", "front_radar"]
    assert len(scene["frames"][0]["sensors"]) == 6  # a pose per sensor, drawn as its outline
    assert "<td>any sensor</td>" in page


def drawn(patch) -> shapely.Polygon:
    """The polygon a region patch shades: its first ring, less the others (holes)."""
    outer, *holes = patch.get_path().to_polygons(closed_only=False)
    return shapely.Polygon(outer, holes)


def test_with_sensors_the_region_shaded_is_what_the_sensors_see() -> None:
    from omega_prime_visibility import visible_area

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(REPO / "highway_merge.mcap")
    ax = plot_frame(r, 0, 30, RAIL, sensors="typical")
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    window = shapely.box(x0, y0, x1, y1)
    shaded = shapely.union_all([drawn(p) for p in ax.patches if p.get_gid() == "region"])
    want = visible_area(r, 0, 30, "typical", RAIL).intersection(window)
    # the same region on the picture, up to the arcs' chords (1°) and the outlines' holes
    assert shaded.intersection(window).symmetric_difference(want).area < 0.01 * want.area
    centre_only = plot_frame(r, 0, 30, RAIL)
    all_round = shapely.union_all([drawn(p) for p in centre_only.patches if p.get_gid() == "region"])
    assert all_round.intersection(window).symmetric_difference(want).area > 0.05 * want.area  # the test can tell
