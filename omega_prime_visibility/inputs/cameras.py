"""A pinhole camera's image: its size in pixels and its intrinsics, checked once.

Conventions (OpenCV's and KITTI's): pixel ``(u, v)`` counts ``u`` to the right and ``v`` down from the image's
top-left corner, and covers ``[u, u + 1) x [v, v + 1)``, so its centre is ``(u + 0.5, v + 0.5)``. A direction
``(x, y, z)`` in the camera frame (``x`` right, ``y`` down, ``z`` forward, metres) has its image point at
``(fx x / z + cx, fy y / z + cy)``; it is in the image when that point lies in ``[0, width] x [0, height]`` and
``z > 0``. No skew, no lens distortion.

>>> cam = Pinhole.from_fov(1920, 1080, math.radians(90))
>>> round(cam.fx, 9), cam.cx, cam.cy, round(math.degrees(cam.horizontal_fov), 9)
(960.0, 960.0, 540.0, 90.0)
>>> round(math.degrees(cam.vertical_fov), 4)
58.7155
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, slots=True)
class Pinhole:
    """The image of a pinhole camera.

    Attributes
    ----------
    width, height : int
        Pixels, ``> 0``.
    fx, fy : float
        Focal lengths in pixels, ``> 0`` (square pixels: equal).
    cx, cy : float
        The principal point in pixels from the top-left corner (the image centre: ``width / 2, height / 2``).
    """

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value <= 0:
                raise ValueError(f"camera {name} must be a positive whole number of pixels, not {value!r}")
            object.__setattr__(self, name, int(value))
        for name in ("fx", "fy", "cx", "cy"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
                raise ValueError(f"camera {name} must be a number of pixels, not {value!r}")
            if not math.isfinite(value):
                raise ValueError(f"camera {name} must be finite, not {value!r}")
            object.__setattr__(self, name, float(value))
        if not (self.fx > 0 and self.fy > 0):
            raise ValueError(f"camera focal lengths must be > 0 pixels, not fx={self.fx!r}, fy={self.fy!r}")
        if not (0 < self.cx < self.width and 0 < self.cy < self.height):
            raise ValueError(
                f"camera principal point ({self.cx:g}, {self.cy:g}) must lie inside the {self.width} x "
                f"{self.height} image"
            )

    @classmethod
    def from_fov(cls, width: int, height: int, fov: float) -> Pinhole:
        """The camera of ``width`` x ``height`` pixels with horizontal field of view ``fov`` (radians, in (0, π)):
        square pixels, the principal point at the image centre, ``f = (width / 2) / tan(fov / 2)`` (as CARLA
        builds its camera matrix).

        >>> round(Pinhole.from_fov(800, 600, math.pi / 2).fy, 9)
        400.0
        """
        if isinstance(fov, bool) or not isinstance(fov, int | float | np.floating) or not 0 < fov < math.pi:
            hint = f"; {fov:g} looks like degrees" if isinstance(fov, int | float) and 3.2 < fov < 180 else ""
            raise ValueError(f"camera fov must be in (0, π) radians, not {fov!r}{hint}")
        f = (width / 2) / math.tan(fov / 2)
        return cls(width, height, f, f, width / 2, height / 2)

    @classmethod
    def from_focal_length(cls, width: int, height: int, focal: float) -> Pinhole:
        """Square pixels of focal length ``focal`` (pixels), the principal point at the image centre."""
        return cls(width, height, focal, focal, width / 2, height / 2)

    @classmethod
    def from_matrix(cls, width: int, height: int, matrix: Sequence[Sequence[float]] | np.ndarray) -> Pinhole:
        """From the 3 x 3 intrinsic matrix ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]`` (pixels)."""
        k = np.asarray(matrix, dtype=np.float64)
        if k.shape != (3, 3) or not np.isfinite(k).all():
            raise ValueError(f"a camera matrix is 3 x 3 finite numbers, not shape {k.shape}")
        if k[0, 1] != 0 or k[1, 0] != 0 or tuple(k[2]) != (0.0, 0.0, 1.0):
            raise ValueError("a camera matrix must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)")
        return cls(width, height, float(k[0, 0]), float(k[1, 1]), float(k[0, 2]), float(k[1, 2]))

    def matrix(self) -> np.ndarray:
        """The 3 x 3 intrinsic matrix ``K`` (pixels)."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    @property
    def horizontal_fov(self) -> float:
        """Radians between the image's left and right edges through the principal point's row."""
        return math.atan(self.cx / self.fx) + math.atan((self.width - self.cx) / self.fx)

    @property
    def vertical_fov(self) -> float:
        """Radians between the image's top and bottom edges through the principal point's column."""
        return math.atan(self.cy / self.fy) + math.atan((self.height - self.cy) / self.fy)

    def to_dict(self) -> dict:
        """The camera as plain JSON-able values (``width``, ``height``, ``fx``, ``fy``, ``cx``, ``cy``)."""
        return {"width": self.width, "height": self.height, "fx": self.fx, "fy": self.fy, "cx": self.cx, "cy": self.cy}


def pinhole_from_dict(item: dict) -> Pinhole:
    """A :class:`Pinhole` from a JSON object: ``width`` and ``height`` with ``fov`` (radians), or ``focal``, or
    ``matrix`` (3 x 3), or all of ``fx, fy, cx, cy``.

    >>> pinhole_from_dict({"width": 640, "height": 480, "focal": 500}).fx
    500.0
    """
    if not isinstance(item, dict):
        raise ValueError(f"a camera is an object with width, height and fov (or focal, or matrix), not {item!r}")
    known = {"width", "height", "fov", "focal", "matrix", "fx", "fy", "cx", "cy"}
    unknown = sorted(set(item) - known)
    if unknown:
        raise ValueError(f"camera has unknown field(s) {unknown}; known: {sorted(known)}")
    missing = [k for k in ("width", "height") if k not in item]
    if missing:
        raise ValueError(f"camera needs {' and '.join(missing)} (pixels)")
    width, height = item["width"], item["height"]
    ways = [k for k in ("fov", "focal", "matrix") if k in item] + (["fx"] if "fx" in item else [])
    if len(ways) != 1:
        raise ValueError("camera needs exactly one of fov (radians), focal (pixels), matrix or fx, fy, cx, cy")
    if "fov" in item:
        return Pinhole.from_fov(width, height, item["fov"])
    if "focal" in item:
        return Pinhole.from_focal_length(width, height, item["focal"])
    if "matrix" in item:
        return Pinhole.from_matrix(width, height, item["matrix"])
    missing = [k for k in ("fx", "fy", "cx", "cy") if k not in item]
    if missing:
        raise ValueError(f"camera with fx needs fy, cx and cy too; missing: {missing}")
    return Pinhole(width, height, item["fx"], item["fy"], item["cx"], item["cy"])
