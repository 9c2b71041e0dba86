"""The counting engine room: cameras count pixels, lidars count beams, exactly, among the 3D mode's convex bodies.

:mod:`.lines` counts the rays of one plane through the eye (a pixel row, an azimuth column), :mod:`.camera` and
:mod:`.lidar` lay out their sensor's lines, :mod:`.solid_angle` measures a camera's truncation, :mod:`.scene`
turns a frame's bodies into one sensor's frame, and :mod:`.engine` answers the engine contract with the sensor's
own columns.
"""

from .engine import ImagingEngine

__all__ = ["ImagingEngine"]
