"""The default engine: VisiLibity1's exact visibility polygon, attributed back to the objects.

Per frame and observer:

1. Coordinates are taken relative to the nearest point of a 1024 m grid, for precision with large map
   coordinates, and so that static geometry is converted to VisiLibity once per grid cell.
2. A *valid* VisiLibity environment is built (outer boundary counter-clockwise, holes clockwise, disjoint and
   inside): blocking bodies (objects, static polygons, LineString walls thickened to ``2 * wall_half_width``) whose
   bounding boxes overlap are tested exactly and overlapping groups are merged with shapely; every group becomes
   one hole, inside a box around everything. Groups that only touch at a point are joined by a ``touch_gap``
   buffer. If the observer is enclosed by a group (say a ring of cars around it), the environment is instead the
   piece of free space holding the observer.
3. VisiLibity computes the visibility polygon (VisiLibity1 1.0.10 compiled with the package, its sweep's edge
   queue patched: see :mod:`.polygon_check`, which checks every polygon exactly). Each of its edges either runs
   along some body's boundary (it then lies on one original edge, found as the nearest edge to the edge's
   midpoint) or points straight at the observer (it subtends no angle). The angle subtended by a body's edges is
   its visible angle.
4. Occluders: candidates are blocking objects whose extent meets the target's and static edges that come nearer
   than the target's farthest point within its bearings (:mod:`...geometry.candidates`); those certain to occlude
   (wholly nearer) are kept at once, the exact pairwise test of :mod:`...geometry.occlusion` keeps the others
   really hit before the target. A target hidden behind a single nearer object is left out of the environment and
   sees nothing.

When every viewpoint of a chunk of frames sees all around without range, :mod:`.chunk` runs these steps over the
whole chunk in compiled loops around VisiLibity's calls, with the same numbers; where no two bodies meet, step 2
is the plain environment of :mod:`.plain` (the bodies themselves as holes).
"""

from .engine import VisiLibityEngine

__all__ = ["VisiLibityEngine"]
