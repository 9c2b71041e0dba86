"""The campaign page (plot/campaign.py): offline, its tables say what campaign_statistics says, and it draws in a
real headless browser."""

from __future__ import annotations

import shutil
import subprocess
import sys

import pytest
from chromium import Browser, find_chromium
from conftest import REPO

from omega_prime_visibility import campaign_statistics, run_batch
from omega_prime_visibility.plot.campaign import write_campaign_page


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    folder = tmp_path_factory.mktemp("campaign")
    shutil.copyfile(REPO / "highway_merge.mcap", folder / "a.mcap")
    run_batch([folder / "a.mcap"], folder / "results", ego=0, conflicts=True, progress=False)
    return folder / "results"


def test_the_page_is_offline_and_its_tables_are_the_statistics(results, tmp_path) -> None:
    page = write_campaign_page(results, tmp_path / "campaign.html")
    text = page.read_text()
    assert "window.vegaEmbed=" in text and "<script src=" not in text and "cdn." not in text
    stats = campaign_statistics(results)
    row = stats["by_recording"].row(0, named=True)
    assert f"<td>{row['rows']}</td>" in text and f"<td>{100 * row['visible']:.1f} %</td>" in text  # % as the charts
    assert '<table id="conflicts">' in text and "<td>4</td>" in text  # the ego follows car 4
    assert [p.name for p in tmp_path.iterdir()] == ["campaign.html"]  # written atomically, nothing else left


def test_the_cli_writes_it_for_a_folder_and_refuses_an_empty_one(results, tmp_path) -> None:
    def cli(*args):
        command = [sys.executable, "-m", "omega_prime_visibility.cli", "report", *map(str, args)]
        return subprocess.run(command, capture_output=True, text=True)

    done = cli(results, "-o", tmp_path / "c.html")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "c.html").is_file()
    (tmp_path / "empty").mkdir()
    empty = cli(tmp_path / "empty", "-o", tmp_path / "d.html")
    assert empty.returncode == 2 and "holds no batch results" in empty.stderr and not (tmp_path / "d.html").exists()
    # options for one recording are refused for a folder, not ignored
    ego = cli(results, "-o", tmp_path / "e.html", "--ego", "3", "--mode", "3d")
    assert ego.returncode == 2 and ego.stderr.startswith("error: --ego and --mode apply to one recording")


def test_the_page_in_a_headless_browser(results, tmp_path) -> None:
    binary = find_chromium()
    if binary is None:
        pytest.skip("no chromium binary found (Debian: apt-get install chromium; .ci/run installs it as root)")
    page = write_campaign_page(results, tmp_path / "campaign.html")
    with Browser(binary) as browser:
        browser.open(page.as_uri())
        assert browser.wait_for("document.body.dataset.charts") == "ready"
        for chart in ("bands", "histogram", "occluders"):
            assert browser.evaluate(f"document.querySelectorAll('#{chart} svg .mark-rect path').length") > 0, chart
        # the stacked bars: three classes in each of the three bands, for the one type of target (vehicles), no
        # panel "all" repeating it
        assert browser.evaluate("document.querySelectorAll('#bands svg .mark-rect path').length") == 9
        assert browser.console_errors() == []


def test_every_bar_says_its_rows_and_an_empty_band_says_so() -> None:
    # pedestrians only near: their far bands have no rows, which the chart says ("no rows") instead of drawing a bar
    import polars as pl

    from omega_prime_visibility.plot.campaign import _bands_chart

    by_band = pl.DataFrame(
        {"band": ["< 20 m", "< 20 m", ">= 20 m"], "target_type": ["all", "pedestrian", "all"], "rows": [5, 2, 3],
         "visible": [0.6, 0.5, 1.0], "partly": [0.2, 0.5, 0.0], "hidden": [0.2, 0.0, 0.0], "out_of_view": [0.0] * 3}
    )  # fmt: skip
    spec = _bands_chart(by_band)
    rows = [r for data in spec["datasets"].values() for r in data]
    empty = [r for r in rows if r["band"] == ">= 20 m" and r["target_type"] == "pedestrian"]
    assert empty and all(r["rows"] == 0 for r in empty)
    text = json_text(spec)
    assert "'n = ' + format(datum.rows, ',')" in text and "'no rows'" in text and "datum.rows > 0" in text


def json_text(spec: dict) -> str:
    import json

    return json.dumps(spec)


def test_a_panel_for_all_only_beside_two_types_or_more() -> None:
    import polars as pl

    from omega_prime_visibility.plot.campaign import _bands_chart

    def panels(types: list[str]) -> set[str]:
        by_band = pl.DataFrame(
            {"band": ["< 20 m"] * len(types), "target_type": types, "rows": [4] * len(types),
             "visible": [0.5] * len(types), "partly": [0.25] * len(types), "hidden": [0.25] * len(types),
             "out_of_view": [0.0] * len(types)}
        )  # fmt: skip
        spec = _bands_chart(by_band)
        return {r["target_type"] for data in spec["datasets"].values() for r in data}

    assert panels(["all", "vehicle"]) == {"vehicle"}  # "all" would repeat the vehicles
    assert panels(["all", "pedestrian", "vehicle"]) == {"all", "pedestrian", "vehicle"}
