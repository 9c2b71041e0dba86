"""What a camera sees: its image plane at its resolution, each target's visible pixels in its visibility colour.

:func:`plot_camera` draws one frame through one camera of the ego: the pixels each road user is the first thing
hit along (the engine's own label image, so the picture counts what the table counts), coloured on the scale of
:mod:`.style` (cividis, as every picture) by the share of its pixels seen (``1 - occlusion``: truncation by the
image border is not hiding); the rest of each target's projection pale and hatched (what is hidden of it); the
buildings' and other static occluders' outlines in grey; each target's full 2D box (dashed) and visible 2D box
(vermillion); and, for targets at least :data:`LABEL_MIN_HEIGHT` pixels tall, a label with its idx,
visibility, occlusion and KITTI difficulty (where labels would overlap, the larger target's is kept).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely

from ..analysis.levels import kitti_levels
from ..engines.imaging import ImagingEngine
from ..inputs.sensors import Sensor
from ..query import Query
from ..table.pipeline import observer_rows, viewpoints
from ..table.rows import frame_rows
from ..table.schema import TableBuilder, to_polars
from ._optional import require
from .data import load_source, picture_question
from .style import OKABE_ITO, VISIBILITY_CMAP

NEAR = 0.05
"""Metres ahead of the camera where outlines of bodies reaching behind it are cut (their pixels are exact)."""

LABEL_MIN_HEIGHT = 25
"""Pixels: targets whose full 2D box is at least this tall get a label (KITTI's smallest evaluated height)."""


def image_outline(vertices: np.ndarray, edges: np.ndarray, matrix: np.ndarray) -> np.ndarray | None:
    """The outline (pixels, counter-clockwise in the image) of a convex body given by its ``vertices`` in the
    camera frame (shape (k, 3), metres) and ``edges`` (local vertex pairs), cut at :data:`NEAR`; None when it lies
    wholly behind. The projection of the part ahead is the hull of its vertices' images and of its edges'
    crossings with the cutting plane."""
    ahead = vertices[:, 2] >= NEAR
    points = [vertices[ahead]]
    i, j = edges[:, 0], edges[:, 1]
    cross = ahead[i] != ahead[j]
    if cross.any():
        a, b = vertices[i[cross]], vertices[j[cross]]
        w = (NEAR - a[:, 2]) / (b[:, 2] - a[:, 2])
        points.append(a + w[:, None] * (b - a))
    pts = np.concatenate(points)
    if len(pts) < 3:
        return None
    image = (matrix @ pts.T).T
    uv = image[:, :2] / image[:, 2:3]
    hull = shapely.convex_hull(shapely.MultiPoint(uv))
    if not isinstance(hull, shapely.Polygon) or hull.is_empty:
        return None
    return np.asarray(hull.exterior.coords)


def _camera(sensors: Sequence[Sensor], name: str | None) -> Sensor:
    cameras = [s for s in sensors if s.camera is not None]
    if not cameras:
        raise ValueError("plot_camera needs a camera among the sensors (inputs.sensors.camera)")
    if name is None:
        return cameras[0]
    for s in cameras:
        if s.name == name:
            return s
    raise ValueError(f"no camera named {name!r}; the cameras are {[s.name for s in cameras]}")


def plot_camera(
    df: Any,
    ego_idx: int,
    frame: int,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    sensors: Any = None,
    camera: str | None = None,
    query: Query | None = None,
    ax: Any = None,
    cmap: str = VISIBILITY_CMAP,
    labels: bool = True,
    **question: Any,
) -> Any:
    """Draw what ``camera`` (a name among ``sensors``; default the first camera) of ``ego_idx`` sees in
    ``frame``; return the matplotlib ``Axes`` (image coordinates: pixels, ``u`` right, ``v`` down from the
    top-left corner).

    ``sensors`` (a layout name, a JSON file, a Sensor or a sequence of them) must hold a camera
    (:func:`~omega_prime_visibility.inputs.sensors.camera`); the question's other keywords (static occluder
    heights, occluders, targets, ...) are those of :func:`~omega_prime_visibility.get_visibility_df`, in 3D.
    """
    plt = require("matplotlib.pyplot")
    colormaps = require("matplotlib").colormaps
    patches = require("matplotlib.patches")
    q = picture_question(query, ego_idx, static_occluder_polys, sensors=sensors, mode="3d", **question)
    if q.sensors is None:
        raise ValueError("plot_camera needs sensors with a camera (sensors=[camera(...)] or a layout)")
    source = load_source(df, q, lanes=False)
    k = source.position_of(frame)
    objects = source.objects.frame_objects(k)
    rows = observer_rows(objects, np.array([ego_idx]))
    if not len(rows):
        raise ValueError(f"the ego idx {ego_idx} is not in frame {frame}")
    own = source.scene.sensors
    own = own[ego_idx] if isinstance(own, dict) else own
    sensor = _camera(own, camera)
    view = viewpoints(objects, rows, source.statics, [sensor])[0]
    observation, scene, targets = ImagingEngine(source.statics).picture(objects, view)
    label_image = observation.counts.pop("labels")
    counted = tuple(observation.counts)
    builder = TableBuilder()
    builder.add(frame_rows([observation], np.array([view.own]), objects.idx, np.array([0]), counted),
                frame=objects.frame, total_nanos=objects.total_nanos)  # fmt: skip
    table = to_polars(builder.arrays(), with_ego=False, sensor_names=[sensor.name], counted=counted)
    table = kitti_levels(table) if "bbox_unoccluded" in table.columns else table
    image = sensor.camera
    if ax is None:
        width = 11.0
        _, ax = plt.subplots(figsize=(width, width * image.height / image.width + 0.9))
    colours = colormaps[cmap]
    ax.set_facecolor("#f2f2f2")
    matrix = image.matrix()
    n_targets = len(targets)
    for body in range(n_targets, len(scene)):  # the static occluders, grey
        outline = _outline(scene, body, matrix)
        if outline is not None:
            ax.add_patch(patches.Polygon(outline, closed=True, facecolor="#b0b0b0", edgecolor="#7a7a7a", lw=0.6))
    by_row = {r["idx"]: r for r in table.iter_rows(named=True)}
    seen_share = {idx: 1.0 - (r["occlusion"] if r["occlusion"] is not None else 1.0) for idx, r in by_row.items()}
    outlines = {}
    for slot, row in enumerate(targets.tolist()):  # each target's whole projection, pale and hatched
        idx = int(objects.idx[row])
        outline = _outline(scene, slot, matrix)
        if outline is None or idx not in by_row or not by_row[idx]["pixels_unoccluded"]:
            continue
        outlines[idx] = outline
        colour = colours(seen_share[idx])
        ax.add_patch(patches.Polygon(outline, closed=True, facecolor=(*colour[:3], 0.18), edgecolor="none",
                                     hatch="////", lw=0.5))  # fmt: skip
    rgba = np.zeros((*label_image.shape, 4))
    seen = label_image >= 0
    if seen.any():
        share = np.zeros(len(objects.idx))
        for idx, value in seen_share.items():
            share[int(np.searchsorted(objects.idx, idx))] = value
        rgba[seen] = colours(share[label_image[seen]])
    ax.imshow(rgba, extent=(0, image.width, image.height, 0), interpolation="nearest", zorder=3)
    for outline in outlines.values():  # outlines over the pixels, so that neighbours of one colour part
        ax.add_patch(patches.Polygon(outline, closed=True, fill=False, edgecolor="#333333", lw=0.5, zorder=4))
    placed: list[tuple[float, float, float, float]] = []
    scale = image.width / 1000  # pixels of the image per point of text, about, at the default size
    for info in sorted(by_row.values(), key=lambda r: -(r["pixels_unoccluded"] or 0)):
        if info["bbox_unoccluded"] is None:
            continue
        u0, v0, u1, v1 = info["bbox_unoccluded"]
        ax.add_patch(patches.Rectangle((u0, v0), u1 - u0 + 1, v1 - v0 + 1, fill=False, ls="--", lw=0.8,
                                       edgecolor="black", zorder=5))  # fmt: skip
        if info["bbox"] is not None:
            a0, b0, a1, b1 = info["bbox"]
            ax.add_patch(patches.Rectangle((a0, b0), a1 - a0 + 1, b1 - b0 + 1, fill=False, lw=1.2,
                                           edgecolor=OKABE_ITO["vermillion"], zorder=5))  # fmt: skip
        if not labels or v1 - v0 < LABEL_MIN_HEIGHT:
            continue
        level = info.get("kitti_difficulty") or "ignored"
        text = f"{info['idx']}: {info['visibility']:.0%} seen · occl {info['occlusion']:.2f} · {level}"
        box = (u0, max(v0 - 14 * scale, 0), u0 + 6.2 * scale * len(text), max(v0, 14 * scale))
        if any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in placed):
            continue  # it would cover another label
        placed.append(box)
        ax.text(u0, box[3], text, fontsize=7, zorder=6, va="bottom", clip_on=True,
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.85})  # fmt: skip
    ax.set_xlim(0, image.width)
    ax.set_ylim(image.height, 0)
    ax.set_aspect("equal")
    ax.set_xlabel("u (pixels)")
    ax.set_ylabel("v (pixels)")
    ax.set_title(
        f"frame {frame}: what camera {sensor.name!r} of ego {ego_idx} sees ({image.width} x {image.height}); "
        "hatched: hidden, dashed: full 2D box, red: visible 2D box",
        fontsize=9,
    )
    mappable = plt.cm.ScalarMappable(cmap=colours, norm=plt.Normalize(0, 1))
    ax.figure.colorbar(mappable, ax=ax, fraction=0.025, pad=0.01, label="share of its pixels seen (1 - occlusion)")
    return ax


def _outline(scene: Any, body: int, matrix: np.ndarray) -> np.ndarray | None:
    v0, v1 = scene.vstart[body], scene.vstart[body + 1]
    edges = scene.edges[scene.estart[body] : scene.estart[body + 1]] - v0
    return image_outline(scene.vertices[v0:v1], edges, matrix)
