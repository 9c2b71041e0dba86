"""Sensors mounted on an observer: where they sit, where they look, how wide and how far they see.

A :class:`Sensor` is given in the observer's own frame: ``x`` forward and ``y`` left of the observer's
bounding-box centre (metres), ``yaw`` counter-clockwise from the observer's heading (radians). Each frame the
sensor's pose follows from the observer's ``x, y, yaw`` (:func:`sensor_poses`). ``fov`` is the full horizontal
opening angle, centred on the sensor's heading; ``range`` the distance up to which a hit counts.

``z`` (mounting height above the ground, metres) and ``vertical_fov``/``pitch`` are used only by the 3D mode;
the 2D engines look in the ground plane.

Ready-made layouts (:data:`LAYOUTS`, numbers in each function's docstring): :func:`roof` (one 360° sensor at the
centre), :func:`typical` (front camera, front long-range radar, four corner radars) and :func:`nuscenes` (six
pixel-counting cameras and a roof lidar), each scaled to the observer's length and width. :func:`camera` and
:func:`lidar` make the sensors that count pixels and beams (the 3D mode).

>>> import math
>>> cam = Sensor("front_camera", x=1.0, fov=math.radians(60), range=150.0)
>>> round(cam.fov_degrees, 9)
60.0
>>> [s.name for s in typical()]
['front_camera', 'front_radar', 'corner_front_left', 'corner_front_right', 'corner_rear_left', 'corner_rear_right']
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, fields

import numpy as np

from ..geometry.kernels import TWO_PI
from .cameras import Pinhole
from .lidars import BeamPattern, pattern_from

DRIVER_EYE_HEIGHT = 1.25
"""Metres above the ground: the default eye point of the 3D mode."""


@dataclass(frozen=True, slots=True)
class Sensor:
    """One sensor, mounted on the observer.

    Attributes
    ----------
    name : str
        Unique among the sensors of one call; the table's ``sensor`` column.
    x, y : float
        Mounting position, metres, in the observer's frame: ``x`` forward, ``y`` to the left of the centre of its
        bounding box.
    yaw : float
        Direction the sensor faces, radians counter-clockwise from the observer's heading.
    fov : float
        Horizontal field of view, radians, ``0 < fov <= 2π``, centred on the sensor's heading.
    range : float
        Metres, ``> 0``; ``math.inf`` for no limit. A direction counts as seen only where its first hit is within
        this distance of the sensor.
    z : float
        Mounting height above the ground, metres (3D mode only).
    vertical_fov : float
        Vertical field of view, radians, ``0 < vertical_fov <= π``, centred on ``pitch`` (3D mode only).
    pitch : float
        Radians, positive looking down, as OSI's pitch of a forward axis turned towards -z (3D mode only).
    camera : Pinhole, optional
        Makes the sensor a camera that counts pixels (3D mode only, :func:`camera`): its frustum is the image's,
        and ``fov`` and ``vertical_fov`` are the image's (set from it).
    lidar : BeamPattern, optional
        Makes the sensor a spinning lidar that counts beams (3D mode only, :func:`lidar`): ``fov`` is 2π and
        ``vertical_fov`` the span of its elevations (set from it).
    """

    name: str
    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    fov: float = TWO_PI
    range: float = math.inf
    z: float = DRIVER_EYE_HEIGHT
    vertical_fov: float = math.pi
    pitch: float = 0.0
    camera: Pinhole | None = None
    lidar: BeamPattern | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"sensor name must be a non-empty string, not {self.name!r}")
        self._take_optics()
        for f in fields(self)[1:-2]:
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
                raise ValueError(f"sensor {self.name!r}: {f.name} must be a number, not {value!r}")
            if math.isnan(value) or (math.isinf(value) and f.name != "range"):
                raise ValueError(f"sensor {self.name!r}: {f.name} must be finite, not {value!r}")
            object.__setattr__(self, f.name, float(value))
        for angle in ("yaw", "pitch"):  # an angle beyond a full turn is degrees given for radians
            value = getattr(self, angle)
            if abs(value) > TWO_PI + 1e-12:
                raise ValueError(
                    f"sensor {self.name!r}: {angle} {value:g} looks like degrees; sensor angles are radians"
                    f" ({value:g}° is {math.radians(value):.4g})"
                )
        for angle, most, text in (("fov", TWO_PI, "2π"), ("vertical_fov", math.pi, "π")):
            value = getattr(self, angle)
            if not 0.0 < value <= most + 1e-12:
                hint = (
                    f"; {value:g} looks like degrees ({value:g}° is {math.radians(value):.4g})"
                    if most < value <= 360.0
                    else ""
                )
                raise ValueError(f"sensor {self.name!r}: {angle} must be in (0, {text}] radians, not {value!r}{hint}")
        if not self.range > 0.0:
            raise ValueError(f"sensor {self.name!r}: range must be > 0 metres (inf for no limit), not {self.range!r}")

    def _take_optics(self) -> None:
        """Check ``camera`` and ``lidar`` and set the fields of view they fix."""
        if self.camera is not None and self.lidar is not None:
            raise ValueError(f"sensor {self.name!r} is a camera or a lidar, not both")
        if self.camera is not None and not isinstance(self.camera, Pinhole):
            raise ValueError(f"sensor {self.name!r}: camera must be a Pinhole, not {self.camera!r}")
        if self.lidar is not None and not isinstance(self.lidar, BeamPattern):
            raise ValueError(f"sensor {self.name!r}: lidar must be a BeamPattern, not {self.lidar!r}")
        if self.camera is None and self.lidar is None:
            return
        if self.camera is not None:
            fov, vertical = self.camera.horizontal_fov, self.camera.vertical_fov
        else:
            fov, vertical = TWO_PI, min(math.pi, self.lidar.elevations[-1] - self.lidar.elevations[0])  # type: ignore[union-attr]
        for name, value in (("fov", fov), ("vertical_fov", vertical)):
            given = getattr(self, name)
            default = TWO_PI if name == "fov" else math.pi
            if isinstance(given, int | float) and given != default and abs(given - value) > 1e-9:
                raise ValueError(
                    f"sensor {self.name!r}: the {self.kind}'s {name} is {value:.6g} radians, set by its "
                    f"{'image' if self.camera is not None else 'beam pattern'}; leave {name} out (given {given!r})"
                )
            object.__setattr__(self, name, max(value, 1e-12))

    @property
    def kind(self) -> str:
        """``"camera"``, ``"lidar"`` or ``"view"`` (a field of view and a range: radars, the 2D sensors)."""
        return "camera" if self.camera is not None else "lidar" if self.lidar is not None else "view"

    @property
    def fov_degrees(self) -> float:
        """The horizontal field of view in degrees."""
        return math.degrees(self.fov)

    @property
    def full_circle(self) -> bool:
        """Whether the sensor looks all around (``fov`` is 2π)."""
        return self.fov >= TWO_PI

    def to_dict(self) -> dict:
        """The sensor as plain JSON-able values (``range`` inf becomes None; a camera's or lidar's fields of view
        are left out, as they follow from its image or pattern)."""
        out = asdict(self)
        out["range"] = None if math.isinf(self.range) else self.range
        for name in ("camera", "lidar"):
            value = getattr(self, name)
            if value is None:
                del out[name]
            else:
                out[name] = value.to_dict()
                del out["fov"], out["vertical_fov"]
        return out


def camera(
    name: str,
    width: int = 1920,
    height: int = 1080,
    fov: float = math.radians(90),
    *,
    focal: float | None = None,
    matrix: Sequence[Sequence[float]] | np.ndarray | None = None,
    x: float = 0.0,
    y: float = 0.0,
    z: float = DRIVER_EYE_HEIGHT,
    yaw: float = 0.0,
    pitch: float = 0.0,
    range: float = math.inf,
) -> Sensor:
    """A pinhole camera of ``width`` x ``height`` pixels, mounted as any :class:`Sensor`: square pixels, the
    principal point at the image centre, horizontal field of view ``fov`` (radians; ``f = (width / 2) /
    tan(fov / 2)``), or else the focal length ``focal`` (pixels) or the intrinsic ``matrix`` (3 x 3, pixels).
    See :mod:`.cameras` for the image's conventions.

    >>> cam = camera("front", 1280, 720, math.radians(60), x=1.5, z=1.4)
    >>> cam.kind, round(math.degrees(cam.fov), 6), round(cam.camera.fx, 3)
    ('camera', 60.0, 1108.513)
    """
    if focal is not None and matrix is not None:
        raise ValueError(f"camera {name!r}: give focal or matrix, not both")
    if matrix is not None:
        image = Pinhole.from_matrix(width, height, matrix)
    elif focal is not None:
        image = Pinhole.from_focal_length(width, height, focal)
    else:
        image = Pinhole.from_fov(width, height, fov)
    return Sensor(name, x=x, y=y, yaw=yaw, range=range, z=z, pitch=pitch, camera=image)


def lidar(
    name: str,
    pattern: str | BeamPattern = "os1-128",
    *,
    x: float = 0.0,
    y: float = 0.0,
    z: float = 2.0,
    yaw: float = 0.0,
    pitch: float = 0.0,
    range: float = 120.0,
) -> Sensor:
    """A spinning lidar with the beam ``pattern`` (a name in :data:`.lidars.PATTERNS` or a
    :class:`~.lidars.BeamPattern`), mounted as any :class:`Sensor` (``pitch`` tilts its spin axis forward-down).

    >>> roof_lidar = lidar("roof_lidar", "vlp16", z=1.9, range=100.0)
    >>> roof_lidar.kind, roof_lidar.lidar.channels, round(math.degrees(roof_lidar.vertical_fov), 6)
    ('lidar', 16, 30.0)
    """
    return Sensor(name, x=x, y=y, yaw=yaw, range=range, z=z, pitch=pitch, lidar=pattern_from(pattern))


def roof(length: float = 4.6, width: float = 1.85, *, range: float = math.inf, z: float = 2.0) -> list[Sensor]:
    """One 360° sensor at the centre of the roof, named ``roof`` (like a roof lidar), unlimited range by default.

    ``length`` and ``width`` are accepted for symmetry with :func:`typical` and do not move it.

    >>> roof()[0].fov == 2 * math.pi, roof(range=120.0)[0].range
    (True, 120.0)
    """
    _check_size(length, width)
    return [Sensor("roof", fov=TWO_PI, range=range, z=z)]


def typical(length: float = 4.6, width: float = 1.85) -> list[Sensor]:
    """A common driver-assistance layout for a car of ``length`` x ``width`` metres (default a 4.6 m x 1.85 m
    mid-size car), positions relative to its centre:

    ========================  ========================  ==========  ======  =======  ======
    name                      position (x, y)           yaw         fov     range    z
    ========================  ========================  ==========  ======  =======  ======
    ``front_camera``          (0.15 L, 0)               0°          60°     150 m    1.3 m
    ``front_radar``           (L / 2, 0)                0°          20°     200 m    0.5 m
    ``corner_front_left``     (L / 2, W / 2)            45°         150°    80 m     0.5 m
    ``corner_front_right``    (L / 2, -W / 2)           -45°        150°    80 m     0.5 m
    ``corner_rear_left``      (-L / 2, W / 2)           135°        150°    80 m     0.5 m
    ``corner_rear_right``     (-L / 2, -W / 2)          -135°       150°    80 m     0.5 m
    ========================  ========================  ==========  ======  =======  ======

    The camera sits behind the windscreen, the radars in the bumpers; together they leave blind spots beside
    the car's flanks at close range, as real layouts do.

    >>> [round(s.x, 2) for s in typical(length=5.0)][:2]
    [0.75, 2.5]
    """
    _check_size(length, width)
    half_l, half_w = length / 2, width / 2
    corner = math.radians(150)
    return [
        Sensor("front_camera", x=0.15 * length, fov=math.radians(60), range=150.0, z=1.3),
        Sensor("front_radar", x=half_l, fov=math.radians(20), range=200.0, z=0.5),
        Sensor("corner_front_left", x=half_l, y=half_w, yaw=math.radians(45), fov=corner, range=80.0, z=0.5),
        Sensor("corner_front_right", x=half_l, y=-half_w, yaw=math.radians(-45), fov=corner, range=80.0, z=0.5),
        Sensor("corner_rear_left", x=-half_l, y=half_w, yaw=math.radians(135), fov=corner, range=80.0, z=0.5),
        Sensor("corner_rear_right", x=-half_l, y=-half_w, yaw=math.radians(-135), fov=corner, range=80.0, z=0.5),
    ]


def nuscenes(length: float = 4.6, width: float = 1.85) -> list[Sensor]:
    """A perception rig after nuScenes' (six 1600 x 900 cameras around the car and a 32-beam roof lidar), its
    mounts approximately those of the dataset's car, scaled to the observer's ``length`` and ``width``:

    ============================  =================  ==========  =====  =======
    name                          position (x, y)    yaw         fov    z
    ============================  =================  ==========  =====  =======
    ``cam_front``                 (0.37 L, 0)        0°          70°    1.5 m
    ``cam_front_left``            (0.35 L, W / 4)    55°         70°    1.5 m
    ``cam_front_right``           (0.35 L, -W / 4)   -55°        70°    1.5 m
    ``cam_back``                  (-0.4 L, 0)        180°        110°   1.5 m
    ``cam_back_left``             (-0.05 L, W / 4)   110°        70°    1.5 m
    ``cam_back_right``            (-0.05 L, -W / 4)  -110°       70°    1.5 m
    ``lidar_top``                 (0, 0)             0°          360°   1.85 m
    ============================  =================  ==========  =====  =======

    The lidar fires the HDL-32E's pattern (:data:`.lidars.PATTERNS`) to 70 m; the cameras see without a range.

    >>> [s.kind for s in nuscenes()].count("camera"), nuscenes()[-1].lidar.channels
    (6, 32)
    """
    _check_size(length, width)
    quarter = width / 4
    front = math.radians(70)
    return [
        camera("cam_front", 1600, 900, front, x=0.37 * length, z=1.5),
        camera("cam_front_left", 1600, 900, front, x=0.35 * length, y=quarter, yaw=math.radians(55), z=1.5),
        camera("cam_front_right", 1600, 900, front, x=0.35 * length, y=-quarter, yaw=math.radians(-55), z=1.5),
        camera("cam_back", 1600, 900, math.radians(110), x=-0.4 * length, yaw=math.pi, z=1.5),
        camera("cam_back_left", 1600, 900, front, x=-0.05 * length, y=quarter, yaw=math.radians(110), z=1.5),
        camera("cam_back_right", 1600, 900, front, x=-0.05 * length, y=-quarter, yaw=math.radians(-110), z=1.5),
        lidar("lidar_top", "hdl32e", z=1.85, range=70.0),
    ]


LAYOUTS = {"roof": roof, "typical": typical, "nuscenes": nuscenes}
"""Ready-made layouts by name, each a function of the observer's ``length`` and ``width``."""


