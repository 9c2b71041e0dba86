"""``get_visibility_df(..., output=)``: the path is checked before computing, workers write parquet parts of one
dataset, and the result appears under its name only when complete (also when the run is killed)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import polars as pl
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from conftest import REPO, boxes_table

from omega_prime_visibility import Query, get_visibility_df
from omega_prime_visibility.query import resolve
from omega_prime_visibility.table import pipeline
from omega_prime_visibility.table.compute import compute
from omega_prime_visibility.table.output import (
    PartWriter,
    atomic_directory,
    atomic_write,
    check_output_path,
    is_dataset,
    parquet_options,
)

SCENE = pl.concat([boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)], f) for f in range(6)])


@pytest.fixture
def engine_calls(monkeypatch) -> list[int]:
    """Counts chunks computed (in this process: workers=1)."""
    calls: list[int] = []
    run_chunk = pipeline.run_chunk

    def counting(*args):
        calls.append(1)
        return run_chunk(*args)

    monkeypatch.setattr(pipeline, "run_chunk", counting)
    return calls


def fail_second_chunk(monkeypatch) -> list[int]:
    """Make the engine fail on the second chunk computed in this process (and forked from it); the calls so far."""
    run_chunk = pipeline.run_chunk
    calls: list[int] = []

    def failing_second(*args):
        calls.append(1)
        if len(calls) == 2:
            raise RuntimeError("engine failed")
        return run_chunk(*args)

    monkeypatch.setattr(pipeline, "run_chunk", failing_second)
    return calls


@pytest.mark.parametrize(
    ("name", "problem"),
    [
        ("missing/vis.parquet", "missing does not exist"),
        ("notes.txt/vis.parquet", "notes.txt is not a folder"),
        ("taken.parquet", "it is a directory (and not a parquet dataset written here)"),
        ("vis.csv", "must end in .parquet; output= streams parquet: to write CSV, call omega_prime_visibility.write_"),
        ("vis.txt", "must end in .parquet"),
        ("vis", "must end in .parquet"),
    ],
)
def test_bad_output_fails_before_computing(tmp_path, engine_calls, name: str, problem: str) -> None:
    (tmp_path / "notes.txt").write_text("a file")
    (tmp_path / "taken.parquet").mkdir()
    before = set(tmp_path.rglob("*"))
    target = tmp_path / name
    with pytest.raises(ValueError, match="cannot write") as err:
        get_visibility_df(SCENE, 0, workers=1, output=target)
    assert str(target) in str(err.value) and problem in str(err.value)
    assert engine_calls == []
    assert set(tmp_path.rglob("*")) == before


def test_unwritable_place() -> None:
    with pytest.raises(ValueError, match=r"cannot write /proc/vis\.parquet: cannot create files in /proc"):
        check_output_path("/proc/vis.parquet")


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root may write anywhere")
def test_read_only_file(tmp_path) -> None:
    target = tmp_path / "vis.parquet"
    target.write_text("old")
    target.chmod(0o444)
    with pytest.raises(ValueError, match="exists and is read-only"):
        check_output_path(target)


def test_check_output_path_accepts_given_suffixes(tmp_path) -> None:
    assert check_output_path(tmp_path / "t.csv", (".parquet", ".csv")) == tmp_path / "t.csv"
    assert check_output_path(str(tmp_path / "t.parquet")) == tmp_path / "t.parquet"
    assert list(tmp_path.iterdir()) == []  # the writability probe is removed


def test_output_leaves_only_the_final_dataset(tmp_path, engine_calls) -> None:
    lazy = get_visibility_df(SCENE, 0, workers=1, chunk_frames=2, output=tmp_path / "vis.parquet")
    assert isinstance(lazy, pl.LazyFrame)
    assert lazy.collect().equals(get_visibility_df(SCENE, 0, workers=1))
    assert len(engine_calls) == 3 + 1  # three chunks, then one in-memory run
    assert [p.name for p in tmp_path.iterdir()] == ["vis.parquet"]
    assert sorted(p.name for p in (tmp_path / "vis.parquet").iterdir()) == [f"part-00000{k}.parquet" for k in range(3)]


def test_workers_write_parts_read_as_one_table_in_order(tmp_path) -> None:
    boxes = [[(0, 0, 4, 2, 0), (10 + 0.5 * f, 0, 4, 4, 0), (20, 0, 4, 2, 0)] for f in range(9)]
    frames = pl.concat([boxes_table(b, f) for f, b in enumerate(boxes)])
    target = tmp_path / "vis.parquet"
    lazy = get_visibility_df(frames, "all", workers=2, chunk_frames=2, output=target, engine="sweep")
    assert lazy.collect().equals(get_visibility_df(frames, "all", workers=1, engine="sweep"))
    assert len(list(target.iterdir())) == 6  # 5 chunks of at most 2 frames, balanced over 2 workers: 6 of 1-2
    assert pl.read_parquet(target).equals(lazy.collect())


def test_an_earlier_result_is_replaced_but_a_foreign_directory_is_not(tmp_path) -> None:
    target = tmp_path / "vis.parquet"
    get_visibility_df(SCENE, 0, workers=1, chunk_frames=2, output=target)
    assert is_dataset(target) and len(list(target.iterdir())) == 3
    lazy = get_visibility_df(SCENE, 0, workers=1, chunk_frames=4, output=target)  # a dataset: replaced whole
    assert len(list(target.iterdir())) == 2 and lazy.collect().equals(get_visibility_df(SCENE, 0))
    assert [p.name for p in tmp_path.iterdir()] == ["vis.parquet"]
    (target / "notes.txt").write_text("the user's own file")
    with pytest.raises(ValueError, match="it is a directory"):
        get_visibility_df(SCENE, 0, output=target)
    assert (target / "notes.txt").exists()


def test_atomic_directory_removes_its_work_on_error(tmp_path) -> None:
    with pytest.raises(RuntimeError), atomic_directory(tmp_path / "t.parquet") as temp:
        (temp / "part-000000.parquet").write_bytes(b"half")
        raise RuntimeError
    assert list(tmp_path.iterdir()) == []


def test_part_writer_turns_codes_into_labels(tmp_path) -> None:
    schema = pa.schema(
        [
            ("n", pa.int64()),
            ("lists", pa.large_list(pa.int64())),
            ("name", pa.large_string()),
            ("kind", pa.dictionary(pa.uint32(), pa.large_string())),
        ]
    )
    writer = PartWriter(tmp_path, schema, {"name": ["a", "b"], "kind": ["x", "y", "z"]})
    columns = {
        "n": np.array([5, 6, 7]),
        "lists": (np.array([2, 0, 1]), np.array([1, 2, 3])),
        "name": np.array([1, 1, 0]),
        "kind": np.array([2, 0, 2]),
    }
    assert writer(3, columns) == 3 and writer(4, None) == 0
    table = pl.read_parquet(tmp_path / "part-000003.parquet")
    assert table["lists"].to_list() == [[1, 2], [], [3]]
    assert table["name"].to_list() == ["b", "b", "a"] and table["kind"].cast(pl.String).to_list() == ["z", "x", "z"]
    assert [p.name for p in tmp_path.iterdir()] == ["part-000003.parquet"]


KILLED_RUN = """
import sys, polars as pl
from omega_prime_visibility import get_visibility_df
boxes = [(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)]
rows = [dict(frame=f, total_nanos=f, idx=i, x=x + 0.01 * f, y=y, length=l, width=w, yaw=a)
        for f in range(100_000) for i, (x, y, l, w, a) in enumerate(boxes)]
