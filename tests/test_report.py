"""The HTML report: self-contained, its data agrees with get_visibility_df, and it works in a real browser."""

from __future__ import annotations

import json
import re
import warnings

import numpy as np
import polars as pl
import pytest
from chromium import Browser, find_chromium
from conftest import REPO, interrupted_writer
from PIL import Image

from omega_prime_visibility import get_visibility_df
from omega_prime_visibility.inputs.io import read_recording
from omega_prime_visibility.plot import write_report
from omega_prime_visibility.plot.report import visibility_colour

MCAP = REPO / "highway_merge.mcap"


@pytest.fixture(scope="module")
def recording():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_recording(MCAP)


@pytest.fixture(scope="module")
def report(recording, tmp_path_factory):
    return write_report(recording, 0, tmp_path_factory.mktemp("report") / "merge.html", progress=False)


@pytest.fixture(scope="module")
def expected(recording) -> pl.DataFrame:
    return get_visibility_df(recording, 0, engine="sweep", progress=False)


def embedded(page: str, name: str):
    return json.loads(re.search(rf'<script id="{name}" type="application/json">(.*?)</script>', page, re.S).group(1))


def test_report_is_one_file_that_needs_no_network(report) -> None:
    page = report.read_text()
    assert "<script src" not in page and "<link" not in page and "cdn.jsdelivr" not in page
    assert "window.vegaEmbed=" in page  # the vega libraries are inside
    assert 0.5e6 < len(page) < 5e6


def test_report_scene_and_summary_agree_with_the_table(report, expected) -> None:
    page = report.read_text()
    scene = embedded(page, "scene-data")
    assert [f["frame"] for f in scene["frames"]] == list(range(201))
    for f in (scene["frames"][0], scene["frames"][150]):
        want = dict(expected.filter(pl.col("frame") == f["frame"]).select("idx", "visibility").rows())
        got = {o["idx"]: o["vis"] for o in f["objects"] if not o["ego"]}
        assert got == pytest.approx(want, abs=1e-4)
        assert all(o["fill"] == visibility_colour(o["vis"]) for o in f["objects"] if not o["ego"])
    summary = re.search(r'<table id="summary">(.*?)</table>', page, re.S).group(1)
    rows = re.findall(r"<tr><td>(\d+)</td><td>(\d+)</td><td>([0-9.]+)%</td>", summary)  # mean visibility in %
    means = expected.group_by("idx").agg(pl.col("visibility").mean()).sort("idx").rows()
    assert [(int(i), int(n)) for i, n, _ in rows] == [(i, 201) for i, _ in means]
    assert [float(m) / 100 for _, _, m in rows] == pytest.approx([m for _, m in means], abs=6e-4)
    timeline = embedded(page, "timeline-data")
    assert timeline["mode"] == "vega-lite"
    bands, rule = timeline["spec"]["layer"]
    assert bands["encoding"]["color"]["field"] == "visibility"
    assert rule["mark"]["type"] == "rule" and rule["encoding"]["x"]["datum"] == {"expr": "now"}
    config = timeline["spec"]["config"]  # text a reader can read on the page: 12 px at least, titles not cut
    sizes = [config[part][key] for part in ("axis", "legend") for key in ("labelFontSize", "titleFontSize")]
    assert min(sizes) >= 12 and config["title"]["fontSize"] >= 12 and config["legend"]["titleLimit"] == 0


def summary_row(page: str, idx: int, sensor: str | None = None) -> dict[str, str]:
    """The cells of the report's summary row of target ``idx`` (and ``sensor``), by column heading."""
    summary = re.search(r'<table id="summary">(.*?)</table>', page, re.S).group(1)
    heads = re.findall(r"<th>(.*?)</th>", summary)
    for row in re.findall(r"<tr>(.*?)</tr>", summary, re.S)[1:]:
        cells = dict(zip(heads, re.findall(r"<td>(.*?)</td>", row), strict=True))
        if cells["idx"] == str(idx) and (sensor is None or cells.get("sensor") == sensor):
            return cells
    raise AssertionError(f"no summary row of idx {idx} {sensor or ''}")


def test_report_shows_a_given_status_table(recording, expected, tmp_path) -> None:
    status = expected.with_columns(
        status=pl.when(pl.col("visibility") == 0).then(pl.lit("occluded")).otherwise(pl.lit("visible"))
    )
    out = write_report(recording, 0, tmp_path / "s.html", frames=slice(0, 20), table=status, progress=False)
    page = out.read_text()
    assert embedded(page, "timeline-data")["spec"]["layer"][0]["encoding"]["color"]["field"] == "status"
    # idx 2 is hidden in frames 0 to 19: the summary's hidden share is all of them, by the stated definition
    assert summary_row(page, 2)["hidden"] == "100%" and summary_row(page, 2)["partly hidden"] == "0%"
    assert "hidden: nothing of it is seen, something is in front" in page


