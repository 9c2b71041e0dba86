"""``omega-prime-visibility batch`` and ``run_batch``: called as a user would (console script in a subprocess), on
folders mixing good, corrupt and mistaken files; results compared with ``get_visibility_df`` on the same files;
interrupted by a real signal and resumed; on a real two-process dask cluster."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import polars as pl
import pyarrow.parquet as pq
import pytest
import shapely
from conftest import REPO, SHARED_DATA, interrupted_writer
from polars.testing import assert_frame_equal

from omega_prime_visibility import VisibilityInputWarning, get_visibility_df, run_batch
from omega_prime_visibility.batch.files import OPTIONS_KEY, BatchNotice, find_recordings
from omega_prime_visibility.inputs.io import RecordingReadError, read_recording, read_static_occluders

MCAP = REPO / "highway_merge.mcap"
SCRIPT = Path(sys.executable).parent / "omega-prime-visibility"
SUMMARY = "_batch_summary.parquet"


def batch_cli(*args: str | Path, **popen) -> subprocess.CompletedProcess:
    return subprocess.run([str(SCRIPT), "batch", *map(str, args)], capture_output=True, text=True, **popen)


@pytest.fixture(scope="module")
def expected() -> pl.DataFrame:
    """The bundled recording's table from the API, ego 0 (what every batch result of a copy must equal)."""
    return get_visibility_df(read_recording(MCAP), 0, workers=1, progress=False)


def copies(folder: Path, n: int, prefix: str = "copy") -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / f"{prefix}{k}.mcap" for k in range(n)]
    for p in paths:
        shutil.copyfile(MCAP, p)
    return paths


def leftovers(folder: Path) -> list[Path]:
    return [p for p in folder.rglob("*") if p.name.endswith(".tmp")]