get_visibility_df(pl.DataFrame(rows), 0, engine="sweep", workers=1, chunk_frames=50, output=sys.argv[1])
"""


@pytest.mark.skipif(os.name != "posix", reason="SIGKILL")
@pytest.mark.parametrize("previous", [False, True])
def test_a_killed_run_leaves_nothing_that_reads_as_complete(tmp_path, previous: bool) -> None:
    target = tmp_path / "vis.parquet"
    if previous:
        get_visibility_df(SCENE, 0, output=target)
    before = pl.read_parquet(target) if previous else None
    proc = subprocess.Popen([sys.executable, "-c", KILLED_RUN, str(target)], cwd=REPO)
    try:
        deadline = time.monotonic() + 60
        while not list(tmp_path.glob(".vis.parquet.*.tmp/part-000002.parquet")):  # a few parts are written
            assert proc.poll() is None and time.monotonic() < deadline, "the run ended before it could be killed"
            time.sleep(0.05)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    if previous:
        assert pl.scan_parquet(target).collect().equals(before)
    else:
        assert not target.exists()
        with pytest.raises(Exception):  # noqa: B017 (polars raises one of several types)
            pl.scan_parquet(target).collect()


@pytest.mark.parametrize("workers", [1, 2], ids=["in order into the file", "parts joined"])
@pytest.mark.parametrize("observers", [0, "all"])
def test_one_file_holds_the_table_and_its_metadata(tmp_path, engine_calls, workers: int, observers) -> None:
    """``compute(output_file=)`` (batch's results): one parquet file, the table as in memory, row group by chunk
    in order, the metadata in its schema, nothing else left in the folder; written as results are."""
    boxes = [[(0, 0, 4, 2, 0), (10 + 0.5 * f, 0, 4, 4, 0), (20, 0, 4, 2, 0), (30, 1, 4, 2, 0.3)] for f in range(9)]
    frames = pl.concat([boxes_table(b, f) for f, b in enumerate(boxes)])
    question = Query(observers=observers, engine="sweep")
    target = tmp_path / "result.parquet"
    lazy = compute(resolve(question, frames), workers=workers, chunk_frames=2, output_file=target,
                   metadata={b"key": b"value"})  # fmt: skip
    expected = get_visibility_df(frames, query=question, workers=1)
    assert lazy.collect().equals(expected) and pl.read_parquet(target).equals(expected)
    assert [p.name for p in tmp_path.iterdir()] == ["result.parquet"]
    stored = pq.ParquetFile(target)
    assert stored.schema_arrow.metadata[b"key"] == b"value"
    assert stored.metadata.num_row_groups == (5 if workers == 1 else 6)  # chunks of at most 2 frames (balanced)
    column = {stored.metadata.row_group(0).column(i).path_in_schema: i for i in range(stored.metadata.num_columns)}
    chunk = stored.metadata.row_group(0)
    assert chunk.column(column["visibility"]).compression == "ZSTD"
    assert "RLE_DICTIONARY" in chunk.column(column["occluder_idxs.list.element"]).encodings
    assert "RLE_DICTIONARY" not in chunk.column(column["visibility"]).encodings
    assert len(engine_calls) == (5 if workers == 1 else 0) + 1  # (the workers' chunks run elsewhere)


def test_one_file_of_no_rows_and_a_failed_one(tmp_path, monkeypatch) -> None:
    # output_file is the caller's (batch: a temporary name it renames when complete): an empty result still has the
    # schema; a failing engine, with one worker or two, leaves the previous file under the final name and nothing else
    target = tmp_path / "result.parquet"
    lonely = compute(resolve(Query(observers=0), boxes_table([(0, 0, 4, 2, 0)])), workers=1, output_file=target)
    assert lonely.collect().height == 0 and "visibility" in pl.read_parquet_schema(target)
    previous = target.read_bytes()
    calls = fail_second_chunk(monkeypatch)
    for workers in (1, 2):
        calls.clear()
        with pytest.raises(RuntimeError, match="engine failed"), atomic_write(target) as temp:
            compute(resolve(Query(observers=0), SCENE), workers=workers, chunk_frames=2, output_file=temp)
        assert [p.name for p in tmp_path.iterdir()] == ["result.parquet"] and target.read_bytes() == previous
    with pytest.raises(ValueError, match="not both"):
        compute(resolve(Query(observers=0), SCENE), output=tmp_path / "d.parquet", output_file=target)


def test_parquet_options_name_every_stored_column(tmp_path) -> None:
    # use_dictionary names the stored columns by their paths (a list's values are "name.list.element"): every one
    # but the floating-point ones, for the widest table (sensors: labels, counts, in_view)
    schema = get_visibility_df(SCENE, 0, sensors="typical").to_arrow().schema
    options = parquet_options(schema)
    path = tmp_path / "t.parquet"
    pq.write_table(schema.empty_table(), path, **options)
    stored = pq.ParquetFile(path).schema
    paths = {stored.column(i).path: stored.column(i).physical_type for i in range(len(stored))}
    assert set(options["use_dictionary"]) == {p for p, kind in paths.items() if kind not in ("DOUBLE", "FLOAT")}


def test_failed_run_leaves_no_partial_file(tmp_path, monkeypatch) -> None:
    target = tmp_path / "vis.parquet"
    get_visibility_df(SCENE, 0, workers=1, chunk_frames=4, output=target)  # the previous result: two parts
    previous = {p.name: p.read_bytes() for p in target.iterdir()}
    calls = fail_second_chunk(monkeypatch)
    with pytest.raises(RuntimeError, match="engine failed"):
        get_visibility_df(SCENE, 0, workers=1, chunk_frames=2, output=target)
    assert calls == [1, 1]  # the first chunk was written (to the temporary directory) before the failure
    assert [p.name for p in tmp_path.iterdir()] == ["vis.parquet"]
    assert {p.name: p.read_bytes() for p in target.iterdir()} == previous


def test_empty_result_is_written_too(tmp_path) -> None:
    # the ego alone: no targets, but the file must exist with the schema
    lazy = get_visibility_df(boxes_table([(0, 0, 4, 2, 0)]), 0, output=tmp_path / "vis.parquet")
    assert lazy.collect().height == 0
    assert "visibility" in lazy.collect_schema().names()
    assert [p.name for p in tmp_path.iterdir()] == ["vis.parquet"]


def test_relative_output_path(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    get_visibility_df(SCENE, 0, output="vis.parquet").collect()
    assert sorted(p.name for p in Path(".").iterdir()) == ["vis.parquet"]


def test_an_interrupted_write_keeps_the_previous_dataset_readable(tmp_path, monkeypatch) -> None:
    # A first run leaves a dataset of 3 parts (6 frames in chunks of 2). A second run whose parquet writer writes
    # half a part and fails must leave those 3 parts, byte for byte, and nothing else in the folder; while it
    # writes, a reader of the final name reads the first run's table.
    from omega_prime_visibility.table import output

    target = tmp_path / "vis.parquet"
    first = get_visibility_df(SCENE, 0, workers=1, chunk_frames=2, output=target).collect()
    old = {p.name: p.read_bytes() for p in target.iterdir()}
    assert len(old) == 3
    seen: list[int] = []

    def half_then_fail(table, where, *args, **kwargs):
        Path(where).write_bytes(b"PAR1 half a part")
        assert {p.name: p.read_bytes() for p in target.iterdir()} == old
        assert pl.read_parquet(target).equals(first)
        seen.append(1)
        raise OSError("disk full")

    monkeypatch.setattr(output.pq, "write_table", half_then_fail)
    with pytest.raises(OSError, match="disk full"):
        get_visibility_df(SCENE, 0, workers=1, chunk_frames=2, output=target, engine="sweep")
    assert seen == [1]
    assert [p.name for p in tmp_path.iterdir()] == ["vis.parquet"]
    assert {p.name: p.read_bytes() for p in target.iterdir()} == old


def test_atomic_write_keeps_the_previous_file_until_the_new_one_is_complete(tmp_path) -> None:
    # the unit every file writer here goes through (CSV from the CLI, batch results and summary, pictures, reports)
    target = tmp_path / "t.csv"
    target.write_bytes(b"old")
    with pytest.raises(OSError, match="disk full"), atomic_write(target) as temp:
        temp.write_bytes(b"ne")
        assert target.read_bytes() == b"old"  # a reader meanwhile
        raise OSError("disk full")
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"] and target.read_bytes() == b"old"
    with atomic_write(target) as temp:
        temp.write_bytes(b"new")
        assert target.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"] and target.read_bytes() == b"new"


def test_write_csv_as_the_advice_says(tmp_path) -> None:
    # the advice given when output= ends in .csv works: one file, the occluder lists as idx joined by spaces, the
    # numbers as in the table; a table with static occluders and statuses too
    import shapely

    from omega_prime_visibility import write_csv

    boxes = [(0, 0, 1, 1, 0), (10, 0, 2, 2, 0), (20, 0.5, 2, 2, 0), (30, 0, 2, 2, 0)]
    table = get_visibility_df(boxes_table(boxes), 0, [shapely.box(25, -3, 26, -0.5)])
    assert write_csv(table, tmp_path / "vis.csv") == tmp_path / "vis.csv"
    assert [p.name for p in tmp_path.iterdir()] == ["vis.csv"]
    back = pl.read_csv(tmp_path / "vis.csv")
    assert back["visibility"].to_list() == table["visibility"].to_list()
    joined = [" ".join(map(str, row)) for row in table["occluder_idxs"].to_list()]
    assert back["occluder_idxs"].fill_null("").cast(pl.String).to_list() == joined
    assert any(" " in j for j in joined) and any(table["static_occluder_idxs"].list.len() > 0)
    with pytest.raises(ValueError, match=r"must end in \.csv"):
        write_csv(table, tmp_path / "vis.parquet")


def test_a_single_file_under_the_output_name_is_refused(tmp_path, engine_calls) -> None:
    # output= writes a folder of parts: a single parquet file already there (batch's, another tool's) is kept and
    # the call refused before computing, instead of being silently replaced by a folder
    target = tmp_path / "vis.parquet"
    pl.DataFrame({"a": [1]}).write_parquet(target)
    before = target.read_bytes()
    with pytest.raises(ValueError, match=r"vis\.parquet: it is a single file, and the output is a folder of parquet"):
        get_visibility_df(SCENE, 0, workers=1, output=target)
    assert engine_calls == [] and target.read_bytes() == before
    link = tmp_path / "link.parquet"
    link.symlink_to(target)
    with pytest.raises(ValueError, match="it is a single file"):
        get_visibility_df(SCENE, 0, workers=1, output=link)
    assert link.is_symlink() and target.read_bytes() == before