def _check_size(length: float, width: float) -> None:
    for name, value in (("length", length), ("width", width)):
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a positive number of metres, not {value!r}")


def check_sensors(sensors: Iterable[Sensor]) -> tuple[Sensor, ...]:
    """``sensors`` as a non-empty tuple of :class:`Sensor` with unique names, else a ``ValueError``."""
    out = tuple(sensors)
    if not out:
        raise ValueError("sensors must hold at least one Sensor")
    for s in out:
        if not isinstance(s, Sensor):
            raise ValueError(f"sensors must be Sensor objects, not {type(s).__name__} ({s!r})")
    names = [s.name for s in out]
    duplicates = sorted({n for n in names if names.count(n) > 1})
    if duplicates:
        raise ValueError(f"sensor names must be unique; repeated: {duplicates}")
    return out


def is_layout(spec: object) -> bool:
    """Whether ``spec`` names a ready-made layout (:data:`LAYOUTS`)."""
    return isinstance(spec, str) and spec in LAYOUTS


def fitted_layout(name: str, sizes: dict[int, tuple[float, float]]) -> dict[int, tuple[Sensor, ...]]:
    """The layout ``name`` (:data:`LAYOUTS`) per observer, fitted to each one's ``(length, width)`` in ``sizes``
    (metres, by idx).

    >>> fitted = fitted_layout("typical", {0: (4.0, 1.8), 7: (12.0, 2.5)})
    >>> [s.x for s in fitted[7] if s.name == "front_radar"], [s.x for s in fitted[0] if s.name == "front_radar"]
    ([6.0], [2.0])
    """
    return {idx: check_sensors(LAYOUTS[name](length, width)) for idx, (length, width) in sizes.items()}


