"""The perception datasets' occlusion levels, from a table with camera and lidar columns (:data:`..table.schema.
COUNT_SCHEMA`).

Every threshold is the dataset's own where it publishes one, else a parameter (its default said here):

- **KITTI** (object devkit's readme, ``kitti_object_eval``'s ``clean_data``): ``truncated`` is the table's
  ``truncation``; ``occluded`` is 0 (fully visible: ``occlusion <= occluded_bounds[0]``, default 0, no pixel
  hidden), 1 (partly occluded: ``<= occluded_bounds[1]``, default 0.5), 2 (largely occluded) or 3 (unknown: no
  pixel of it meets a pixel centre); the difficulty is the easiest class it meets: ``easy`` (full 2D box height
  >= 40 px, occluded 0, truncated <= 0.15), ``moderate`` (>= 25 px, occluded <= 1, <= 0.30), ``hard`` (>= 25 px,
  occluded <= 2, <= 0.50), else null (KITTI ignores it). The box height is ``v1 - v0`` of ``bbox_unoccluded``
  (the devkit's ``bottom - top`` of 0-based pixel indices).
- **nuScenes** (its schema's ``visibility`` table): the visible share pooled over the vehicle's cameras,
  ``sum(pixels) / sum(pixels_unoccluded)``, binned into tokens ``"1"`` (0-40 %), ``"2"`` (40-60 %), ``"3"``
  (60-80 %), ``"4"`` (80-100 %), each bin closed above; ``num_lidar_pts`` the lidar beams that meet it first.
- **TIER IV T4** (its annotation format's visibility): from the occlusion pooled likewise: ``full`` (none hidden),
  ``most`` (occluded by less than 50 %), ``partial`` (50 % or more, below 90 %), ``none`` (90-100 %, nothing seen
  included), ``unavailable`` where no camera pixel meets it.
- **Waymo** (its detection metrics' difficulty): ``LEVEL_2`` for boxes with at most 5 lidar points (the common
  convention; ``waymo_level2_points``), ``LEVEL_1`` above, null for boxes with none (not evaluated).
- **Argoverse 2**: a box is kept for evaluation when at least one lidar point lies in it (``av2_kept``).

>>> import polars as pl
>>> rows = pl.DataFrame({"frame": [0, 0], "idx": [1, 2], "sensor": ["cam", "cam"], "pixels": [900, 10],
...     "pixels_unoccluded": [900, 100], "occlusion": [0.0, 0.9], "truncation": [0.0, 0.2],
...     "bbox_unoccluded": [[10, 10, 40, 60], [0, 5, 9, 35]]},
...     schema_overrides={"bbox_unoccluded": pl.Array(pl.Int64, 4)})
>>> kitti_levels(rows).select("idx", "kitti_occluded", "kitti_difficulty").rows()
[(1, 0, 'easy'), (2, 2, 'hard')]
>>> camera_visibility(rows, by=("frame", "idx")).select("idx", "nuscenes_visibility", "t4_visibility").rows()
[(1, '4', 'full'), (2, '1', 'none')]
"""

from __future__ import annotations

from collections.abc import Sequence

import polars as pl

KITTI_MIN_HEIGHT = (40, 25, 25)
KITTI_MAX_OCCLUSION = (0, 1, 2)
KITTI_MAX_TRUNCATION = (0.15, 0.30, 0.50)
KITTI_DIFFICULTIES = ("easy", "moderate", "hard")
"""KITTI's classes and their limits, as ``kitti_object_eval_python``'s ``clean_data`` has them."""

NUSCENES_BINS = (0.4, 0.6, 0.8)
"""nuScenes' visibility bins (upper bounds of tokens 1 to 3; token 4 above)."""

T4_LEVELS = ("full", "most", "partial", "none", "unavailable")

Frame = pl.DataFrame | pl.LazyFrame


def _need(table: Frame, columns: Sequence[str], what: str) -> None:
    names = table.collect_schema().names()
    missing = [c for c in columns if c not in names]
    if missing:
        raise ValueError(f"{what} needs the table's {', '.join(missing)}: give the observer a camera or lidar sensor")