def test_end_to_end_folder_with_bad_files(tmp_path, expected) -> None:
    data = tmp_path / "data"
    copies(data, 2)
    (data / "sub").mkdir()
    shutil.copyfile(MCAP, data / "highway_merge.mcap")
    shutil.copyfile(MCAP, data / "sub" / "highway_merge.mcap")  # same name, other folder: its own result
    (data / "truncated.mcap").write_bytes(MCAP.read_bytes()[: MCAP.stat().st_size // 2])
    (data / "notes.mcap").write_text("these are my notes, not a recording\n")
    (data / "README.txt").write_text("ignored: not a recording suffix")
    osi = (SHARED_DATA / "pedestrian.osi").exists()
    if osi:  # an OSI trace with its map, when the real recordings are here
        shutil.copyfile(SHARED_DATA / "pedestrian.osi", data / "pedestrian.osi")
        shutil.copyfile(SHARED_DATA / "fabriksgatan.xodr", data / "fabriksgatan.xodr")
    out = tmp_path / "results"
    maps = ["--map", data / "fabriksgatan.xodr"] if osi else []
    run = batch_cli(data, "-o", out, "--ego", "0", *maps, "--workers", "2", "--no-progress")
    assert run.returncode == 1, run.stderr
    summary = pl.read_parquet(out / SUMMARY)
    failed = summary.filter(pl.col("status") == "failed")
    assert sorted(failed["result"]) == ["notes.mcap.parquet", "truncated.mcap.parquet"]
    for name, message in failed.select("result", "error").iter_rows():
        path = data / name.removesuffix(".parquet")
        cause = "the file is truncated" if name.startswith("truncated") else "it is not an MCAP file"
        assert f"cannot read {path}" in message and cause in message
        # one line per failure, naming the path once
        assert "\n" not in message and f"failed: {message}\n" in run.stdout
        assert sum(line.count(str(path)) for line in run.stdout.splitlines() if line.startswith("failed:")) == 1
    done = summary.filter(pl.col("status") == "done")
    names = ["copy0.mcap.parquet", "copy1.mcap.parquet", "highway_merge.mcap.parquet", "sub/highway_merge.mcap.parquet"]
    assert sorted(done["result"]) == sorted([*names, *(["pedestrian.osi.parquet"] if osi else [])])
    assert done["rows"].to_list().count(1206) == 4
    for name in names:
        assert_frame_equal(pl.read_parquet(out / name), expected)
    if osi:
        trace = read_recording(data / "pedestrian.osi", data / "fabriksgatan.xodr")
        assert_frame_equal(pl.read_parquet(out / "pedestrian.osi.parquet"), get_visibility_df(trace, 0, progress=False))
    assert not leftovers(out)
    assert "7 recordings: 5 done, 2 failed" in run.stdout or "6 recordings: 4 done, 2 failed" in run.stdout


def test_python_function_resumes_and_recomputes_on_new_options(tmp_path, expected) -> None:
    a, b = copies(tmp_path / "in", 2)
    out = tmp_path / "out"
    first = run_batch(tmp_path / "in", out, ego=0, workers=1, progress=False)
    assert first.select("result", "status", "rows").rows() == [
        ("copy0.mcap.parquet", "done", 1206),
        ("copy1.mcap.parquet", "done", 1206),
    ]
    stamp = {p: p.stat().st_mtime_ns for p in out.glob("*.mcap.parquet")}
    again = run_batch(str(tmp_path / "in" / "*.mcap"), out, ego=0, workers=1, progress=False)
    assert again["status"].to_list() == ["skipped", "skipped"] and again["rows"].to_list() == [1206, 1206]
    assert stamp == {p: p.stat().st_mtime_ns for p in stamp}  # nothing rewritten
    # a newer recording is recomputed, the other stays
    os.utime(b, ns=(time.time_ns() + 10**9, time.time_ns() + 10**9))
    assert run_batch([a, b], out, ego=0, workers=1, progress=False)["status"].to_list() == ["skipped", "done"]
    # other options: recomputed, and recorded in the result
    other = run_batch([a, b], out, ego=0, engine="sweep", workers=1, progress=False)
    assert other["status"].to_list() == ["done", "done"]
    assert b'"engine": "sweep"' in pq.read_metadata(out / "copy0.mcap.parquet").metadata[OPTIONS_KEY]
    assert_frame_equal(pl.read_parquet(out / "copy0.mcap.parquet"), expected, abs_tol=1e-6)
    assert run_batch([a], out, ego=0, engine="sweep", overwrite=True, progress=False)["status"].to_list() == ["done"]


def test_static_occluders_file_and_its_edits(tmp_path) -> None:
    wall = shapely.LineString([(60, -5.4), (140, -5.4)])
    walls = tmp_path / "walls.wkt"
    walls.write_text(f"# guard rail\n{wall.wkt}\n")
    out = tmp_path / "out"
    assert run_batch(MCAP, out, ego=0, static=walls, engine="sweep", progress=False)["status"][0] == "done"
    reference = get_visibility_df(read_recording(MCAP), 0, [wall], engine="sweep", progress=False)
    assert reference["static_occluder_idxs"].list.len().sum() > 0  # the wall does hide something
    assert_frame_equal(pl.read_parquet(out / "highway_merge.mcap.parquet"), reference)
    assert run_batch(MCAP, out, ego=0, static=walls, engine="sweep", progress=False)["status"][0] == "skipped"
    walls.write_text(f"{wall.wkt}\nLINESTRING (0 20, 10 20)\n")  # same path, new content: recomputed
    assert run_batch(MCAP, out, ego=0, static=walls, engine="sweep", progress=False)["status"][0] == "done"


def test_sensors_option(tmp_path) -> None:
    out = tmp_path / "out"
    first = run_batch(MCAP, out, ego=0, engine="sweep", sensors="roof", progress=False)
    assert first["status"].to_list() == ["done"]
    expected = get_visibility_df(read_recording(MCAP), 0, engine="sweep", sensors="roof", progress=False)
    assert "sensor" in expected.columns
    assert_frame_equal(pl.read_parquet(out / "highway_merge.mcap.parquet"), expected)
    # without sensors the result is another table: recomputed, not kept
    assert run_batch(MCAP, out, ego=0, engine="sweep", progress=False)["status"].to_list() == ["done"]
    assert "sensor" not in pl.read_parquet(out / "highway_merge.mcap.parquet").columns
    with pytest.raises(ValueError, match="unknown sensor layout 'lidar'"):
        run_batch(MCAP, out, sensors="lidar", progress=False)


def test_choices_options(tmp_path) -> None:
    choices = {"occluders": ["CAR"], "targets": [3, 2], "measure": "area"}
    first = run_batch(MCAP, tmp_path, ego=0, progress=False, **choices)
    assert first["status"].to_list() == ["done"], first["error"][0]
    expected = get_visibility_df(read_recording(MCAP), 0, progress=False, **choices)
    assert_frame_equal(pl.read_parquet(tmp_path / "highway_merge.mcap.parquet"), expected)
    stored = pq.read_metadata(tmp_path / "highway_merge.mcap.parquet").metadata[OPTIONS_KEY]
    assert b'"targets": [2, 3]' in stored and b'"measure": "area"' in stored and b'"occluders": ["CAR"]' in stored
    assert run_batch(MCAP, tmp_path, ego=0, progress=False, **choices)["status"].to_list() == ["skipped"]
    # the same choice spelt otherwise is the same table: skipped
    again = choices | {"occluders": ["car", " Car", "CAR"], "targets": [2, 3, 3]}
    assert run_batch(MCAP, tmp_path, ego=0, progress=False, **again)["status"].to_list() == ["skipped"]
    # other choices are another table: recomputed
    assert run_batch(MCAP, tmp_path, ego=0, progress=False, targets=[2, 3])["status"].to_list() == ["done"]
    for bad, message in (
        ({"occluders": "lorries"}, "unknown object kind 'lorries'"),
        ({"measure": "area", "engine": "sweep"}, "has its own exact engine"),
        ({"measure": "volume"}, "unknown measure"),
    ):
        with pytest.raises(ValueError, match=message):
            run_batch(MCAP, tmp_path, progress=False, **bad)


def test_the_whole_question(tmp_path) -> None:
    """run_batch takes a Query (with what the keywords cannot say: expressions, static heights), and its table is
    get_visibility_df's with the same question; the same question in other words is skipped."""
    from shapely import box

    from omega_prime_visibility import Query

    question = Query(
        observers=0,
        mode="3d",
        targets=pl.col("type") == 2,
        static_occluders=[box(30, -8, 40, -6), box(60, 2, 70, 4)],
        static_heights=(0.8, 3.0),
    )
    first = run_batch(MCAP, tmp_path, question, progress=False)
    assert first["status"].to_list() == ["done"], first["error"][0]
    expected = get_visibility_df(read_recording(MCAP), query=question, progress=False)
    assert_frame_equal(pl.read_parquet(tmp_path / "highway_merge.mcap.parquet"), expected)
    assert run_batch(MCAP, tmp_path, question.replace(observers=[0]), progress=False)["status"][0] == "done"
    assert run_batch(MCAP, tmp_path, question, progress=False)["status"][0] == "done"  # [0] is another table
    same = question.replace(targets=(pl.col("type") == 2))  # an equal expression built again
    assert run_batch(MCAP, tmp_path, same, progress=False)["status"][0] == "skipped"
    for changed in (question.replace(static_heights=(0.8, 3.5)), question.replace(targets=pl.col("type") == 3)):
        assert run_batch(MCAP, tmp_path, changed, progress=False)["status"][0] == "done"
    with pytest.raises(ValueError, match="mode='2d' contradicts the query's mode='3d'"):
        run_batch(MCAP, tmp_path, question, mode="2d", progress=False)
    # keywords and the question they fold into are one batch
    keywords = run_batch(MCAP, tmp_path / "k", ego=0, engine="sweep", targets="vehicles", progress=False)
    as_query = run_batch(MCAP, tmp_path / "k", Query(observers=0, engine="sweep", targets="VEHICLES"), progress=False)
    assert keywords["status"][0] == "done" and as_query["status"][0] == "skipped"


def test_mode_3d_option(tmp_path, widths_as_heights_mcap) -> None:
    summary = run_batch(widths_as_heights_mcap, tmp_path, ego=0, mode="3d", progress=False)
    assert summary["status"].to_list() == ["done"], summary["error"][0]
    with pytest.warns(VisibilityInputWarning, match="heights look like a copy of the widths"):
        expected = get_visibility_df(read_recording(widths_as_heights_mcap), 0, mode="3d", progress=False)
    assert "heights look like a copy of the widths" in summary["warnings"][0]  # the worker's warning, kept
    assert_frame_equal(pl.read_parquet(tmp_path / "highway_merge.mcap.parquet"), expected)
    assert b'"mode": "3d"' in pq.read_metadata(tmp_path / "highway_merge.mcap.parquet").metadata[OPTIONS_KEY]
    # the 2D table is another one: recomputed
    assert run_batch(MCAP, tmp_path, ego=0, progress=False)["status"].to_list() == ["done"]
    with pytest.raises(ValueError, match="unknown engine 'sweep' for mode='3d'"):
        run_batch(MCAP, tmp_path, mode="3d", engine="sweep", progress=False)


def test_static_occluder_files(tmp_path) -> None:
    geojson = tmp_path / "city.geojson"
    geojson.write_text(
        '{"type": "FeatureCollection", "features": ['
        '{"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", '
        '"coordinates": [[[0, 0], [4, 0], [4, 3], [0, 0]]]}},'
        '{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[0, 5], [9, 5]]}}]}'
    )
    parsed = read_static_occluders(geojson)
    assert [g.geom_type for g in parsed] == ["Polygon", "LineString"] and parsed[0].area == 6.0
    (tmp_path / "bad.wkt").write_text("LINESTRING (0 0, 1 1)\nPOLYGON ((0 0, 1\n")
    with pytest.raises(RecordingReadError, match=r"bad\.wkt, line 2, as WKT"):
        read_static_occluders(tmp_path / "bad.wkt")
    (tmp_path / "nogeom.geojson").write_text('{"type": "FeatureCollection", "features": [{"type": "Feature"}]}')
    with pytest.raises(RecordingReadError, match="feature 0 is no GeoJSON geometry"):
        read_static_occluders(tmp_path / "nogeom.geojson")
    # a map given as static occluders, by its name or (renamed) by its content: said so, with where it belongs
    (tmp_path / "town.xodr").write_text('<?xml version="1.0"?>\n<OpenDRIVE>\n  <header/>\n</OpenDRIVE>\n')
    (tmp_path / "town.txt").write_text((tmp_path / "town.xodr").read_text())
    for name in ("town.xodr", "town.txt"):
        with pytest.raises(RecordingReadError, match=r"is an OpenDRIVE map, not GeoJSON or WKT: give it with --map"):
            read_static_occluders(tmp_path / name)


def test_per_file_failures_for_ego(tmp_path) -> None:
    summary = run_batch(MCAP, tmp_path, ego=99, progress=False)
    assert summary["status"][0] == "failed" and "ego idx [99] never occurs" in summary["error"][0]
    assert not (tmp_path / "highway_merge.mcap.parquet").exists()


def test_osi_trace_without_host_vehicle_asks_for_ego(tmp_path, shared_data) -> None:
    summary = run_batch(shared_data / "pedestrian.osi", tmp_path, map=shared_data / "fabriksgatan.xodr", progress=False)
    assert summary["status"][0] == "failed"
    assert summary["error"][0] == (
        "pedestrian.osi names no host vehicle: give an observer for such recordings (--fallback-ego IDX keeps each "
        "recording's host vehicle where it names one), or one for all (--ego IDX, --ego all); present: VEHICLE idx "
        "[0]; PEDESTRIAN idx [1]"
    )


def test_a_mixed_folder_takes_each_host_vehicle_and_the_fallback_elsewhere(tmp_path, shared_data) -> None:
    # an MCAP file naming its host vehicle (idx 0; a copy whose host is idx 3) and an OSI trace naming none
    from omega_prime_visibility import campaign_statistics, get_visibility_df, read_recording

    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copyfile(MCAP, folder / "merge.mcap")
    shutil.copyfile(shared_data / "acc-test.osi", folder / "acc.osi")
    host_3 = read_recording(MCAP).to_omega_prime()
    host_3.host_vehicle_idx = 3
    host_3.to_mcap(folder / "merge_host3.mcap")
    kwargs = {"map": shared_data / "straight_500m.xodr", "progress": False, "engine": "sweep"}
    summary = run_batch(folder, tmp_path / "out", fallback_ego=1, **kwargs)
    assert summary.select("result", "status", "observer").rows() == [
        ("acc.osi.parquet", "done", "idx 1 (fallback: names no host vehicle)"),
        ("merge.mcap.parquet", "done", "host vehicle idx 0"),
        ("merge_host3.mcap.parquet", "done", "host vehicle idx 3"),
    ]
    for name, ego in (("acc.osi", 1), ("merge.mcap", 0), ("merge_host3.mcap", 3)):
        r = read_recording(folder / name, kwargs["map"] if name.endswith(".osi") else None)
        expected = get_visibility_df(r, ego, engine="sweep", progress=False)
        assert pl.read_parquet(tmp_path / "out" / f"{name}.parquet").equals(expected), name
    # a rerun skips them all and still says whom each is seen from; the campaign measures from the same observers
    again = run_batch(folder, tmp_path / "out", fallback_ego=1, **kwargs)
    assert again["status"].to_list() == ["skipped"] * 3 and again["observer"].equals(summary["observer"])
    assert campaign_statistics(tmp_path / "out")["by_recording"]["rows"].to_list() == summary["rows"].to_list()
    # a fallback is a new option: those results are recomputed; --ego beside it would never use it
    assert run_batch(folder, tmp_path / "out", **kwargs)["status"].to_list() == ["failed", "done", "done"]
    with pytest.raises(ValueError, match="fallback_ego applies where the observer is each recording's host"):
        run_batch(folder, tmp_path / "out", ego=0, fallback_ego=1, **kwargs)
    for bad in (1.5, "0", True):
        with pytest.raises(ValueError, match="fallback_ego takes one idx"):
            run_batch(folder, tmp_path / "out", fallback_ego=bad, **kwargs)


def test_map_list_for_traces(tmp_path) -> None:
    from omega_prime_visibility.batch.options import FileOptions

    (tmp_path / "maps").mkdir()
    (tmp_path / "maps" / "town.xodr").write_text("<OpenDRIVE/>")
    (tmp_path / "maps.json").write_text('[["a.osi", "maps/town.xodr"], ["b.osi", "maps/town.xodr"]]')
    options = FileOptions(map=tmp_path / "maps.json")
    options.check()
    assert options.map_for(Path("/anywhere/a.osi")) == str((tmp_path / "maps" / "town.xodr").resolve())
    with pytest.raises(ValueError, match=r"has no map for c\.osi"):  # not listed: refused, as run refuses it
        options.map_for(Path("c.osi"))
    assert FileOptions(map=tmp_path / "maps" / "town.xodr").map_for(Path("run.mcap")) is None  # its own map
    (tmp_path / "maps.json").write_text('[["a.osi", "maps/gone.xodr"]]')
    with pytest.raises(ValueError, match=r"names maps that do not exist: .*gone\.xodr"):
        FileOptions(map=tmp_path / "maps.json").check()
    (tmp_path / "maps.json").write_text("{not json")
    with pytest.raises(ValueError, match="cannot read the map list"):
        FileOptions(map=tmp_path / "maps.json").check()


def test_result_names_never_collide(tmp_path) -> None:
    for name in ("a/x.mcap", "b/x.mcap", "b/deeper/x.osi", "b/.hidden/y.mcap", "c/x.mcap"):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).touch()
    pairs = find_recordings([tmp_path / "a" / "x.mcap", tmp_path / "b", tmp_path / "c" / "x.mcap"], Path("out"))
    assert [str(result) for _, result in pairs] == [
        "out/a/x.mcap.parquet",
        "out/b/x.mcap.parquet",  # three x.mcap: each below the folder all three share
        "out/deeper/x.osi.parquet",
        "out/c/x.mcap.parquet",
    ]


def test_interrupted_by_a_signal_then_resumed(tmp_path, expected) -> None:
    copies(tmp_path / "in", 8)
    out = tmp_path / "out"
    args = [str(SCRIPT), "batch", str(tmp_path / "in"), "-o", str(out), "--workers", "2", "--no-progress"]
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 120
    while len(list(out.glob("*.mcap.parquet"))) < 2 and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    os.killpg(process.pid, signal.SIGINT)  # Ctrl-C: the whole process group
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 130, stderr
    assert "interrupted: run the same command again" in stderr
    assert "leaked" not in stderr  # (multiprocessing's resource tracker: a lock the stopped workers held)
    assert not leftovers(out)
    before = {p.name: p.stat().st_mtime_ns for p in out.glob("*.mcap.parquet")}
    assert 2 <= len(before) < 8
    stopped = pl.read_parquet(out / SUMMARY)
    assert set(stopped["status"]) <= {"done", "interrupted"} and (stopped["status"] == "interrupted").any()
    assert_summary_says_what_is_on_disk(stopped, out)
    rerun = batch_cli(tmp_path / "in", "-o", out, "--workers", "2", "--no-progress")
    assert rerun.returncode == 0, rerun.stderr
    summary = pl.read_parquet(out / SUMMARY)
    status = dict(zip(summary["result"], summary["status"], strict=True))
    assert {name for name, s in status.items() if s == "skipped"} == set(before)
    assert {name for name, s in status.items() if s == "done"} == {f"copy{k}.mcap.parquet" for k in range(8)} - set(
        before
    )
    assert before == {name: (out / name).stat().st_mtime_ns for name in before}  # not recomputed
    for name in status:
        assert_frame_equal(pl.read_parquet(out / name), expected)
    assert not leftovers(out)


def assert_summary_says_what_is_on_disk(summary: pl.DataFrame, out: Path) -> None:
    """Every result on disk is labelled done (with its rows), every interrupted one is absent."""
    for result, status, rows in summary.select("result", "status", "rows").iter_rows():
        on_disk = (out / result).is_file()
        assert (status == "done") == on_disk, (result, status, on_disk)
        if on_disk:
            assert rows == pl.scan_parquet(out / result).select(pl.len()).collect().item()


def test_ctrl_c_is_heard_while_every_worker_is_busy(tmp_path) -> None:
    # 3D through six sensors: each copy keeps its worker busy for tens of seconds (more with kernels to compile).
    # Ctrl-C once both workers have started must stop the batch at once, not when a file finishes: the stopped
    # workers remove what they were writing, and the summary says what is on disk.
    copies(tmp_path / "in", 4)
    out = tmp_path / "out"
    args = [str(SCRIPT), "batch", str(tmp_path / "in"), "-o", str(out), "--workers", "2", "--no-progress"]
    args += ["--mode", "3d", "--sensors", "typical", "--ego", "all"]
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 60
    while len(descendants(process.pid, 2)) < 2 and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(1.0)  # the workers are inside their first file
    os.killpg(process.pid, signal.SIGINT)
    _, stderr = process.communicate(timeout=12)  # a file takes longer than this: the stop did not wait for one
    assert process.returncode == 130, stderr
    assert not leftovers(out)
    assert_summary_says_what_is_on_disk(pl.read_parquet(out / SUMMARY), out)


def descendants(pid: int, depth: int) -> list[int]:
    """Processes ``depth`` generations below ``pid`` (from /proc): the pool's workers sit below its forkserver."""
    parents = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                parents[int(entry.name)] = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError):
                pass
    level = [pid]
    for _ in range(depth):
        level = [child for child, parent in parents.items() if parent in level]
    return level


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="finds the workers through /proc")
def test_killed_worker_loses_nothing(tmp_path, expected) -> None:
    copies(tmp_path / "in", 10)
    out = tmp_path / "out"
    args = [str(SCRIPT), "batch", str(tmp_path / "in"), "-o", str(out), "--workers", "2", "--no-progress"]
    process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list(out.glob("*.mcap.parquet")) and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    workers = descendants(process.pid, 2)
    assert workers, "no pool workers found"
    os.kill(workers[0], signal.SIGKILL)
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == 0, stdout + stderr
    summary = pl.read_parquet(out / SUMMARY)
    assert summary["status"].to_list() == ["done"] * 10  # the files the dead worker held were computed again
    for name in summary["result"]:
        assert_frame_equal(pl.read_parquet(out / name), expected)
    assert not leftovers(out)


