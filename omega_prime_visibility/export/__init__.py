"""Exporters: the answer in the files other tools read (a front end beside the CLI and batch).

- :mod:`.kitti`: :func:`~.kitti.write_kitti`, KITTI object labels and calibration files per camera and frame;
- :mod:`.mcap`: :func:`~.mcap.write_mcap`, the recording with the answer drawn in for Lichtblick (:mod:`.scene`)
  and OSI SensorData of what each sensor sees (:mod:`.sensordata`), also as ``.osi`` traces.
"""
