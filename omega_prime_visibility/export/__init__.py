"""Exporters: the answer in the files other tools read (a front end beside the CLI and batch).

- :mod:`.kitti`: :func:`~.kitti.write_kitti`, KITTI object labels and calibration files per camera and frame.
"""