def test_dask_local_cluster_gives_the_local_results(tmp_path, expected) -> None:
    from distributed import LocalCluster

    copies(tmp_path / "in", 3)
    (tmp_path / "in" / "broken.mcap").write_bytes(b"\x89MCAP0\r\n")
    local = run_batch(tmp_path / "in", tmp_path / "local", workers=1, progress=False)
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=":0"
    ) as cluster:
        remote = batch_cli(tmp_path / "in", "-o", tmp_path / "dask", "--scheduler", cluster.scheduler_address)
    assert remote.returncode == 1, remote.stderr
    assert "failed: " in remote.stdout and "broken.mcap" in remote.stdout
    columns = ["recording", "result", "status", "rows", "error"]
    assert_frame_equal(pl.read_parquet(tmp_path / "dask" / SUMMARY).select(columns), local.select(columns))
    assert local["status"].to_list() == ["failed", "done", "done", "done"]
    for k in range(3):
        assert_frame_equal(pl.read_parquet(tmp_path / "dask" / f"copy{k}.mcap.parquet"), expected)
    assert not leftovers(tmp_path / "dask")


def assert_cli_error(run: subprocess.CompletedProcess, *fragments: str) -> None:
    assert run.returncode == 2, run.stderr
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), run.stderr
    for fragment in fragments:
        assert fragment in lines[0]


