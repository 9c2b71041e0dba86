"""Shared fixtures: scene builders and the real recordings (the folder named by $OMEGA_PRIME_VISIBILITY_DATA, by
default ../shared/data; skipped when absent)."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
import polars as pl
import pytest
from hypothesis import settings

# A failure prints the blob that replays it (@reproduce_failure). CI draws the same examples on every run, so a
# landing never depends on which random scenes were drawn; a developer's run draws new ones (and replays its
# failures from .hypothesis/).
settings.register_profile("dev", print_blob=True)
settings.register_profile("ci", print_blob=True, derandomize=True)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

REPO = Path(__file__).resolve().parent.parent
DATA_VARIABLE = "OMEGA_PRIME_VISIBILITY_DATA"
"""The environment variable naming the folder of real recordings (esmini traces with their maps, the upstream
``highway_merge.mcap``); by default ``../shared/data`` beside the repository."""
SHARED_DATA = Path(os.environ.get(DATA_VARIABLE) or REPO.parent / "shared" / "data")


def boxes_table(boxes: list[tuple[float, float, float, float, float]], frame: int = 0) -> pl.DataFrame:
    """A one-frame object table from ``(x, y, length, width, yaw)`` boxes; idx = position."""
    arr = np.asarray(boxes, dtype=float).reshape(-1, 5)
    return pl.DataFrame(
        {
            "frame": np.full(len(arr), frame, dtype=np.int64),
            "total_nanos": np.full(len(arr), frame * 100_000_000, dtype=np.int64),
            "idx": np.arange(len(arr), dtype=np.int64),
            "x": arr[:, 0],
            "y": arr[:, 1],
            "length": arr[:, 2],
            "width": arr[:, 3],
            "yaw": arr[:, 4],
        }
    )


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """The folder of real esmini recordings (:data:`DATA_VARIABLE`); tests using it are skipped where it is absent."""
    if not (SHARED_DATA / "highway_merge.mcap").exists():
        pytest.skip(f"real recordings not available at {SHARED_DATA} (set {DATA_VARIABLE} to their folder)")
    return SHARED_DATA


def scene_table(observer, objects, include_ego: bool) -> pl.DataFrame:
    """A one-frame table with a ``polygon`` column for a reference scene; the ego (idx 0) sits at ``observer``.

    With ``include_ego`` the scene's object 0 is the ego's outline; otherwise a 0.2 m square at the observer is
    added as idx 0. Scene object ``k`` gets idx ``k`` (with ego) or ``k + 1`` (without).
    """
    import shapely

    polys = (
        list(objects) if include_ego else [shapely.box(*(np.r_[observer, observer] + [-0.1, -0.1, 0.1, 0.1])), *objects]
    )
    centres = np.array([[p.centroid.x, p.centroid.y] for p in polys])
    centres[0] = observer
    return pl.DataFrame(
        {
            "frame": np.zeros(len(polys), dtype=np.int64),
            "total_nanos": np.zeros(len(polys), dtype=np.int64),
            "idx": np.arange(len(polys), dtype=np.int64),
            "x": centres[:, 0],
            "y": centres[:, 1],
            "polygon": pl.Series(polys, dtype=pl.Object),
        }
    )


def interrupted_writer(monkeypatch, module, name: str, target: Path, old: bytes, partial: Callable[..., None]):
    """Replace ``module.name`` (a writer) by one that writes part of its data with ``partial(path)``, checks that
    ``target`` still holds ``old`` (what a reader sees meanwhile), and raises."""

    def writer(*args, **kwargs):
        path = next(a for a in (*args, *kwargs.values()) if isinstance(a, str | os.PathLike))
        partial(Path(path))
        assert target.read_bytes() == old  # a reader during the write sees the previous result whole
        raise OSError("disk full")

    monkeypatch.setattr(module, name, writer)


@pytest.fixture(scope="session")
def widths_as_heights_mcap(tmp_path_factory) -> Path:
    """The bundled recording as omega-prime 0.3.7's writer leaves it without the scenario's workaround: every
    object's height equal to its width (what many MCAP files in the wild hold)."""
    import warnings

    import omega_prime

    path = tmp_path_factory.mktemp("widths") / "highway_merge.mcap"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        recording = omega_prime.Recording.from_file(REPO / "highway_merge.mcap")
        recording.to_mcap(path)
        written = omega_prime.Recording.from_file(path)._df
    assert (written["height"] == written["width"]).all(), "omega-prime's writer now keeps heights: drop this fixture"
    return path


def cap_directions(centre: np.ndarray, radius: float, eye: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` unit directions uniform over the cone from ``eye`` around the sphere (``centre``, ``radius``, metres)
    that a 3D Monte Carlo count shoots at a target."""
    axis = np.asarray(centre, dtype=float) - eye
    dist = np.linalg.norm(axis)
    cos_cap = np.cos(np.arcsin(min(1.0, radius / dist)))
    z = rng.uniform(cos_cap, 1, n)
    phi = rng.uniform(0, 2 * np.pi, n)
    s = np.sqrt(1 - z * z)
    a = axis / dist
    t = np.cross(a, [0.0, 0, 1])
    t /= np.linalg.norm(t)
    return (s * np.cos(phi))[:, None] * t + (s * np.sin(phi))[:, None] * np.cross(a, t) + z[:, None] * a
