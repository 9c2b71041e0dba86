"""``omega-prime-visibility animate`` and ``report`` as a user calls them: files written, one-line errors."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from conftest import REPO
from PIL import Image
from test_cli import assert_error, files_under

MCAP = REPO / "highway_merge.mcap"


def cli(*args: str | Path) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-m", "omega_prime_visibility", *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True)


def test_animate_writes_a_gif_of_the_asked_frames(tmp_path) -> None:
    out = cli("animate", MCAP, "--ego", "0", "--frames", "30:36:2", "--target", "2", "--no-progress",
              "-o", tmp_path / "merge.gif")  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == f"wrote {tmp_path / 'merge.gif'}"
    with Image.open(tmp_path / "merge.gif") as im:
        assert im.n_frames == 3  # frames 30, 32, 34
    assert files_under(tmp_path) == {Path("merge.gif")}


def test_report_writes_one_html_file(tmp_path) -> None:
    out = cli("report", MCAP, "--frames", "0:10", "--no-progress", "-o", tmp_path / "r.html")  # host vehicle
    assert out.returncode == 0, out.stderr
    page = (tmp_path / "r.html").read_text()
    assert "Visibility report: highway_merge.mcap" in page and "seen from host vehicle idx 0; 10 frames" in page
    assert out.stdout.splitlines()[0] == "observer: host vehicle idx 0 (the recording's; --ego IDX for another)"


def test_the_default_observer_is_named_by_every_command(tmp_path) -> None:
    # run, animate and report without --ego say whom they look from; with --ego they say nothing of it
    said = "observer: host vehicle idx 0 (the recording's; --ego IDX for another)"
    for args in (("run", MCAP, "--rows", "1"), ("animate", MCAP, "--frames", "0:2", "-o", tmp_path / "a.gif")):
        out = cli(*args, "--no-progress")
        assert out.returncode == 0, out.stderr
        assert said in out.stdout.splitlines()
        out = cli(*args, "--no-progress", "--ego", "0")
        assert out.returncode == 0 and "observer:" not in out.stdout + out.stderr


def test_a_report_of_a_read_recording_is_titled_by_its_file(tmp_path) -> None:
    from omega_prime_visibility import read_recording, write_report

    write_report(read_recording(MCAP), 3, tmp_path / "r.html", frames=range(0, 3), progress=False)
    page = (tmp_path / "r.html").read_text()
    assert "Visibility report: highway_merge.mcap" in page and "seen from idx 3; 3 frames" in page


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (("animate", MCAP, "-o", "x.avi"), ("x.avi", ".gif or .mp4")),
        (("report", MCAP, "-o", "x.pdf"), ("x.pdf", ".html")),
        (("animate", MCAP, "--frames", "30-40", "-o", "x.gif"), ("--frames", "'30-40'")),
        (("animate", MCAP, "--ego", "0,1", "-o", "x.gif"), ("one idx",)),
        (("animate", MCAP, "--engine", "nope", "-o", "x.gif"), ("unknown engine 'nope'",)),
        (("report", MCAP, "--view-range", "-1", "-o", "x.html"), ("--view-range must be a positive number", "-1.0")),
        (("report", MCAP, "--view-range", "nan", "-o", "x.html"), ("--view-range must be a positive number", "nan")),
        (("animate", MCAP, "--view-range", "-1", "-o", "x.gif"), ("--view-range must be a positive number",)),
    ],
)
def test_bad_arguments_fail_before_computing(tmp_path, args, fragments) -> None:
    out = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility", *map(str, args)], capture_output=True, text=True,
        cwd=tmp_path,
    )  # fmt: skip
    assert_error(out, *fragments)
    assert files_under(tmp_path) == set()


def test_frames_that_do_not_occur_are_one_line(tmp_path) -> None:
    out = cli("animate", MCAP, "--frames", "300:400", "-o", tmp_path / "x.gif")
    assert_error(out, "frame range 300 to 400 (stop excluded) is empty", "frames 0 to 200")
    assert files_under(tmp_path) == set()


RAIL = '{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[60, -5.4], [140, -5.4]]}}]}'  # noqa: E501


def test_animate_and_report_take_static_and_mode_3d(tmp_path) -> None:
    rail = tmp_path / "rail.geojson"
    rail.write_text(RAIL)
    out = cli("animate", MCAP, "--ego", "0", "--frames", "30:32", "--static", rail, "--mode", "3d", "--no-progress",
              "-o", tmp_path / "a.gif")  # fmt: skip
    assert out.returncode == 0, out.stderr
    with Image.open(tmp_path / "a.gif") as im:
        assert im.n_frames == 2
    out = cli("report", MCAP, "--frames", "30:32", "--static", rail, "--mode", "3d", "--no-progress",
              "-o", tmp_path / "r.html")  # fmt: skip
    assert out.returncode == 0, out.stderr
    page = (tmp_path / "r.html").read_text()
    assert '"statics":[{"kind":"line","points":[60.0,-5.4,140.0,-5.4]}]' in page  # the rail is in the scene
    # the scene shows the 3D numbers (the rail 100 m high by default: a wall), which differ from the 2D ones
    import json
    import re
    import warnings

    import polars as pl
    import shapely

    from omega_prime_visibility import get_visibility_df
    from omega_prime_visibility.inputs.io import read_recording

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(MCAP)
        rail_line = [shapely.LineString([(60, -5.4), (140, -5.4)])]
        want = get_visibility_df(r, 0, rail_line, mode="3d", progress=False).filter(pl.col("frame") == 30)
        flat = get_visibility_df(r, 0, rail_line, progress=False).filter(pl.col("frame") == 30)
    scene = json.loads(re.search(r'<script id="scene-data" type="application/json">(.*?)</script>', page, re.S)[1])
    got = {o["idx"]: o["vis"] for o in scene["frames"][0]["objects"] if not o["ego"]}
    assert got == pytest.approx(dict(want.select("idx", "visibility").rows()), abs=1e-4)
    assert got != pytest.approx(dict(flat.select("idx", "visibility").rows()), abs=1e-4)


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (("--target", "99"), ("target idx 99 never occurs",)),
        (("--mode", "4d"), ("mode must be '2d' or '3d'",)),
        (("--mode", "3d", "--engine", "sweep"), ("'sweep' is a 2d engine", "--mode 2d")),
        (("--static", "missing.geojson"), ("missing.geojson",)),
    ],
)
def test_animate_bad_target_mode_or_static_is_one_line(tmp_path, args, fragments) -> None:
    out = cli("animate", MCAP, "--frames", "30:32", *args, "-o", tmp_path / "x.gif")
    assert_error(out, *fragments)
    assert files_under(tmp_path) == set()


def test_a_view_range_of_a_thousand_kilometres_is_drawn(tmp_path) -> None:
    # VisiLibity cannot draw a region in a box of thousands of km: the sweep's outline takes over
    out = cli("report", MCAP, "--ego", "0", "--frames", "0:2", "--view-range", "1e6", "--no-progress",
              "-o", tmp_path / "r.html")  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert files_under(tmp_path) == {Path("r.html")}


def test_pictures_take_who_may_block(tmp_path) -> None:
    # only idx 1 may block: the report's scene shows the numbers of that choice, not the default's
    import json
    import re
    import warnings

    import polars as pl

    from omega_prime_visibility import get_visibility_df
    from omega_prime_visibility.inputs.io import read_recording

    out = cli("report", MCAP, "--frames", "0:201:20", "--occluders", "1", "--no-progress", "-o", tmp_path / "r.html")
    assert out.returncode == 0, out.stderr
    page = (tmp_path / "r.html").read_text()
    scene = json.loads(re.search(r'<script id="scene-data" type="application/json">(.*?)</script>', page, re.S)[1])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(MCAP)
        want = get_visibility_df(r, 0, occluders=[1], progress=False)
        default = get_visibility_df(r, 0, progress=False)
    frames = [f["frame"] for f in scene["frames"]]
    got = {(f["frame"], o["idx"]): o["vis"] for f in scene["frames"] for o in f["objects"] if not o["ego"]}
    rows = want.filter(pl.col("frame").is_in(frames)).select("frame", "idx", "visibility").rows()
    assert got == pytest.approx({(f, i): v for f, i, v in rows}, abs=1e-4)
    rows = default.filter(pl.col("frame").is_in(frames)).select("frame", "idx", "visibility").rows()
    assert got != pytest.approx({(f, i): v for f, i, v in rows}, abs=1e-4)
    out = cli("animate", MCAP, "--frames", "30:32", "--occluders", "walkers", "-o", tmp_path / "x.gif")
    assert_error(out, "--occluders", "unknown object kind 'walkers'")
    assert not (tmp_path / "x.gif").exists()


def test_the_picture_commands_take_every_table_option_run_takes(tmp_path) -> None:
    # the report of targets 2 and 5 by their footprints' area: its scene shows those numbers (the others are
    # context, without a number) and its subtitle states the choices
    import json
    import re
    import warnings

    import polars as pl

    from omega_prime_visibility import get_visibility_df
    from omega_prime_visibility.inputs.io import read_recording

    page_path = tmp_path / "r.html"
    out = cli("report", MCAP, "--frames", "0:201:40", "--targets", "2,5", "--measure", "area", "--no-progress",
              "-o", page_path)  # fmt: skip
    assert out.returncode == 0, out.stderr
    page = page_path.read_text()
    assert "engine area, % = share of its area seen, whom to look for: 2, 5" in page
    scene = json.loads(re.search(r'<script id="scene-data" type="application/json">(.*?)</script>', page, re.S)[1])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        want = get_visibility_df(read_recording(MCAP), 0, targets=[2, 5], measure="area", progress=False)
    got = {(f["frame"], o["idx"]): o["vis"] for f in scene["frames"] for o in f["objects"] if not o["ego"]}
    frames = [f["frame"] for f in scene["frames"]]
    rows = want.filter(pl.col("frame").is_in(frames)).select("frame", "idx", "visibility").rows()
    assert {k: v for k, v in got.items() if v is not None} == pytest.approx({(f, i): v for f, i, v in rows}, abs=1e-4)
    assert {i for (_, i), v in got.items() if v is None} == {1, 3, 4, 6}  # context: no row, no number
    for command, suffix in (("animate", "a.gif"), ("report", "b.html")):
        bad = cli(command, MCAP, "--targets", "lorries", "--no-progress", "-o", tmp_path / suffix)
        assert_error(bad, "--targets: unknown object kind 'lorries'")
        lone = cli(command, MCAP, "--map-occluders", "--no-progress", "-o", tmp_path / suffix)
        assert lone.returncode in (0, 2)  # the bundled MCAP carries no OpenDRIVE map: refused in words, or none
        if lone.returncode == 2:
            assert_error(lone, "--map-occluders needs a recording that carries an OpenDRIVE map")
