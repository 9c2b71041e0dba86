"""Draws docs/threed.png: a scene where 2D and 3D disagree (a truck behind a low car), from above and from the
driver's eye. ``scripts/make_pictures.py`` (``make pictures``) runs it with the README's other pictures."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import polars as pl
from matplotlib.patches import Polygon

from omega_prime_visibility import get_visibility_df
from omega_prime_visibility.threed.boxes import corners

BOXES = {  # idx: (x, y, z, length, width, height, roll, pitch, yaw), name, colour
    0: ((0.0, 0.0, 0.75, 4.5, 1.8, 1.5, 0, 0, 0), "ego", "#1f77b4"),
    1: ((10.0, 0.3, 0.65, 4.2, 1.9, 1.3, 0, 0, 0), "low car", "#7f7f7f"),
    2: ((22.0, 0.0, 2.0, 10.0, 2.5, 4.0, 0, 0, 0), "truck", "#ff7f0e"),
}
FACES = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]


def table() -> pl.DataFrame:
    rows = np.array([b for b, _, _ in BOXES.values()])
    names = ("x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw")
    return pl.DataFrame(
        {"frame": [0] * len(rows), "total_nanos": [0] * len(rows), "idx": list(BOXES)}
        | {n: rows[:, k] for k, n in enumerate(names)}
    )


OUT = Path(__file__).resolve().parent.parent / "docs" / "threed.png"


def main(out: Path = OUT) -> None:
    df = table()
    flat = get_visibility_df(df, 0).filter(pl.col("idx") == 2)["visibility"].item()
    solid = get_visibility_df(df, 0, mode="3d", engine="silhouette3d").filter(pl.col("idx") == 2)
    fig, (top, eye) = plt.subplots(1, 2, figsize=(11, 3.6), gridspec_kw={"width_ratios": [1.25, 1]})
    for box, name, colour in BOXES.values():
        c = corners(np.array([box]))[0]
        top.add_patch(Polygon(c[[0, 4, 6, 2], :2], closed=True, fc=colour, ec="k", alpha=0.8))
        top.annotate(name, (box[0], box[1] + box[4] / 2 + 0.4), ha="center", fontsize=9)
    truck = corners(np.array([BOXES[2][0]]))[0][:, :2]
    for p in truck[[0, 2]]:  # the truck's angular extent from the eye, in 2D
        top.plot([0, p[0] * 1.05], [0, p[1] * 1.05], "k--", lw=0.8)
    top.set(xlim=(-4, 30), ylim=(-5, 5), aspect="equal", xlabel="x (m)", ylabel="y (m)")
    top.set_title(f"2D, from above: truck visibility {flat:.2f} (hidden)", fontsize=10)
    eye_point = np.array([0.0, 0.0, 1.25])
    for idx in (2, 1):  # far to near: the painter's algorithm is enough for these two boxes
        box, _, colour = BOXES[idx]
        c = corners(np.array([box]))[0] - eye_point
        for face in FACES:
            p = c[face]
            if np.dot(p.mean(axis=0) - c.mean(axis=0), p.mean(axis=0)) >= 0:
                continue  # faces turned away from the eye
            eye.add_patch(Polygon(np.column_stack([-p[:, 1] / p[:, 0], p[:, 2] / p[:, 0]]), fc=colour, ec="k"))
    eye.axhline(-1.25 / 200, color="0.6", lw=0.8)
    eye.set(xlim=(-0.3, 0.3), ylim=(-0.2, 0.18), aspect="equal", xticks=[], yticks=[])
    v, can = solid.select("visibility", "can_see").row(0)
    eye.set_title(f"3D, driver's eye 1.25 m up: truck visibility {v:.2f}, can_see {can}", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}: 2D {flat:.3f}, 3D {v:.3f}")


if __name__ == "__main__":
    main()
