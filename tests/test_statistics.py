"""Occlusion statistics (analysis/statistics.py): shares per distance band and type, the histogram and the
occluders' types, on a hand-made table with shares derived on paper."""

from __future__ import annotations

import polars as pl
import pytest

from omega_prime_visibility import VisibilityInputWarning, occlusion_statistics

VEHICLE, PEDESTRIAN = 2, 3


def scene() -> tuple[pl.DataFrame, pl.DataFrame]:
    """Two frames, the ego 0 at (6000, -3000), positions below relative to it. Frame 0: car 1 at 10 m (visibility
    1.0), pedestrian 2 at 19.99 m (0.5, behind 1), car 3 at 20 m exactly (0.05, behind 1 and 4), truck 4 at 35 m
    (0.9); frame 1: car 1 at 50 m (0.0, behind 4), pedestrian 2 at 70 m (0.1, behind 4), truck 4 at 40 m (0.95)."""
    objects = pl.DataFrame(
        {
            "total_nanos": [0] * 5 + [100] * 4,
            "idx": [0, 1, 2, 3, 4, 0, 1, 2, 4],
            "x": [0.0, 10.0, 0.0, 20.0, 35.0, 0.0, 50.0, 0.0, 40.0],
            "y": [0.0, 0.0, 19.99, 0.0, 0.0, 0.0, 0.0, 70.0, 0.0],
            "type": [VEHICLE, VEHICLE, PEDESTRIAN, VEHICLE, VEHICLE, VEHICLE, VEHICLE, PEDESTRIAN, VEHICLE],
        }
    ).with_columns(x=pl.col("x") + 6000.0, y=pl.col("y") - 3000.0)  # at map coordinates: distances are relative
    table = pl.DataFrame(
        {
            "frame": [0, 0, 0, 0, 1, 1, 1],
            "total_nanos": [0, 0, 0, 0, 100, 100, 100],
            "idx": [1, 2, 3, 4, 1, 2, 4],
            "visibility": [1.0, 0.5, 0.05, 0.9, 0.0, 0.1, 0.95],
            "occluder_idxs": [[], [1], [1, 4], [], [4], [4], []],
        },
        schema_overrides={"occluder_idxs": pl.List(pl.Int64)},
    )
    return table, objects


def test_shares_by_band_and_type_on_paper() -> None:
    table, objects = scene()
    stats = occlusion_statistics(table, objects, ego_idx=0, partly=(0.1, 0.9))
    rows = {(r["band"], r["target_type"]): r for r in stats["by_band"].iter_rows(named=True)}
    # bounds (0.1, 0.9): hidden at or below 0.1, visible at or above 0.9 (each bound belongs to the outer class)
    # < 20 m: car 1 (visible, 1.0), pedestrian 2 (partly, 0.5)
    near = rows[("< 20 m", "all")]
    assert (near["rows"], near["visible"], near["partly"], near["hidden"]) == (2, 0.5, 0.5, 0.0)
    # 20 to 50 m: car 3 at exactly 20 m (hidden, 0.05), truck 4 at 35 m (0.9: visible, the bound is in it),
    # truck 4 at 40 m (visible)
    mid = rows[("20 to 50 m", "all")]
    assert mid["rows"] == 3 and mid["visible"] == pytest.approx(2 / 3)
    assert mid["partly"] == 0.0 and mid["hidden"] == pytest.approx(1 / 3)
    # >= 50 m: car 1 at exactly 50 m (hidden), pedestrian 2 at 70 m (0.1: hidden, the bound is in it)
    far = rows[(">= 50 m", "all")]
    assert (far["rows"], far["visible"], far["partly"], far["hidden"]) == (2, 0.0, 0.0, 1.0)
    assert rows[("< 20 m", "pedestrian")]["partly"] == 1.0 and rows[(">= 50 m", "vehicle")]["hidden"] == 1.0
    assert stats["by_band"]["out_of_view"].to_list() == [0.0] * stats["by_band"].height  # no sensors: all in view
    bands = stats["by_band"]["band"].to_list()
    assert bands == sorted(bands, key=["< 20 m", "20 to 50 m", ">= 50 m"].index)  # near to far
    # histogram: 0.0, 0.05 in [0, 0.1); 0.1 in [0.1, 0.2); 0.5 in [0.5, 0.6); 0.9, 0.95, 1.0 in [0.9, 1.0]
    hist = stats["histogram"]
    assert hist["rows"].to_list() == [2, 1, 0, 0, 0, 1, 0, 0, 0, 3]
    assert hist["share"].sum() == pytest.approx(1.0) and hist["bin_start"][9] == pytest.approx(0.9)
    # occluders: car 1 twice (rows of 2 and 3), truck 4 three times (rows of 3, of 1 and of 2 in frame 1): vehicles
    # hide the target in 4 rows (the row of 3 counted once though two vehicles hide it), 5 occluding objects in all
    assert stats["occluder_types"].rows() == [("vehicle", 4, 5)]


