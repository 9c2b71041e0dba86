"""Inputs: from a recording (an omega-prime ``Recording``, a polars table, an MCAP or OSI path, static occluders,
sensors) to the per-frame scene arrays the engines take.

- :mod:`.io`: reading recordings and maps from files, with clear errors;
- :mod:`.reader`: MCAP files of OSI ground truth straight into omega-prime's table (:mod:`.osi_wire` decodes
  them);
- :mod:`.scene`: the checks of the moving-object table, once, and :func:`~.scene.load_objects`;
- :mod:`.outlines`: outlines (shapely polygons or box corners) as rings;
- :mod:`.objects`: the arrays themselves (:class:`~.objects.ObjectTable`, :class:`~.objects.FrameObjects`) and
  :class:`~.objects.VisibilityInputWarning`;
- :mod:`.boxes3d`: the 3D columns (``z, height, roll, pitch``);
- :mod:`.statics`: static occluders as rings and edges; :mod:`.containment`: which bodies contain a viewpoint;
- :mod:`.sensors`: sensors and their poses; :mod:`.observers`: which objects observe;
- :mod:`.errors`: :class:`~.errors.OptionError`, a bad option named, worded by each front end.

Validates at the edge, so the stages after it trust their arrays.
"""
