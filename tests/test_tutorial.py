"""The tutorial notebook runs top to bottom, and shows what it says."""

from __future__ import annotations

import re

import nbformat
from conftest import REPO
from nbclient import NotebookClient


def test_tutorial_runs_top_to_bottom() -> None:
    nb = nbformat.read(REPO / "tutorial.ipynb", as_version=4)
    NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(REPO)}}).execute()
    code = [cell for cell in nb.cells if cell.cell_type == "code"]
    outputs = [o for cell in code for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    assert any("image/png" in o.get("data", {}) for o in outputs)

    def text_of(prefix: str) -> str:
        cell = next(c for c in code if c.source.startswith(prefix))
        return "\n".join(o.get("text", "") + o.get("data", {}).get("text/plain", "") for o in cell.outputs)

    # the Metric's table has the 1206 rows of 201 frames x 6 targets, in the table's 6 columns
    assert "(1206, 6)" in text_of("manager = ")
    # the two engines agree: the largest visibility difference printed is below 1e-6
    difference = float(re.findall(r"[0-9.e-]+", text_of("import time").splitlines()[-1])[-1])
    assert difference < 1e-6
    # who sees whom: observers and targets in ascending order
    header = text_of("everyone = ").splitlines()
    columns = next(line for line in header if "idx_ego" in line)
    assert re.findall(r"\b\d\b", columns) == ["0", "1", "2", "3", "4", "5", "6"]