def test_report_through_sensors(recording, tmp_path) -> None:
    out = write_report(recording, 0, tmp_path / "s.html", frames=slice(0, 10), sensors="roof", progress=False)
    page = out.read_text()
    assert embedded(page, "timeline-data")["spec"]["layer"][0]["encoding"]["color"]["field"] == "status"
    summary = re.search(r'<table id="summary">(.*?)</table>', page, re.S).group(1)
    assert "<th>sensor</th>" in summary and "<td>roof</td>" in summary
    roof = summary_row(page, 2, "roof")  # idx 2, behind the truck in all ten frames
    assert (roof["hidden"], roof["out of view"], roof["frames"]) == ("100%", "0%", "10")


def test_report_bad_input(recording, tmp_path) -> None:
    with pytest.raises(ValueError, match=r"must end in \.html"):
        write_report(recording, 0, tmp_path / "r.htm")
    with pytest.raises(ValueError, match=r"frame range 500 to 600 .* is empty"):
        write_report(recording, 0, tmp_path / "r.html", frames=slice(500, 600))
    assert list(tmp_path.iterdir()) == []


def red_pixels(png, box) -> int:
    """Pixels of the scene box close to the colour of visibility 0."""
    with Image.open(png) as im:
        x, y, w, h = (round(v) for v in box)
        scene = np.asarray(im.convert("RGB"))[y : y + h, x : x + w].astype(int)
    red = np.array([int(visibility_colour(0.0)[i : i + 2], 16) for i in (1, 3, 5)])
    return int((np.abs(scene - red).sum(axis=2) < 30).sum())


def test_report_in_a_headless_browser(report, expected, tmp_path) -> None:
    binary = find_chromium()
    if binary is None:
        pytest.skip("no chromium binary found (Debian: apt-get install chromium; .ci/run installs it as root)")
    with Browser(binary) as browser:
        browser.open(report.as_uri())
        assert browser.wait_for("document.body.dataset.timeline") == "ready"  # vega-embed drew the timeline
        assert browser.evaluate("document.querySelectorAll('#timeline svg .mark-rect path').length") > 10
        box = browser.evaluate(
            "(r => [r.x, r.y, r.width, r.height])(document.getElementById('scene').getBoundingClientRect())"
        )
        assert browser.evaluate("window.devicePixelRatio") == 1
        rule = """document.querySelector('#timeline line[stroke="#222222"]').getBoundingClientRect().x"""
        rule_before = browser.evaluate(rule)
        before = browser.screenshot(tmp_path / "frame0.png")
        # frame 0: the merging car idx 2 is hidden behind the truck, drawn in the colour of visibility 0
        assert red_pixels(before, box) > 20
        browser.evaluate(
            "(() => { const s = document.getElementById('slider'); s.value = 150;"
            " s.dispatchEvent(new Event('input')); })()"
        )
        assert browser.evaluate("document.getElementById('frame-label').textContent").startswith(
            "frame 150, t = 15.00 s"
        )
        fill = browser.evaluate("document.querySelector('#scene polygon[data-idx=\"2\"]').getAttribute('fill')")
        want = expected.filter((pl.col("frame") == 150) & (pl.col("idx") == 2))["visibility"].item()
        assert fill == visibility_colour(round(want, 4))
        # the timeline's rule moved from 0 s to 15 s: three quarters of the 20.1 s axis
        plot_width = browser.evaluate("document.querySelector('#timeline .mark-rect').getBoundingClientRect().width")
        browser.wait_for(f"{rule} !== {rule_before}", timeout=10)  # Vega redraws asynchronously
        assert browser.evaluate(rule) - rule_before == pytest.approx(plot_width * 15 / 20.1, abs=2)
        after = browser.screenshot(tmp_path / "frame150.png")
        # frame 150: everyone in view is visible: no hidden colour left in the scene
        assert red_pixels(after, box) == 0
        assert browser.console_errors() == []


def test_an_interrupted_report_keeps_the_previous_one(recording, tmp_path, monkeypatch) -> None:
    # the page is written half and the write fails: the earlier report stays whole under its name (also while the
    # new one is being written) and nothing else is left in the folder
    from pathlib import Path

    target = write_report(recording, 0, tmp_path / "r.html", frames=slice(0, 3), progress=False)
    old = target.read_bytes()
    interrupted_writer(monkeypatch, Path, "write_text", target, old, lambda path: path.write_bytes(old[:1000]))
    with pytest.raises(OSError, match="disk full"):
        write_report(recording, 0, target, frames=slice(0, 4), progress=False)
    assert [p.name for p in tmp_path.iterdir()] == ["r.html"] and target.read_bytes() == old


def strict(text: str):
    """JSON as a browser's JSON.parse reads it: NaN and Infinity are no JSON."""
    return json.loads(text, parse_constant=lambda name: (_ for _ in ()).throw(ValueError(f"{name} is no JSON")))