def test_bad_options(tmp_path) -> None:
    (tmp_path / "file.txt").write_text("a file")
    out = tmp_path / "out"
    assert_cli_error(batch_cli(MCAP, "-o", out, "--workers", "0"), "workers must be", "not 0")
    assert_cli_error(
        batch_cli(MCAP, "-o", tmp_path / "file.txt"), f"the output folder {tmp_path / 'file.txt'} is a file"
    )
    assert_cli_error(batch_cli(tmp_path / "nowhere", "-o", out), f"input {tmp_path / 'nowhere'} does not exist")
    # the same checks behind the command, called directly
    for kwargs, message in [
        ({"engine": "nope"}, "unknown engine 'nope'"),
        ({"static": tmp_path / "file.txt"}, "file.txt, line 1, as WKT"),
        ({"static": tmp_path / "none.wkt"}, "static occluders .*none.wkt does not exist"),
        ({"workers": 2, "scheduler": "tcp://127.0.0.1:1"}, "workers counts local processes"),
        ({"scheduler": "tcp://127.0.0.1:1", "scheduler_file": "s.json"}, "give one of"),
        ({"ego": "everyone"}, "ego_idx must be an int"),
        ({"sensor": "roof"}, r"unknown option\(s\) \['sensor'\]"),
    ]:
        with pytest.raises(ValueError, match=message):
            run_batch(MCAP, out, progress=False, **kwargs)
    with pytest.raises(ValueError, match=r"no recordings \(.mcap, .osi\) found"):
        run_batch(tmp_path, out, progress=False)
    assert not out.exists()


