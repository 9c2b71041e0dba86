"""The tutorial notebook runs top to bottom."""

from __future__ import annotations

import nbformat
from conftest import REPO
from nbclient import NotebookClient


def test_tutorial_runs_top_to_bottom() -> None:
    nb = nbformat.read(REPO / "tutorial.ipynb", as_version=4)
    NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(REPO)}}).execute()
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    assert any("image/png" in o.get("data", {}) for o in outputs)
