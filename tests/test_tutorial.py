"""The tutorial notebook: saved with its outputs, public API only, and it runs top to bottom showing what it says."""

from __future__ import annotations

import re

import nbformat
from conftest import REPO
from nbclient import NotebookClient

NOTEBOOK = REPO / "tutorial.ipynb"
COMPILING = "omega-prime-visibility: compiling the "  # the first run's notice (omega_prime_visibility._compiled)


def code_cells(nb) -> list:
    return [cell for cell in nb.cells if cell.cell_type == "code"]


def test_tutorial_is_saved_with_its_outputs_and_uses_public_api_only() -> None:
    nb = nbformat.read(NOTEBOOK, as_version=4)
    code = code_cells(nb)
    # readable on a code host without running it: every cell but the warnings filter shows something
    assert sum(1 for cell in code if cell.outputs) >= len(code) - 1
    kinds = {m for cell in code for o in cell.outputs for m in o.get("data", {})}
    assert {"image/png", "image/gif", "text/html"} <= kinds
    source = "\n".join(cell.source for cell in code)
    assert "._" not in source  # no private attributes such as Recording._df
    assert not re.search(r"omega_prime_visibility\.\w+\.", source)  # nothing reached inside the package's modules
    headings = [line for cell in nb.cells if cell.cell_type == "markdown" for line in cell.source.splitlines()]
    assert "## Sensors" in headings  # the place the sensor model's section goes


def test_tutorial_runs_top_to_bottom() -> None:
    nb = nbformat.read(NOTEBOOK, as_version=4)
    NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(REPO)}}).execute()
    code = code_cells(nb)
    outputs = [o for cell in code for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    # no warnings, no progress bars (only the one-time notice that an engine's kernels are being compiled)
    said = [o.text for o in outputs if o.get("name") == "stderr"]
    assert not [line for text in said for line in text.splitlines() if COMPILING not in line], said
    assert sum("image/png" in o.get("data", {}) for o in outputs) == 4  # frame, timeline, sensors, 3D
    assert sum("image/gif" in o.get("data", {}) for o in outputs) == 1  # the animation

    def text_of(prefix: str) -> str:
        cell = next(c for c in code if c.source.startswith(prefix))
        return "\n".join(o.get("text", "") + o.get("data", {}).get("text/plain", "") for o in cell.outputs)

    # the Metric's table has the 1206 rows of 201 frames x 6 targets, in the table's 6 columns
    assert "(1206, 6)" in text_of("manager = ")
    # the two engines agree: the largest visibility difference printed is below 1e-6
    difference = float(re.findall(r"[0-9.e-]+", text_of("import time").splitlines()[-1])[-1])
    assert difference < 1e-6
    # who sees whom: observers and targets in ascending order
    lines = text_of("everyone = ").splitlines()
    header = next(line for line in lines if "idx_ego" in line)
    assert re.findall(r"\b\d\b", header) == ["0", "1", "2", "3", "4", "5", "6"]
    observers = [int(m.group(1)) for line in lines if (m := re.match(r"│ (\d) ", line))]
    assert observers == [0, 1, 2, 3, 4, 5, 6]
    # the command line wrote the same table
    assert text_of("import subprocess").split() == ["wrote", "1206", "rows", "to", "out/visibility.parquet", "True"]
    # sensors: the status column, the merging car noticed at 5.0 s, and the seen area of frame 30
    assert "out_of_range" in text_of("from omega_prime_visibility import seen_by_any")
    intervals = text_of("best = seen_by_any")
    assert re.search(r"│ 2\s+┆ 45\s+┆ 200\s+┆ 15.5\s+┆ 5000000000", intervals)
    assert "frame 30: the sensors see 17,771 m²" in text_of("seen = visible_area")
    # 3D: the truck hidden in 2D is seen over the low car from the driver's eye
    three_d = text_of("boxes = ")
    assert re.search(r"│ 2\s+┆ 0.0\s+┆ 0.65\d*\s+┆ true", three_d)
