"""``get_visibility_df(..., output=)``: the path is checked before computing and the file appears only when complete."""

from __future__ import annotations

import os
from pathlib import Path

import polars as pl
import pytest
from conftest import boxes_table

from omega_prime_visibility import get_visibility_df, pipeline
from omega_prime_visibility.output import check_output_path

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


@pytest.mark.parametrize(
    ("name", "problem"),
    [
        ("missing/vis.parquet", "missing does not exist"),
        ("notes.txt/vis.parquet", "notes.txt is not a folder"),
        ("taken.parquet", "it is a directory"),
        ("vis.csv", "must end in .parquet; output= streams parquet: to write CSV, call write_csv"),
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


def test_output_leaves_only_the_final_file(tmp_path, engine_calls) -> None:
    lazy = get_visibility_df(SCENE, 0, workers=1, chunk_frames=2, output=tmp_path / "vis.parquet")
    assert isinstance(lazy, pl.LazyFrame)
    assert lazy.collect().equals(get_visibility_df(SCENE, 0, workers=1))
    assert len(engine_calls) == 3 + 1  # three chunks, then one in-memory run
    assert [p.name for p in tmp_path.iterdir()] == ["vis.parquet"]


def test_failed_run_leaves_no_partial_file(tmp_path, monkeypatch) -> None:
    run_chunk = pipeline.run_chunk
    calls: list[int] = []

    def failing_second(*args):
        calls.append(1)
        if len(calls) == 2:
            raise RuntimeError("engine failed")
        return run_chunk(*args)

    monkeypatch.setattr(pipeline, "run_chunk", failing_second)
    target = tmp_path / "vis.parquet"
    target.write_bytes(b"previous result")
    with pytest.raises(RuntimeError, match="engine failed"):
        get_visibility_df(SCENE, 0, workers=1, chunk_frames=2, output=target)
    assert calls == [1, 1]  # the first chunk was written (to the temporary file) before the failure
    assert [p.name for p in tmp_path.iterdir()] == ["vis.parquet"]
    assert target.read_bytes() == b"previous result"


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
