"""The README's example runs as written."""

from __future__ import annotations

import os
import re
import warnings

import polars as pl
import pytest
from conftest import REPO

from omega_prime_visibility import get_visibility_df

COLUMNS = ("idx", "occluder_idxs", "static_occluder_idxs", "visibility")


def test_readme_example_runs() -> None:
    text = (REPO / "README.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    cwd = os.getcwd()
    os.chdir(REPO)
    try:
        namespace: dict = {}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            exec(compile(code, "README.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
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
