"""Regenerate the README's pictures from the bundled recording: ``uv run python scripts/readme_figures.py``."""

from __future__ import annotations

import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import omega_prime

from omega_prime_visibility import get_visibility_df
from omega_prime_visibility.plot import plot_frame

REPO = Path(__file__).resolve().parent.parent


def main() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = omega_prime.Recording.from_file(str(REPO / "highway_merge.mcap"), compute_polygons=True)
    fig, ax = plt.subplots(figsize=(11, 4.2))
    plot_frame(r, 0, 30, target=2, ax=ax, view_range=70)
    fig.tight_layout()
    fig.savefig(REPO / "docs" / "frame.png", dpi=110)
    table = get_visibility_df(r, 0)
    fig, ax = plt.subplots(figsize=(11, 3.2))
    for (idx,), part in sorted(table.partition_by("idx", as_dict=True).items()):
        ax.plot(part["total_nanos"] / 1e9, part["visibility"], label=f"idx {idx}")
    ax.set(xlabel="time [s]", ylabel="visibility from ego 0", ylim=(-0.05, 1.05))
    ax.legend(ncol=6, fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(REPO / "docs" / "timeline.png", dpi=110)


if __name__ == "__main__":
    main()
