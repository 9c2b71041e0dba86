"""Every import path the README, the tutorial and the published 0.1.0 document keeps working after the package's
layout moved to stages (inputs, geometry, engines, table, analysis, front ends)."""

from __future__ import annotations

import importlib
import json
import re

import pytest
from conftest import REPO

TOP_LEVEL = [
    "ENGINES",
    "ENGINES_3D",
    "SCHEMA",
    "Observation",
    "Reason",
    "Sensor",
    "Viewpoint",
    "VisibilityInputWarning",
    "animate",
    "get_visibility_df",
    "get_visibility_df_for_frame",
    "metrics",
    "plot_frame",
    "run_batch",
    "save_timeline",
    "seen_by_any",
    "timeline_chart",
    "visibility",
    "visible_area",
    "visible_area_over_time",
    "visible_intervals",
    "write_report",
]
MODULES = {
    "omega_prime_visibility.sensors": ["Sensor", "roof", "typical", "read_sensors", "resolve_sensors", "LAYOUTS"],
    "omega_prime_visibility.table": ["SCHEMA", "STATUSES", "SENSOR_SCHEMA", "LIST_COLUMNS"],
    "omega_prime_visibility.cli": ["main"],
    "omega_prime_visibility.metric": ["visibility", "metrics"],
    "omega_prime_visibility.batch": ["run_batch", "FileOptions", "SUMMARY_NAME"],
    "omega_prime_visibility.plot": ["plot_frame", "animate", "write_report", "save_timeline", "timeline_chart"],
    "omega_prime_visibility.threed.mapobjects": ["read_map_objects"],
    "omega_prime_visibility.engines": ["ENGINES", "ENGINES_3D", "get_engine", "Observation", "Viewpoint"],
}


@pytest.mark.parametrize("name", TOP_LEVEL)
def test_every_public_name_imports_from_the_package(name: str) -> None:
    package = importlib.import_module("omega_prime_visibility")
    assert name in package.__all__
    assert getattr(package, name) is not None


@pytest.mark.parametrize("module", sorted(MODULES))
def test_documented_module_paths_keep_their_names(module: str) -> None:
    imported = importlib.import_module(module)
    for name in MODULES[module]:
        assert hasattr(imported, name), f"{module}.{name}"


def resolve(path: str) -> object:
    """A dotted path named in the docs: a module, or an object in one (as the API reference names them)."""
    try:
        return importlib.import_module(path)
    except ModuleNotFoundError:
        module, name = path.rsplit(".", 1)
        return getattr(importlib.import_module(module), name)


def test_every_import_in_the_readme_the_docs_and_the_tutorial_resolves() -> None:
    texts = [(REPO / "README.md").read_text()] + [page.read_text() for page in sorted((REPO / "docs").glob("*.md"))]
    cells = json.loads((REPO / "tutorial.ipynb").read_text())["cells"]
    texts += ["".join(cell["source"]) for cell in cells if cell["cell_type"] == "code"]
    found = 0
    for text in texts:
        for module, names in re.findall(r"from (omega_prime_visibility[\w.]*) import (\([^)]*\)|[\w, ]+)", text):
            imported = importlib.import_module(module)
            names = re.sub(r"#[^\n]*", "", names).strip("()")
            for name in (n.strip().split(" as ")[0] for n in names.replace("\n", ",").split(",")):
                if name:
                    assert hasattr(imported, name), f"{module}.{name}"
                    found += 1
        for path in re.findall(r"\b(omega_prime_visibility(?:\.\w+)+)\b", text):
            if path.rsplit(".", 1)[-1] not in ("options",):  # (a parquet metadata key, not a module)
                resolve(path)
    assert found >= 10  # the README's and the tutorial's imports were really read


def test_the_packaging_entry_points_resolve() -> None:
    text = (REPO / "pyproject.toml").read_text()
    targets = re.findall(r'= "(omega_prime_visibility[\w.]*):(\w+)"', text)
    assert len(targets) >= 2
    for module, name in targets:
        assert callable(getattr(importlib.import_module(module), name))