def test_a_table_of_some_targets_makes_a_page_the_browser_can_read(recording, tmp_path) -> None:
    # objects without a row (targets=[3]) have no number: null, not NaN, which would stop the page's script
    table = get_visibility_df(recording, 0, targets=[3], progress=False)
    page = write_report(recording, 0, tmp_path / "t.html", frames=slice(0, 3), table=table, progress=False).read_text()
    scene = strict(re.search(r'<script id="scene-data" type="application/json">(.*?)</script>', page, re.S).group(1))
    objects = {o["idx"]: o for o in scene["frames"][0]["objects"]}
    assert objects[3]["vis"] == pytest.approx(table.filter(pl.col("frame") == 0)["visibility"][0], abs=1e-4)
    assert all(o["vis"] is None for i, o in objects.items() if i != 3)


def test_static_occluders_are_named_in_the_report(tmp_path) -> None:
    # the ego at x = 0, a wall at x = 10, a car at x = 20 wholly behind it: hidden by static occluder 0
    import shapely
    from conftest import boxes_table

    boxes = pl.concat([boxes_table([(0, 0, 4, 2, 0), (20, 0, 4, 2, 0)], frame=k) for k in range(3)])
    wall = [shapely.box(10, -5, 10.5, 5)]
    page = write_report(boxes, 0, tmp_path / "w.html", wall, progress=False).read_text()
    scene = strict(re.search(r'<script id="scene-data" type="application/json">(.*?)</script>', page, re.S).group(1))
    car = next(o for o in scene["frames"][0]["objects"] if o["idx"] == 1)
    assert (car["vis"], car["occluders"], car["statics"]) == (0.0, [], [0])
    summary = re.search(r'<table id="summary">(.*?)</table>', page, re.S).group(1)
    assert "<th>hidden by static occluders</th>" in summary
    assert summary_row(page, 1)["hidden by static occluders"] == "static #0"  # never a bare 0 that reads as none


def test_in_town_the_scene_keeps_its_labels_readable_and_off_other_road_users(tmp_path) -> None:
    import sys

    sys.path.insert(0, str(REPO / "scenarios"))
    from urban import urban_scene

    binary = find_chromium()
    if binary is None:
        pytest.skip("no chromium binary found (Debian: apt-get install chromium; .ci/run installs it as root)")
    table, buildings = urban_scene(frames=2)
    page = write_report(table, 0, tmp_path / "town.html", buildings, progress=False)
    assert "not seen (white)" in page.read_text()
    with Browser(binary) as browser:
        browser.open(page.as_uri())
        browser.wait_for("document.body.dataset.timeline")
        found = browser.evaluate(
            """(() => {
              const boxes = (sel) => [...document.querySelectorAll(sel)].map((e) => {
                const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom, e]; });
              const hit = (a, b) => a[0] < b[2] - 1 && b[0] < a[2] - 1 && a[1] < b[3] - 1 && b[1] < a[3] - 1;
              const labels = boxes('#scene text').filter((b) => /^\\d+: /.test(b[4].textContent));
              const bodies = boxes('#scene [data-idx]');
              const covering = labels.filter((l) => bodies.some((b) =>
                b[4].getAttribute('data-idx') !== l[4].textContent.split(':')[0] && hit(l, b)));
              return { labels: labels.length, px: labels.length ? labels[0][3] - labels[0][1] : 0,
                       covering: covering.map((l) => l[4].textContent), dots: document.querySelectorAll(
                         '#scene circle.object').length };
            })()"""
        )
    assert found["labels"] > 40 and found["covering"] == []
    assert found["px"] >= 12  # 13 px text whatever the window
    assert found["dots"] > 50  # pedestrians drawn as dots of 7 px, filled with their colour


def test_a_crowded_report_shows_the_most_hidden_targets_and_says_how_many_are_left_out(tmp_path) -> None:
    # 45 cars in three lanes ahead of the ego: the timeline shows the 40 least seen, the summary lists all 45
    from omega_prime_visibility.plot.report import MAX_BANDS, most_hidden_targets

    rows = [{"frame": f, "total_nanos": f * 10**8, "idx": 0, "x": 0.0, "y": 0.0, "length": 4.5, "width": 1.8,
             "yaw": 0.0} for f in range(2)]  # fmt: skip
    for k in range(45):
        for f in range(2):
            rows.append({"frame": f, "total_nanos": f * 10**8, "idx": k + 1, "x": 8.0 + 7.0 * (k // 3) + f,
                         "y": 3.5 * (k % 3 - 1), "length": 4.5, "width": 1.8, "yaw": 0.0})  # fmt: skip
    table = pl.DataFrame(rows)
    out = write_report(table, 0, tmp_path / "crowd.html", progress=False, view_range=200)
    page = out.read_text()
    assert f"the {MAX_BANDS} most hidden targets; 5 more in the summary below" in page
    vis = get_visibility_df(table, 0, progress=False)
    banded, left_out = most_hidden_targets(vis)
    means = vis.group_by("idx").agg(pl.col("visibility").mean()).sort("visibility", "idx")
    assert left_out == 5 and set(banded["idx"]) == set(means["idx"].head(MAX_BANDS))
    assert means["visibility"].head(MAX_BANDS).max() <= means["visibility"].tail(5).min()  # the least seen kept
    few, none_left = most_hidden_targets(vis.filter(pl.col("idx") <= 10))
    assert few.equals(vis.filter(pl.col("idx") <= 10)) and none_left == 0