def test_occluder_types_count_rows_once_per_type() -> None:
    # one target hidden by two cars and a pedestrian, another by one car, a third by nothing: cars hide 2 rows
    # (3 cars in all), pedestrians 1 row; a type whose objects repeat in a row's list still counts that row once
    objects = pl.DataFrame(
        {
            "total_nanos": [0] * 7,
            "idx": [0, 1, 2, 3, 4, 5, 6],
            "x": [0.0, 10.0, 12.0, 30.0, 14.0, 40.0, 50.0],
            "y": [0.0] * 7,
            "type": [2, 2, 2, 2, 3, 2, 2],
        }
    )
    table = pl.DataFrame(
        {
            "frame": [0, 0, 0],
            "total_nanos": [0, 0, 0],
            "idx": [3, 5, 6],
            "visibility": [0.0, 0.4, 1.0],
            "occluder_idxs": [[1, 2, 4], [1, 1], []],
        },
        schema_overrides={"occluder_idxs": pl.List(pl.Int64)},
    )
    stats = occlusion_statistics(table, objects, ego_idx=0)
    assert stats["occluder_types"].rows() == [("vehicle", 2, 4), ("pedestrian", 1, 1)]
    # never more rows than the table has, for every type
    assert (stats["occluder_types"]["rows"] <= table.height).all()


def test_the_default_is_the_exact_definition() -> None:
    # visible: all seen (1.0); hidden: nothing seen (0.0); everything else partly hidden, as target_summary says
    table, objects = scene()
    all_rows = occlusion_statistics(table, objects, ego_idx=0)["by_band"].filter(pl.col("target_type") == "all")
    assert all_rows.select("band", "rows", "visible", "partly", "hidden").rows() == [
        ("< 20 m", 2, 0.5, 0.5, 0.0),
        ("20 to 50 m", 3, 0.0, 1.0, 0.0),
        (">= 50 m", 2, 0.0, 0.5, 0.5),
    ]


def test_out_of_view_rows_are_not_hidden() -> None:
    # through sensors (combined by seen_by_any, which keeps the best in_view): car 1 out of every sensor's view,
    # pedestrian 2 half in view and all of that half seen (visible, nothing in front), car 3 in view and hidden
    table, objects = scene()
    table = table.with_columns(in_view=pl.Series([0.0, 0.5, 1.0, 1.0, 1.0, 1.0, 1.0]))
    table = table.with_columns(visibility=pl.Series([0.0, 0.5, 0.0, 0.9, 0.0, 0.1, 0.95]))
    near = occlusion_statistics(table, objects, ego_idx=0)["by_band"].row(0, named=True)
    assert (near["band"], near["target_type"], near["rows"]) == ("< 20 m", "all", 2)
    assert (near["visible"], near["partly"], near["hidden"], near["out_of_view"]) == (0.5, 0.0, 0.0, 0.5)


def test_other_bands_and_bounds() -> None:
    table, objects = scene()
    stats = occlusion_statistics(table, objects, ego_idx=0, bands=(30.0,), partly=(0.01, 0.99), bins=2)
    all_rows = stats["by_band"].filter(pl.col("target_type") == "all")
    assert all_rows.select("band", "rows").rows() == [("< 30 m", 3), (">= 30 m", 4)]
    # < 30 m: 1.0 visible, 0.5 and 0.05 partly; >= 30 m: 0.9, 0.1 partly, 0.95 partly, 0.0 hidden
    assert all_rows.select("visible", "partly", "hidden").rows() == [
        (pytest.approx(1 / 3), pytest.approx(2 / 3), 0.0),
        (0.0, 0.75, 0.25),
    ]
    assert stats["histogram"]["rows"].to_list() == [3, 4]


def test_bad_input() -> None:
    table, objects = scene()
    with pytest.raises(ValueError, match="pass ego_idx"):
        occlusion_statistics(table, objects)
    with pytest.raises(ValueError, match="object table lacks"):
        occlusion_statistics(table, objects.drop("type"), ego_idx=0)
    with pytest.raises(ValueError, match="ascending"):
        occlusion_statistics(table, objects, ego_idx=0, bands=(50.0, 20.0))
    with pytest.raises(ValueError, match="partly"):
        occlusion_statistics(table, objects, ego_idx=0, partly=(0.9, 0.1))
    with pytest.raises(ValueError, match="partly"):
        occlusion_statistics(table, objects, ego_idx=0, partly=(0.5, 0.5))
    with pytest.raises(ValueError, match="seen_by_any"):
        occlusion_statistics(table.with_columns(sensor=pl.lit("camera")), objects, ego_idx=0)


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """A batch output folder: the bundled recording twice (two names), ego 0, default options."""
    import shutil

    from conftest import REPO

    from omega_prime_visibility import run_batch

    folder = tmp_path_factory.mktemp("campaign")
    for name in ("a.mcap", "b.mcap"):
        shutil.copyfile(REPO / "highway_merge.mcap", folder / name)
    run_batch([folder / "a.mcap", folder / "b.mcap"], folder / "results", ego=0, progress=False)
    return folder