def sensor_poses(
    sensors: Sensor | Sequence[Sensor], position: np.ndarray, heading: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """World positions (metres) and headings (radians, counter-clockwise from +x) of ``sensors`` on observers at
    ``position`` (shape (m, 2)) facing ``heading`` (shape (m,)): shape (m * s, 2) and (m * s,), observer by
    observer, each with its sensors in order (one Sensor: shape (m, 2) and (m,)).

    >>> p, h = sensor_poses(Sensor("s", x=2.0, yaw=math.pi / 2), np.array([[10.0, 0.0]]), np.array([math.pi / 2]))
    >>> np.round(p, 12).tolist(), round(float(h[0]), 12)
    ([[10.0, 2.0]], 3.14159265359)
    """
    sensors = [sensors] if isinstance(sensors, Sensor) else sensors
    position = np.asarray(position, dtype=np.float64).reshape(-1, 1, 2)
    heading = np.asarray(heading, dtype=np.float64).reshape(-1, 1)
    mount = np.array([(s.x, s.y, s.yaw) for s in sensors], dtype=np.float64).reshape(1, -1, 3)
    c, s = np.cos(heading), np.sin(heading)
    dx = c * mount[..., 0] - s * mount[..., 1]
    dy = s * mount[..., 0] + c * mount[..., 1]
    world = position + np.stack([dx, dy], axis=-1)
    return world.reshape(-1, 2), (heading + mount[..., 2]).reshape(-1)