def test_unreadable_input_folder(tmp_path, monkeypatch) -> None:
    def walk(folder, onerror):
        onerror(PermissionError(13, "Permission denied", str(folder)))
        return iter(())

    monkeypatch.setattr(os, "walk", walk)
    with pytest.raises(ValueError, match=rf"cannot read input folder {tmp_path} \(Permission denied\)"):
        run_batch(tmp_path, tmp_path / "out", progress=False)


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root reads any folder")
def test_unreadable_input_folder_cli(tmp_path) -> None:
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0)
    try:
        assert_cli_error(batch_cli(locked, "-o", tmp_path / "out"), f"cannot read input folder {locked}")
    finally:
        locked.chmod(0o755)


def test_module_entry_point() -> None:
    run = subprocess.run([sys.executable, "-m", "omega_prime_visibility", "--help"], capture_output=True, text=True)
    assert run.returncode == 0 and "batch" in run.stdout and "run" in run.stdout


def test_readme_batch_examples(tmp_path) -> None:
    """The batch page of the docs (the README links to it): its first command and its Python example, run in a
    folder holding the bundled recording (as on a fresh clone)."""
    import re

    section = (REPO / "docs" / "batch.md").read_text()
    command = re.search(r"```bash\n(omega-prime-visibility batch [^#\n]*)", section).group(1).split()
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    shutil.copyfile(MCAP, tmp_path / "highway_merge.mcap")
    run = subprocess.run([str(SCRIPT), *command[1:], "--no-progress"], capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "1 recordings: 1 done" in run.stdout
    assert pl.read_parquet(tmp_path / "results" / "highway_merge.mcap.parquet").height == 1206
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        namespace: dict = {}
        exec(compile(code, "README.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
    # other options than the command's (engine): recomputed, not skipped
    assert namespace["summary"].select("result", "status", "rows").rows() == [
        ("highway_merge.mcap.parquet", "done", 1206)
    ]


def test_batch_in_3d(tmp_path) -> None:
    from omega_prime_visibility import get_visibility_df, run_batch

    copy = tmp_path / "in" / "highway_merge.mcap"
    copy.parent.mkdir()
    shutil.copyfile(MCAP, copy)
    summary = run_batch([copy], tmp_path / "out", ego=0, mode="3d", workers=1, progress=False)
    assert summary["status"].to_list() == ["done"]
    result = pl.read_parquet(tmp_path / "out" / summary["result"][0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        expected = get_visibility_df(copy, 0, mode="3d", progress=False)
    assert "can_see" in result.columns and result.equals(expected)
    # other options recompute: back in 2D
    again = run_batch([copy], tmp_path / "out", ego=0, workers=1, progress=False)
    assert again["status"].to_list() == ["done"]
    assert "can_see" not in pl.read_parquet(tmp_path / "out" / again["result"][0]).columns


def test_printed_summary_shows_failures_first(capsys) -> None:
    from omega_prime_visibility.batch.run import SUMMARY_SCHEMA
    from omega_prime_visibility.cli import print_summary

    # rows in input order: done, failed, interrupted, skipped, failed; shown: both failed (in input order), then
    # the interrupted one, then the rest in input order
    rows = [
        ("a", "done", 10),
        ("b", "failed", None),
        ("c", "interrupted", None),
        ("d", "skipped", 7),
        ("e", "failed", None),
    ]
    summary = pl.DataFrame(
        [
            {"recording": f"{n}.mcap", "result": f"{n}.mcap.parquet", "status": s, "rows": r, "seconds": 1.0}
            | {"error": "boom" if s == "failed" else None, "warnings": None}
            for n, s, r in rows
        ],
        schema=SUMMARY_SCHEMA,
    )
    print_summary(summary, Path("out") / SUMMARY)
    shown = [line for line in capsys.readouterr().out.splitlines() if ".mcap.parquet" in line]
    assert [line.split()[1].strip('"') for line in shown] == [f"{n}.mcap.parquet" for n in "bec" + "ad"]
    # a recording's warnings (stored in the summary) are printed with it, one line each, as run prints them
    noted = summary.with_columns(
        warnings=pl.when(pl.col("recording") == "a.mcap").then(pl.lit("the 3D result may be wrong | heights 0"))
    )
    print_summary(noted, Path("out") / SUMMARY)
    lines = capsys.readouterr().out.splitlines()
    assert [line for line in lines if line.startswith("warning:")] == [
        "warning: a.mcap: the 3D result may be wrong",
        "warning: a.mcap: heights 0",
    ]


@pytest.mark.parametrize(
    ("options", "beside"),
    [({}, []), ({"conflicts": True}, ["copy0.mcap.conflicts.parquet"])],
    ids=["streamed", "whole-table"],
)
def test_batch_result_and_summary_are_written_atomically(tmp_path, monkeypatch, options, beside) -> None:
    # A failure half-way through writing must leave the previous file under the final name with its old bytes,
    # and nothing else in the folder (no half-written file, no temporary left over): the result streamed chunk by
    # chunk into its file, and the whole table written at once (when conflicts need it at hand)
    (a,) = copies(tmp_path / "in", 1)
    out = tmp_path / "out"
    run_batch([a], out, ego=0, workers=1, progress=False, **options)
    result, summary, objects = out / "copy0.mcap.parquet", out / SUMMARY, out / "copy0.mcap.objects.parquet"
    old_result, old_summary = result.read_bytes(), summary.read_bytes()
    half = lambda path: path.write_bytes(b"PAR1 half")  # noqa: E731
    interrupted_writer(monkeypatch, pq, "ParquetWriter", result, old_result, half)  # (results are written by it)
    failed = run_batch([a], out, ego=0, engine="sweep", workers=1, progress=False, **options)  # new: recomputed
    assert failed.select("status", "error").row(0) == ("failed", "OSError: disk full")
    assert result.read_bytes() == old_result
    assert sorted(p.name for p in out.iterdir()) == sorted([result.name, objects.name, SUMMARY, *beside])
    monkeypatch.undo()
    old_summary = summary.read_bytes()
    interrupted_writer(monkeypatch, pl.DataFrame, "write_parquet", summary, old_summary, half)
    with pytest.raises(OSError, match="disk full"):
        run_batch([a], out, ego=0, workers=1, progress=False)
    assert summary.read_bytes() == old_summary
    assert sorted(p.name for p in out.iterdir()) == sorted([result.name, objects.name, SUMMARY, *beside])


def test_a_failed_recomputation_leaves_the_previous_result_with_its_own_objects(tmp_path, monkeypatch) -> None:
    # the objects beside a result are written once its table is computed, before it takes its name: an engine that
    # fails on the recomputation (new options, and the recording changed meanwhile: its objects moved) leaves the
    # previous result and the objects it was computed from
    from omega_prime_visibility.inputs import io
    from omega_prime_visibility.inputs.scene import as_polars
    from omega_prime_visibility.table import pipeline

    (a,) = copies(tmp_path / "in", 1)
    out = tmp_path / "out"
    run_batch([a], out, ego=0, workers=1, progress=False)
    result, objects = out / "copy0.mcap.parquet", out / "copy0.mcap.objects.parquet"
    before = result.read_bytes(), objects.read_bytes()
    read = io.read_recording

    def failing(*args):
        raise RuntimeError("engine failed")

    monkeypatch.setattr(io, "read_recording", lambda *args: as_polars(read(*args)).with_columns(pl.col("x") + 1.0))
    monkeypatch.setattr(pipeline, "run_chunk", failing)
    for options in ({}, {"conflicts": True}):  # streamed, and the whole table at hand
        failed = run_batch([a], out, ego=0, engine="sweep", workers=1, progress=False, **options)
        assert failed.select("status", "error").row(0) == ("failed", "RuntimeError: engine failed")
        assert (result.read_bytes(), objects.read_bytes()) == before
        assert sorted(p.name for p in out.iterdir()) == sorted([result.name, objects.name, SUMMARY])


def test_one_file_over_two_cores_is_joined_into_its_result(tmp_path) -> None:
    # a lone file's frames go over the cores: the workers' parts are joined into the one result, none left behind
    (a,) = copies(tmp_path / "in", 1)
    out = tmp_path / "out"
    summary = run_batch([a], out, ego="all", engine="sweep", workers=2, progress=False)
    assert summary["status"].to_list() == ["done"]
    result = out / "copy0.mcap.parquet"
    expected = get_visibility_df(read_recording(a), "all", engine="sweep", workers=1, progress=False)
    assert_frame_equal(pl.read_parquet(result), expected)
    assert OPTIONS_KEY in pq.read_schema(result).metadata
    assert sorted(p.name for p in out.iterdir()) == sorted([result.name, "copy0.mcap.objects.parquet", SUMMARY])


def test_batch_does_not_grow_a_tree_of_folders(tmp_path) -> None:
    # a mistyped output path: its parent does not exist, nothing is created; the folder itself may be new
    assert_cli_error(batch_cli(MCAP, "-o", tmp_path / "typo" / "out"), f"the folder {tmp_path / 'typo'} does not exist")
    assert not (tmp_path / "typo").exists()


def test_inputs_are_named_as_given_through_symbolic_links(tmp_path) -> None:
    # a link's failure names the link, not its target; two names of one file are computed once, and said so
    src, inputs = tmp_path / "src", tmp_path / "in"
    src.mkdir()
    inputs.mkdir()
    (src / "broken.mcap").write_bytes(b"not an MCAP file at all")
    (inputs / "bad_link.mcap").symlink_to(src / "broken.mcap")
    (a,) = copies(inputs, 1, prefix="a")
    (inputs / "b_link.mcap").symlink_to(a)
    with pytest.warns(BatchNotice, match=r"b_link\.mcap is the same file as .*a0\.mcap: computed once"):
        summary = run_batch(inputs, tmp_path / "out", ego=0, engine="sweep", workers=1, progress=False)
    rows = {Path(r).name: (s, e) for r, s, e in summary.select("recording", "status", "error").iter_rows()}
    assert set(rows) == {"a0.mcap", "bad_link.mcap"}
    status, error = rows["bad_link.mcap"]
    assert status == "failed" and "bad_link.mcap" in error and "broken.mcap" not in error
    assert summary.filter(pl.col("status") == "failed")["recording"][0] == str(inputs / "bad_link.mcap")


def test_a_folder_of_parts_is_no_batch_output(tmp_path) -> None:
    # run -o x.parquet wrote a folder of parts: batch must not add its results and summary to that table
    parts = tmp_path / "vis.parquet"
    get_visibility_df(MCAP, 0, engine="sweep", output=parts, progress=False)
    with pytest.raises(ValueError, match=r"holds the parquet parts of one table .* not batch results"):
        run_batch(MCAP, parts, ego=0, progress=False)
    assert pl.read_parquet(parts).height == 1206  # still one readable table
