"""The README's example runs as written, and so do the examples of the documentation pages it links to."""

from __future__ import annotations

import os
import re
import warnings

import polars as pl
import pytest
from conftest import REPO

from omega_prime_visibility import get_visibility_df

COLUMNS = ("idx", "occluder_idxs", "static_occluder_idxs", "visibility")


PAGES = (
    "README.md",
    "docs/getting-started.md",
    "docs/sensors.md",
    "docs/3d.md",
    "docs/batch.md",
    "docs/pictures.md",
    "docs/conflicts.md",
    "docs/choices.md",
)


def python_blocks() -> list[str]:
    """The python code blocks of the README (first) and the documentation pages, in order."""
    return [block for page in PAGES for block in re.findall(r"```python\n(.*?)```", (REPO / page).read_text(), re.S)]


def run_block(code: str, namespace: dict, folder) -> list[warnings.WarningMessage]:
    """Run a code block in ``folder``; the warnings it gave."""
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            exec(compile(code, "README.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
    return caught


@pytest.fixture(scope="module")
def namespace() -> dict:
    """What the README's first example (ten lines) leaves behind, and the warnings it gave (``"warned"``)."""
    out: dict = {}
    warned = run_block(python_blocks()[0], out, REPO)
    out["warned"] = warned
    return out


def test_readme_example_warns_nothing(namespace) -> None:
    # omega-prime's Recording.from_file warned "Failed to apply projections." on the bundled recording
    said = [f"{w.category.__name__}: {w.message}" for w in namespace["warned"] if issubclass(w.category, UserWarning)]
    assert said == []


def test_readme_example_runs(namespace) -> None:
    df, everyone = namespace["df"], namespace["everyone"]
    # the Metric's table (no wall) is get_visibility_df's
    assert namespace["properties"]["visibility"].equals(get_visibility_df(namespace["r"], 0, progress=False))
    # 201 frames: 6 targets seen from the ego; 7 observers x 6 targets for everyone
    assert (df.height, everyone.height) == (1206, 8442)
    assert "idx_ego" in everyone.columns
    # frame 30 (the README's picture): the merging car idx 2 is behind the truck idx 1 and the wall; idx 3 peeks
    # over the wall's end; idx 6 is partly behind idx 4. The sweep engine gives the same numbers independently.
    swept = get_visibility_df(REPO / "highway_merge.mcap", 0, [namespace["wall"]], engine="sweep", progress=False)
    for table in (df, swept):
        rows = {r[0]: r[1:] for r in table.filter(pl.col("frame") == 30).select(COLUMNS).rows()}
        assert rows[2] == ([1], [0], 0.0)
        assert rows[3][:2] == ([], [0]) and rows[3][2] == pytest.approx(0.94707, abs=1e-5)
        assert rows[6][:2] == ([4], []) and rows[6][2] == pytest.approx(0.59755, abs=1e-5)
        assert rows[1] == rows[4] == rows[5] == ([], [], 1.0)
    hidden = df.group_by("idx").agg((pl.col("visibility") == 0).mean()).sort("idx")["visibility"].to_list()
    assert hidden == pytest.approx([0.0, 45 / 201, 96 / 201, 0.0, 0.0, 0.0], abs=1e-12)


def test_readme_pictures_example_runs(namespace, tmp_path) -> None:
    from PIL import Image

    pictures = next(block for block in python_blocks() if "plot_frame(" in block)
    run_block(pictures, dict(namespace), tmp_path)
    with Image.open(tmp_path / "merge.gif") as gif:
        assert gif.n_frames == 100  # every second of frames 0 to 199
    with Image.open(tmp_path / "timeline.png") as png:
        assert png.size[0] > 600
    assert "window.vegaEmbed=" in (tmp_path / "report.html").read_text()


def test_readme_sensors_example_and_its_numbers(namespace) -> None:
    block = next(block for block in python_blocks() if "sensors=" in block and "seen_by_any" in block)
    ns = dict(namespace)
    run_block(block, ns, REPO)
    per_sensor, best, intervals, seen = ns["per_sensor"], ns["best"], ns["intervals"], ns["seen"]
    assert per_sensor.height == 6 * 1206 and per_sensor["sensor"].n_unique() == 6
    at30 = per_sensor.filter(pl.col("frame") == 30)
    looking = at30.filter(pl.col("idx") == 2, pl.col("in_view") > 0)
    assert len(looking) and (looking["status"] == "occluded").all()
    camera6 = at30.filter(pl.col("idx") == 6, pl.col("sensor") == "front_camera").row(0, named=True)
    assert (camera6["status"], camera6["in_view"], round(camera6["visibility"], 2)) == ("partly_visible", 1.0, 0.58)
    truck = at30.filter(pl.col("idx") == 1, pl.col("sensor") == "front_camera").row(0, named=True)
    assert truck["status"] == "partly_visible" and truck["in_view"] < 0.2
    car2 = intervals.filter(pl.col("idx") == 2).row(0, named=True)
    assert (car2["start_nanos"], car2["noticed_nanos"]) == (4_500_000_000, 5_000_000_000)
    car3 = intervals.filter(pl.col("idx") == 3).select("start_frame", "end_frame").rows()
    assert car3 == [(0, 34), (65, 113), (135, 188)]
    assert round(seen.area) == 17771
    assert best.height == 1206


def test_docs_3d_example_runs_on_the_bundled_recording(namespace) -> None:
    block = next(block for block in python_blocks() if 'mode="3d"' in block)
    ns = dict(namespace)
    run_block(block, ns, REPO)
    solid = ns["solid"]
    assert solid.height == 1206 and solid.columns[-1] == "can_see"
    hidden = solid.filter(pl.col("frame") == 30, pl.col("idx") == 2).row(0, named=True)
    assert (hidden["can_see"], hidden["occluder_idxs"]) == (False, [1])  # the 4 m truck hides the merging car


def test_docs_conflicts_examples_run(namespace) -> None:
    blocks = [block for block in python_blocks() if "occluded_conflicts" in block]
    ns = dict(namespace)
    for block in blocks:
        run_block(block, ns, REPO)
    conflicts = ns["conflicts"]
    # the bundled merge: the ego follows car 4 (1.4 s behind it), seen throughout
    assert conflicts["idx"].to_list() == [4] and conflicts["timegap"][0] == pytest.approx(-1.4)
    assert ns["properties"]["occluded_conflicts"].equals(conflicts)
    statistics = next(block for block in python_blocks() if "occlusion_statistics(" in block)
    run_block(statistics, ns, REPO)
    assert ns["one"]["histogram"]["rows"].sum() == 1206


@pytest.mark.parametrize("page", ["docs/cameras.md", "docs/lichtblick.md"])
def test_the_camera_and_lichtblick_pages_examples_run(page, tmp_path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    (tmp_path / "highway_merge.mcap").symlink_to(REPO / "highway_merge.mcap")
    blocks = re.findall(r"```python\n(.*?)```", (REPO / page).read_text(), re.S)
    ns: dict = {}
    for block in blocks:
        run_block(block, ns, tmp_path)
    if page.endswith("cameras.md"):
        label = tmp_path / "kitti" / "front" / "label_2" / "000030.txt"
        assert (
            label.read_text().split()[0] == "Truck"
            and ns["levels"]["kitti_difficulty"].null_count() < ns["levels"].height
        )
    else:
        assert (tmp_path / "vis.mcap").stat().st_size > 0 and list(tmp_path.glob("*_sd_*_201_ego0.osi"))