def kitti_levels(table: Frame, occluded_bounds: tuple[float, float] = (0.0, 0.5)) -> Frame:
    """The rows of a table with camera columns, with KITTI's ``kitti_truncated``, ``kitti_occluded`` (0-3),
    ``kitti_height`` (pixels of the full 2D box) and ``kitti_difficulty`` (``easy``, ``moderate``, ``hard`` or
    null) added (see the module docstring); rows of other sensors get nulls and ``kitti_occluded`` 3."""
    _need(table, ("occlusion", "truncation", "bbox_unoccluded"), "kitti_levels")
    full, partly = occluded_bounds
    if not 0.0 <= full <= partly <= 1.0:
        raise ValueError(f"occluded_bounds must be 0 <= fully visible <= partly occluded <= 1, not {occluded_bounds}")
    occlusion = pl.col("occlusion")
    occluded = (
        pl.when(occlusion.is_null())
        .then(3)
        .when(occlusion <= full)
        .then(0)
        .when(occlusion <= partly)
        .then(1)
        .otherwise(2)
    )
    height = pl.col("bbox_unoccluded").arr.get(3) - pl.col("bbox_unoccluded").arr.get(1)
    difficulty = pl.lit(None, dtype=pl.String)
    for name, low, most, cut in reversed(
        list(zip(KITTI_DIFFICULTIES, KITTI_MIN_HEIGHT, KITTI_MAX_OCCLUSION, KITTI_MAX_TRUNCATION, strict=True))
    ):
        meets = (pl.col("kitti_height") >= low) & (pl.col("kitti_occluded") <= most) & (pl.col("truncation") <= cut)
        difficulty = pl.when(meets.fill_null(False)).then(pl.lit(name)).otherwise(difficulty)
    return table.with_columns(
        kitti_truncated=pl.col("truncation"), kitti_occluded=occluded.cast(pl.Int8), kitti_height=height
    ).with_columns(kitti_difficulty=difficulty)


def camera_visibility(table: Frame, by: Sequence[str] | None = None) -> Frame:
    """One row per target (``by``: default ``frame``, and ``idx_ego`` where present, and ``idx``) pooled over the
    cameras: ``pixels``, ``pixels_unoccluded``, ``visible_share`` (their ratio, null without pixels),
    nuScenes' ``nuscenes_visibility`` token and TIER IV's ``t4_visibility`` level (see the module docstring)."""
    _need(table, ("pixels", "pixels_unoccluded"), "camera_visibility")
    by = _keys(table, by)
    pooled = (
        table.filter(pl.col("pixels").is_not_null())
        .group_by(by, maintain_order=True)
        .agg(pl.col("pixels").sum(), pl.col("pixels_unoccluded").sum())
        .with_columns(
            visible_share=pl.when(pl.col("pixels_unoccluded") > 0).then(pl.col("pixels") / pl.col("pixels_unoccluded"))
        )
    )
    share = pl.col("visible_share")
    token = (
        pl.when(share.is_null())
        .then(None)
        .when(share <= NUSCENES_BINS[0])
        .then(pl.lit("1"))
        .when(share <= NUSCENES_BINS[1])
        .then(pl.lit("2"))
        .when(share <= NUSCENES_BINS[2])
        .then(pl.lit("3"))
        .otherwise(pl.lit("4"))
    )
    occluded = 1.0 - share
    level = (
        pl.when(share.is_null())
        .then(pl.lit("unavailable"))
        .when(occluded <= 0.0)
        .then(pl.lit("full"))
        .when(occluded < 0.5)
        .then(pl.lit("most"))
        .when(occluded < 0.9)
        .then(pl.lit("partial"))
        .otherwise(pl.lit("none"))
    )
    return pooled.with_columns(nuscenes_visibility=token, t4_visibility=level.cast(pl.Enum(T4_LEVELS)))


def lidar_levels(table: Frame, by: Sequence[str] | None = None, waymo_level2_points: int = 5) -> Frame:
    """One row per target (``by`` as :func:`camera_visibility`) pooled over the lidars: ``num_lidar_pts`` (beams
    meeting it first, nuScenes' name), ``waymo_level`` (``LEVEL_1``, ``LEVEL_2`` at ``waymo_level2_points`` or
    fewer, null with none) and ``av2_kept`` (at least one point)."""
    _need(table, ("points",), "lidar_levels")
    by = _keys(table, by)
    pooled = (
        table.filter(pl.col("points").is_not_null())
        .group_by(by, maintain_order=True)
        .agg(num_lidar_pts=pl.col("points").sum())
    )
    points = pl.col("num_lidar_pts")
    waymo = pl.when(points <= 0).then(None).when(points <= waymo_level2_points).then(pl.lit("LEVEL_2"))
    return pooled.with_columns(waymo_level=waymo.otherwise(pl.lit("LEVEL_1")), av2_kept=points > 0)


def _keys(table: Frame, by: Sequence[str] | None) -> list[str]:
    if by is not None:
        return list(by)
    names = table.collect_schema().names()
    return [c for c in ("frame", "idx_ego", "idx") if c in names]