def test_campaign_over_a_batch_folder_equals_the_tables_own(campaign) -> None:
    from omega_prime_visibility import campaign_statistics, get_visibility_df
    from omega_prime_visibility.inputs.io import read_recording

    stats = campaign_statistics(campaign / "results")
    r = read_recording(campaign / "a.mcap")
    one = occlusion_statistics(get_visibility_df(r, 0, progress=False), r._df, ego_idx=0)
    # two copies of one recording: the same shares, twice the rows
    both = stats["by_band"].select("band", "target_type", "visible", "partly", "hidden")
    assert both.equals(one["by_band"].select("band", "target_type", "visible", "partly", "hidden"))
    assert stats["by_band"]["rows"].to_list() == [2 * n for n in one["by_band"]["rows"]]
    assert stats["histogram"]["rows"].to_list() == [2 * n for n in one["histogram"]["rows"]]
    assert stats["by_recording"]["rows"].to_list() == [1206, 1206]
    # in the bundled merge only vehicles occlude (the truck 1 and car 4): in every row with an occluder, counted once
    table = get_visibility_df(r, 0, progress=False)
    hidden_rows = table.filter(pl.col("occluder_idxs").list.len() > 0).height
    pairs = int(table["occluder_idxs"].list.len().sum())
    assert stats["occluder_types"].rows() == [("vehicle", 2 * hidden_rows, 2 * pairs)]


def test_campaign_bad_folders(campaign, tmp_path) -> None:
    import shutil

    from omega_prime_visibility import campaign_statistics, run_batch

    with pytest.raises(ValueError, match="holds no batch results"):
        campaign_statistics(tmp_path)
    with pytest.raises(ValueError, match="is not a folder"):
        campaign_statistics(tmp_path / "missing")
    mixed = tmp_path / "mixed"
    shutil.copytree(campaign / "results", mixed)
    run_batch([campaign / "a.mcap"], tmp_path / "other", ego=0, engine="sweep", progress=False)
    shutil.copyfile(tmp_path / "other" / "a.mcap.parquet", mixed / "c.mcap.parquet")
    with pytest.raises(ValueError, match=r"different options \(engine"):
        campaign_statistics(mixed)
    # a file that is not parquet at all beside the results: skipped and told, the statistics unchanged
    junk = tmp_path / "junk"
    shutil.copytree(campaign / "results", junk)
    (junk / "notes.parquet").write_text("not a table")
    with pytest.warns(
        VisibilityInputWarning, match=r"skipping 1 file\(s\) that are not readable parquet.*notes\.parquet"
    ):
        assert campaign_statistics(junk)["by_band"].equals(campaign_statistics(campaign / "results")["by_band"])
    # a batch whose every recording failed: its summary says so
    (tmp_path / "broken.mcap").write_text("not a recording")
    run_batch([tmp_path / "broken.mcap"], tmp_path / "failed", ego=0, progress=False)
    with pytest.raises(ValueError, match=r"holds no finished results: its batch summary lists 1 failed"):
        campaign_statistics(tmp_path / "failed")


def test_cli_statistics(campaign, tmp_path) -> None:
    import subprocess
    import sys

    def cli(*args):
        command = [sys.executable, "-m", "omega_prime_visibility.cli", "statistics", *map(str, args)]
        return subprocess.run(command, capture_output=True, text=True)

    out = cli(campaign / "results", "--bands", "30")
    assert out.returncode == 0, out.stderr
    assert "per recording" in out.stdout and "< 30 m" in out.stdout and ">= 30 m" in out.stdout
    empty = cli(tmp_path)
    assert empty.returncode == 2 and empty.stderr.startswith("error: ") and "holds no batch results" in empty.stderr
    bad = cli(campaign / "results", "--bands", "near")
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1


