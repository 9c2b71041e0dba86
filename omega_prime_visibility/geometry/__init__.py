"""Geometry: the building blocks every later stage uses, pure functions over plain arrays (metres; bearings in
radians counter-clockwise from +x, relative to the viewpoint where stated).

- :mod:`.kernels`: shared numba helpers (growable buffers, sorts, angles, ray-line distances);
- :mod:`.rings`: ragged polygon rings (:class:`~.rings.Rings`), boxes, orientation, angular extents;
- :mod:`.occlusion`: the exact pairwise "hit before" test and the one tie rule of all 2D engines;
- :mod:`.view`: a sensor's wedge and range as bearing intervals;
- :mod:`.star_union`, :mod:`.union_rings`: unions of star-shaped regions (the visible area).

Takes arrays, gives arrays; imports nothing from the stages after it.
"""
