"""Pictures of one frame: objects coloured by visibility, the visibility polygon, occluders of a target."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import polars as pl
import shapely

from .engines.visilibity import VisiLibityEngine
from .pipeline import observer_rows, run_chunk, viewpoints
from .scene import load_objects
from .statics import load_static_occluders
from .table import to_polars


def plot_frame(
    df: Any,
    ego_idx: int,
    frame: int,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    target: int | None = None,
    ax: Any = None,
    view_range: float | None = 80.0,
    cmap: str = "RdYlGn",
) -> Any:
    """Draw one frame seen from ``ego_idx``; return the matplotlib ``Axes``.

    Objects are filled by their visibility (colour bar 0..1), the ego is drawn in blue, the visible region
    (VisiLibity's visibility polygon) is shaded, static occluders are hatched, and, when ``target`` is given, its
    occluders are outlined in black. ``view_range`` (metres around the ego) limits the axes; None shows all.
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize
    from matplotlib.patches import Polygon as PolygonPatch

    objects = load_objects(df)
    k = int(np.searchsorted(objects.frame[objects.frame_starts[:-1]], frame))
    if k >= objects.n_frames or objects.frame[objects.frame_starts[k]] != frame:
        raise ValueError(f"frame {frame} does not occur in the table")
    fo = objects.frame_objects(k)
    if ego_idx not in fo.idx:
        raise ValueError(f"ego idx {ego_idx} is not present in frame {frame}")
    statics = load_static_occluders(static_occluder_polys)
    # the same per-frame pipeline as get_visibility_df, on the one frame already loaded
    columns, _ = run_chunk(objects.frame_range(k, k + 1), statics, np.array([ego_idx]), "visilibity")
    table = to_polars(columns, with_ego=False)
    vis_of = dict(zip(table["idx"].to_list(), table["visibility"].to_list(), strict=True))
    (view,) = viewpoints(fo, observer_rows(fo, np.array([ego_idx])), statics)
    observer = view.position
    engine = VisiLibityEngine(statics)
    engine.box_margin = 2 * (view_range or 100.0)
    region = engine.visible_region(fo, view)

    if ax is None:
        _, ax = plt.subplots(figsize=(10, 5))
    colours = plt.get_cmap(cmap)
    norm = Normalize(0.0, 1.0)
    ax.add_patch(PolygonPatch(np.asarray(region.exterior.coords), facecolor="#ffe680", alpha=0.35, lw=0, zorder=0))
    for g in statics.geometries:
        for part in getattr(g, "geoms", [g]):
            if isinstance(part, shapely.Polygon):
                ax.add_patch(
                    PolygonPatch(np.asarray(part.exterior.coords), facecolor="#bbbbbb", hatch="///", edgecolor="#555")
                )
            else:
                ax.plot(*np.asarray(part.coords).T, color="#555", lw=2.5, zorder=1)
    occluders = set()
    if target is not None:
        row = table.filter(pl.col("idx") == target)
        occluders = set(row["occluder_idxs"].explode().drop_nulls().to_list()) if row.height else set()
    for i, idx in enumerate(fo.idx.tolist()):
        ring = fo.rings.ring(i)
        if idx == ego_idx:
            face, edge, lw = "#1f5fbf", "#0b2f66", 1.0
        else:
            face, edge, lw = colours(norm(vis_of.get(idx, 1.0))), "#333", 0.6
        if idx in occluders:
            edge, lw = "black", 2.5
        ax.add_patch(PolygonPatch(ring, facecolor=face, edgecolor=edge, lw=lw, zorder=2))
        cx, cy = fo.position[i]
        ax.annotate(str(idx), (cx, cy), ha="center", va="center", fontsize=7, zorder=3)
    ax.plot(*observer, marker="*", color="white", mec="black", ms=10, zorder=4)
    mappable = plt.cm.ScalarMappable(norm=norm, cmap=colours)
    ax.figure.colorbar(mappable, ax=ax, label="visibility", fraction=0.03, pad=0.01)
    ax.set_aspect("equal")
    if view_range is not None:
        ax.set_xlim(observer[0] - view_range, observer[0] + view_range)
        ax.set_ylim(observer[1] - view_range / 3, observer[1] + view_range / 3)
    else:
        ax.autoscale_view()
    ax.set(xlabel="x [m]", ylabel="y [m]", title=f"frame {frame}, seen from idx {ego_idx}")
    return ax