def test_batch_conflicts_beside_each_result_and_in_the_campaign(campaign, tmp_path) -> None:
    import subprocess
    import sys

    from omega_prime.metrics import MetricManager, distance_traveled, timegaps_and_min_timegaps, vel

    from omega_prime_visibility import campaign_statistics, get_visibility_df, occluded_conflicts
    from omega_prime_visibility.inputs.io import read_recording

    out = tmp_path / "results"
    command = [sys.executable, "-m", "omega_prime_visibility.cli", "batch", str(campaign / "a.mcap"), "-o", str(out)]
    done = subprocess.run([*command, "--ego", "0", "--conflicts", "--no-progress"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    written = pl.read_parquet(out / "a.mcap.conflicts.parquet")
    r = read_recording(campaign / "a.mcap")
    manager = MetricManager(metrics=[vel, distance_traveled, timegaps_and_min_timegaps])
    gaps = manager.compute(r, ego_id=0, time_buffer=3e9)[1]["timegaps"]
    assert written.equals(occluded_conflicts(get_visibility_df(r, 0, progress=False), gaps, r._df, ego_idx=0))
    assert written["idx"].to_list() == [4]  # the ego follows car 4
    stats = campaign_statistics(out)
    assert stats["conflicts"].select("recording", "idx").rows() == [(str(campaign / "a.mcap"), 4)]
    # the option is stored: a rerun without it recomputes (and the earlier conflicts file stays as it was)
    again = subprocess.run([*command, "--ego", "0", "--no-progress"], capture_output=True, text=True)
    assert again.returncode == 0 and "1 done" in again.stdout
    assert campaign_statistics(campaign / "results")["conflicts"].height == 0  # a folder without --conflicts


def test_campaign_reads_the_objects_batch_stored_not_the_recording(tmp_path) -> None:
    import shutil

    from conftest import REPO

    from omega_prime_visibility import campaign_statistics, run_batch

    copy = tmp_path / "gone.mcap"
    shutil.copyfile(REPO / "highway_merge.mcap", copy)
    run_batch([copy], tmp_path / "results", ego=0, progress=False)
    objects = tmp_path / "results" / "gone.mcap.objects.parquet"
    assert pl.read_parquet(objects).columns == ["total_nanos", "idx", "x", "y", "type"]
    before = campaign_statistics(tmp_path / "results")
    copy.unlink()  # the recording moved away: the stored objects suffice
    assert campaign_statistics(tmp_path / "results")["by_band"].equals(before["by_band"])
    objects.unlink()  # neither: say which recording is missing
    with pytest.raises(ValueError, match=r"cannot read the recording .*gone\.mcap"):
        campaign_statistics(tmp_path / "results")


def test_an_empty_table_gives_empty_shares_not_nan() -> None:
    table, objects = scene()
    stats = occlusion_statistics(table.clear(), objects, ego_idx=0)
    assert stats["by_band"].height == 0 and stats["occluder_types"].height == 0
    assert stats["histogram"]["rows"].sum() == 0 and stats["histogram"]["share"].to_list() == [0.0] * 10


def test_campaign_of_every_observer_uses_the_stored_objects(tmp_path) -> None:
    import shutil

    from conftest import REPO

    from omega_prime_visibility import campaign_statistics, get_visibility_df, run_batch

    copy = tmp_path / "all.mcap"
    shutil.copyfile(REPO / "highway_merge.mcap", copy)
    run_batch([copy], tmp_path / "results", ego="all", progress=False)
    from omega_prime_visibility.inputs.io import read_recording

    r = read_recording(copy)
    expected = occlusion_statistics(get_visibility_df(r, "all", progress=False), r._df)
    copy.unlink()  # every row names its observer (idx_ego): the stored objects are all that is needed
    assert campaign_statistics(tmp_path / "results")["by_band"].equals(expected["by_band"])


def test_other_tables_and_unknown_observers_are_one_clear_error() -> None:
    objects = pl.DataFrame({"total_nanos": [0, 0, 0], "idx": [0, 1, 2], "x": [0.0, 10.0, 60.0], "y": [0.0] * 3})
    objects = objects.with_columns(type=pl.Series([2, 2, 3]))
    table = pl.DataFrame(
        {"frame": [0, 0], "total_nanos": [0, 0], "idx": [1, 2], "visibility": [1.0, 0.05], "occluder_idxs": [[], [1]]}
    )
    with pytest.raises(ValueError, match=r"observer idx \[9\] never occur"):
        occlusion_statistics(table, objects, ego_idx=9)
    with pytest.raises(TypeError, match=r"visibility must be a polars DataFrame or LazyFrame.*not pandas\.DataFrame"):
        occlusion_statistics(table.to_pandas(), objects, ego_idx=0)
    # float idx in the objects (as get_visibility_df takes them) are the same objects
    floats = occlusion_statistics(table, objects.with_columns(pl.col("idx").cast(pl.Float64)), ego_idx=0)
    assert floats["by_band"].equals(occlusion_statistics(table, objects, ego_idx=0)["by_band"])
