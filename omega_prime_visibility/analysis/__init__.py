"""Analyses: what users compute from visibility tables.

- :mod:`.combine`: :func:`~.combine.seen_by_any`, the best over sensors;
- :mod:`.intervals`: :func:`~.intervals.visible_intervals`, runs of visible frames and when a target is noticed;
- :mod:`.area`: :func:`~.area.visible_area`, the area seen (exact polygons);
- :mod:`.levels`: :func:`~.levels.kitti_levels`, :func:`~.levels.camera_visibility`, :func:`~.levels.lidar_levels`,
  the perception datasets' occlusion levels from camera and lidar counts;
- :mod:`.summary`: :func:`~.summary.target_summary`, one row per target (what the CLI prints).

Takes tables (and, for the area, the scene arrays); gives tables.
"""
