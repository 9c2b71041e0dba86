"""Synthetic motorway on-ramp merge, written as an omega-prime MCAP recording.

The scenario is built for testing visibility and occlusion: a truck next to the ego
vehicle hides an on-ramp, and the cars on it, for a good part of the recording.

Layout (x points in the driving direction, y to the left, metres):

* a straight three-lane motorway, lane width 3.5 m; lane centres at y = 3.5 (left),
  0.0 (middle) and -3.5 (right);
* an on-ramp that curves in from the right (y = -15) and becomes a parallel acceleration
  lane (centre y = -7.0) between x = ``X_JOIN`` and x = ``X_ACC_END``, followed by a taper
  that closes at x = ``X_TAPER_END``.

Moving objects (``idx`` is the object id):

* 0: ego car (host vehicle), middle lane, 27 m/s;
* 1: heavy truck (16.5 m long) in the right lane, 24 m/s, starting a little ahead of the
  ego and falling back alongside and behind it;
* 2: car on the ramp ahead of the truck; accelerates and merges in front of the truck;
* 3: car on the ramp behind the truck; accelerates and merges behind the truck;
* 4: car ahead of the ego in the middle lane;
* 5: car in the left lane overtaking the ego;
* 6: car far ahead in the right lane.

Seen from the ego centre, the truck completely hides car 2 for the first ~4 s (on the ramp,
just ahead of the truck) and car 3 from ~7.8 s to ~14 s (on the acceleration lane, behind the
truck); both are partly hidden in the frames around those intervals.

The recording lasts 20 s at 10 Hz (201 frames). All trajectories are closed-form (smooth
speed profiles and quintic "smootherstep" lane changes), so velocities, accelerations and
yaw angles are exact derivatives of the positions and every run gives the same table.
A lane map (OSI lanes and lane boundaries) is attached. The script checks that no two
objects overlap in any frame before writing.

Run from the repository root::

    uv run python scenarios/highway_merge.py            # writes ./highway_merge.mcap
    uv run python scenarios/highway_merge.py -o out.mcap

Load it back with ``omega_prime.Recording.from_file(path)``. (Passing extra keyword arguments
such as ``compute_polygons=True`` makes omega-prime 0.3.7 fall back from the full ``MapOsi``
to a centre-line-only map, because they are forwarded to ``MapOsi.create``, which rejects them.
omega-prime 0.3.7's writer also puts each object's width into the MCAP height field; this script works
around that (see :func:`real_heights`), so the file holds the real heights and the 3D mode sees a 4 m truck.)
"""

from __future__ import annotations

import argparse
import itertools
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import betterosi
import numpy as np
import omega_prime
import polars as pl
import shapely
from omega_prime.types import (
    LaneBoundaryType,
    LaneSubtype,
    LaneType,
    MovingObjectRole,
    MovingObjectSubtype,
    MovingObjectType,
)

FloatArray = np.ndarray

# --- time base ---------------------------------------------------------------------------
RATE_HZ = 10
N_FRAMES = 201  # 0.0 s ... 20.0 s
NANOS_PER_FRAME = 1_000_000_000 // RATE_HZ

# --- road geometry -----------------------------------------------------------------------
LANE_WIDTH = 3.5
Y_LEFT, Y_MIDDLE, Y_RIGHT = LANE_WIDTH, 0.0, -LANE_WIDTH
Y_ACC = -2 * LANE_WIDTH  # centre of the acceleration lane
RAMP_OFFSET = 8.0  # lateral offset of the ramp before it curves in (ramp centre at y = -15)
X_START, X_END = -150.0, 750.0  # extent of the mapped road
X_RAMP_CURVE = -100.0  # ramp starts curving towards the motorway here
X_JOIN = 40.0  # ramp meets the motorway, acceleration lane starts
X_ACC_END = 360.0  # acceleration lane starts to taper
X_TAPER_END = 420.0  # acceleration lane has closed
MAP_STEP = 10.0  # spacing of map polyline points
MERGE_DURATION = 4.0  # seconds for the lane change from the acceleration lane to the right lane

# --- object classification (values of the OSI enums re-exported by omega_prime.types) -----
VEHICLE = int(MovingObjectType.VEHICLE)  # 2
CIVIL = int(MovingObjectRole.CIVIL)  # 2
CAR = int(MovingObjectSubtype.CAR)  # 4
HEAVY_TRUCK = int(MovingObjectSubtype.HEAVY_TRUCK)  # 7


# --- smooth building blocks --------------------------------------------------------------
def smootherstep(u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Quintic step 0 -> 1 on u in [0, 1] (clamped outside) and its 1st and 2nd derivative."""
    u = np.clip(u, 0.0, 1.0)
    s = u**3 * (10.0 - 15.0 * u + 6.0 * u**2)
    ds = 30.0 * u**2 * (1.0 - u) ** 2
    dds = 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u)
    return s, ds, dds


def smootherstep_integral(u: FloatArray) -> FloatArray:
    """Integral of :func:`smootherstep` from 0 to u (continues linearly with slope 1 after u = 1)."""
    uc = np.clip(u, 0.0, 1.0)
    return uc**6 - 3.0 * uc**5 + 2.5 * uc**4 + np.maximum(u - 1.0, 0.0)


@dataclass(frozen=True)
class SpeedProfile:
    """Longitudinal motion: speed ``v0``, changing smoothly to ``v1`` during [t_start, t_start + duration]."""

    x0: float
    v0: float
    v1: float | None = None
    t_start: float = 0.0
    duration: float = 1.0

    def evaluate(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position, speed and acceleration along the path at times ``t``."""
        dv = 0.0 if self.v1 is None else self.v1 - self.v0
        u = (t - self.t_start) / self.duration
        s, ds, _ = smootherstep(u)
        pos = self.x0 + self.v0 * t + dv * self.duration * smootherstep_integral(u)
        return pos, self.v0 + dv * s, dv * ds / self.duration


@dataclass(frozen=True)
class LaneChange:
    """Smooth lateral shift by ``dy`` metres during [t_start, t_start + duration]."""

    dy: float
    t_start: float
    duration: float

    def evaluate(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Lateral offset and its first and second time derivative."""
        s, ds, dds = smootherstep((t - self.t_start) / self.duration)
        return self.dy * s, self.dy * ds / self.duration, self.dy * dds / self.duration**2


def ramp_centre(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Centre line y(x) of the on-ramp / acceleration lane and dy/dx, d2y/dx2."""
    length = X_JOIN - X_RAMP_CURVE
    s, ds, dds = smootherstep((x - X_RAMP_CURVE) / length)
    y = Y_ACC - RAMP_OFFSET * (1.0 - s)
    return y, RAMP_OFFSET * ds / length, RAMP_OFFSET * dds / length**2


def straight_lane(y0: float) -> Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray]]:
    """Centre line of a straight motorway lane at ``y = y0``."""

    def centre(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        zeros = np.zeros_like(x)
        return zeros + y0, zeros, zeros

    return centre


# --- objects -----------------------------------------------------------------------------
@dataclass(frozen=True)
class Actor:
    """A vehicle following a lane centre line with a speed profile and optional lane change."""

    idx: int
    length: float
    width: float
    height: float
    subtype: int
    speed: SpeedProfile
    path: Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray]]
    lane_change: LaneChange | None = None


def actors() -> list[Actor]:
    """All objects of the scenario; idx 0 is the ego vehicle."""
    middle, left, right = straight_lane(Y_MIDDLE), straight_lane(Y_LEFT), straight_lane(Y_RIGHT)
    merge_dy = Y_RIGHT - Y_ACC
    return [
        Actor(0, 4.5, 1.9, 1.5, CAR, SpeedProfile(x0=0.0, v0=27.0), middle),
        Actor(1, 16.5, 2.55, 4.0, HEAVY_TRUCK, SpeedProfile(x0=12.0, v0=24.0), right),
        Actor(
            2,
            4.6,
            1.85,
            1.5,
            CAR,
            SpeedProfile(x0=30.0, v0=24.0, v1=27.0, t_start=0.5, duration=6.0),
            ramp_centre,
            LaneChange(merge_dy, t_start=5.0, duration=MERGE_DURATION),
        ),
        Actor(
            3,
            4.7,
            1.8,
            1.45,
            CAR,
            SpeedProfile(x0=-12.0, v0=20.0, v1=24.0, t_start=1.0, duration=6.0),
            ramp_centre,
            LaneChange(merge_dy, t_start=12.0, duration=MERGE_DURATION),
        ),
        Actor(4, 4.8, 1.9, 1.55, CAR, SpeedProfile(x0=42.0, v0=27.5), middle),
        Actor(5, 4.9, 1.95, 1.6, CAR, SpeedProfile(x0=-35.0, v0=32.0), left),
        Actor(6, 4.5, 1.8, 1.45, CAR, SpeedProfile(x0=150.0, v0=25.0), right),
    ]


def actor_table(actor: Actor, t: FloatArray) -> pl.DataFrame:
    """Per-frame state of one actor in the omega-prime moving-object schema."""
    x, vx, ax = actor.speed.evaluate(t)
    y, dydx, d2ydx2 = actor.path(x)
    vy = dydx * vx
    ay = d2ydx2 * vx**2 + dydx * ax
    if actor.lane_change is not None:
        dy, dvy, day = actor.lane_change.evaluate(t)
        y, vy, ay = y + dy, vy + dvy, ay + day
    n = len(t)
    zeros = np.zeros(n)
    return pl.DataFrame(
        {
            "total_nanos": np.arange(n, dtype=np.int64) * NANOS_PER_FRAME,
            "idx": np.full(n, actor.idx, dtype=np.int64),
            "x": x,
            "y": y,
            "z": np.full(n, actor.height / 2.0),
            "vel_x": vx,
            "vel_y": vy,
            "vel_z": zeros,
            "acc_x": ax,
            "acc_y": ay,
            "acc_z": zeros,
            "length": np.full(n, actor.length),
            "width": np.full(n, actor.width),
            "height": np.full(n, actor.height),
            "roll": zeros,
            "pitch": zeros,
            "yaw": np.arctan2(vy, vx),
            "type": np.full(n, VEHICLE, dtype=np.int64),
            "role": np.full(n, CIVIL, dtype=np.int64),
            "subtype": np.full(n, actor.subtype, dtype=np.int64),
        }
    )


def build_table() -> pl.DataFrame:
    """The moving-object table for all frames and objects, sorted by time and idx."""
    t = np.arange(N_FRAMES) / RATE_HZ
    return pl.concat([actor_table(a, t) for a in actors()]).sort(["total_nanos", "idx"])


def footprints(df: pl.DataFrame) -> FloatArray:
    """Bounding-box corners of every row, shape (rows, 4, 2)."""
    x, y, yaw = (df[c].to_numpy() for c in ("x", "y", "yaw"))
    half_l, half_w = df["length"].to_numpy() / 2.0, df["width"].to_numpy() / 2.0
    local = np.array([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]])
    lx, ly = local[:, 0] * half_l[:, None], local[:, 1] * half_w[:, None]
    cos, sin = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    return np.stack([x[:, None] + lx * cos - ly * sin, y[:, None] + lx * sin + ly * cos], axis=-1)


def check_no_overlap(df: pl.DataFrame) -> None:
    """Raise if the footprints of any two objects intersect in any frame."""
    polygons = shapely.polygons(footprints(df))
    nanos, idx = df["total_nanos"].to_numpy(), df["idx"].to_numpy()
    for frame_nanos in np.unique(nanos):
        rows = np.flatnonzero(nanos == frame_nanos)
        for i, j in itertools.combinations(rows, 2):
            if shapely.intersects(polygons[i], polygons[j]):
                raise RuntimeError(f"objects {idx[i]} and {idx[j]} overlap at total_nanos={frame_nanos}")


# --- lane map ----------------------------------------------------------------------------
def polyline(x: FloatArray, y: FloatArray) -> list[betterosi.Vector3d]:
    """OSI points of a polyline in the road plane."""
    return [betterosi.Vector3d(x=float(a), y=float(b), z=0.0) for a, b in zip(x, y, strict=True)]


def sample_x(x0: float, x1: float) -> FloatArray:
    """Map sample positions from ``x0`` to ``x1`` (both included)."""
    return np.linspace(x0, x1, round((x1 - x0) / MAP_STEP) + 1)


def lane_boundary(bid: int, x: FloatArray, y: FloatArray, kind: LaneBoundaryType) -> betterosi.LaneBoundary:
    """An OSI lane boundary along (x, y)."""
    return betterosi.LaneBoundary(
        id=betterosi.Identifier(value=bid),
        boundary_line=[betterosi.LaneBoundary.BoundaryPoint(position=p, width=0.15) for p in polyline(x, y)],
        classification=betterosi.LaneBoundary.Classification(type=kind),
    )


def lane(
    lid: int,
    x: FloatArray,
    y: FloatArray,
    boundaries: tuple[int, int],
    subtype: LaneSubtype = LaneSubtype.NORMAL,
    predecessor: int | None = None,
    successor: int | None = None,
) -> betterosi.Lane:
    """An OSI driving lane with centre line (x, y) and (left, right) boundary ids."""
    pairing = betterosi.Lane.Classification.LanePairing(
        antecessor_lane_id=None if predecessor is None else betterosi.Identifier(value=predecessor),
        successor_lane_id=None if successor is None else betterosi.Identifier(value=successor),
    )
    return betterosi.Lane(
        id=betterosi.Identifier(value=lid),
        classification=betterosi.Lane.Classification(
            type=LaneType.DRIVING,
            subtype=subtype,
            centerline=polyline(x, y),
            centerline_is_driving_direction=True,
            left_lane_boundary_id=[betterosi.Identifier(value=boundaries[0])],
            right_lane_boundary_id=[betterosi.Identifier(value=boundaries[1])],
            lane_pairing=[pairing] if predecessor is not None or successor is not None else [],
        ),
    )


def build_map() -> omega_prime.MapOsi:
    """Lane map: three motorway sections (before / along / after the acceleration lane) plus the ramp.

    Lane ids are ``10 * section + k`` (k = 0 left, 1 middle, 2 right) for the motorway, 30 for the
    ramp and 31 for the acceleration lane; boundary ids are ``100 + 10 * section + k`` (k = 0 is the
    left road edge) for the motorway and 130-132 for ramp and acceleration lane.
    """
    sections = [(X_START, X_JOIN), (X_JOIN, X_TAPER_END), (X_TAPER_END, X_END)]
    boundary_y = [
        Y_LEFT + LANE_WIDTH / 2,
        Y_MIDDLE + LANE_WIDTH / 2,
        Y_RIGHT + LANE_WIDTH / 2,
        Y_ACC + LANE_WIDTH / 2,
    ]
    boundaries, lanes = [], []
    for s, (x0, x1) in enumerate(sections):
        x = sample_x(x0, x1)
        for k, y in enumerate(boundary_y):
            outer = k in (0, 3)
            kind = LaneBoundaryType.SOLID_LINE if outer and not (s == 1 and k == 3) else LaneBoundaryType.DASHED_LINE
            boundaries.append(lane_boundary(100 + 10 * s + k, x, np.full_like(x, y), kind))
        for k, y in enumerate((Y_LEFT, Y_MIDDLE, Y_RIGHT)):
            predecessor = 10 * (s - 1) + k if s > 0 else None
            successor = 10 * (s + 1) + k if s < len(sections) - 1 else None
            boundary_ids = (100 + 10 * s + k, 100 + 10 * s + k + 1)
            lanes.append(
                lane(10 * s + k, x, np.full_like(x, y), boundary_ids, predecessor=predecessor, successor=successor)
            )

    x_ramp = sample_x(X_START, X_JOIN)
    y_ramp = ramp_centre(x_ramp)[0]
    boundaries.append(lane_boundary(130, x_ramp, y_ramp + LANE_WIDTH / 2, LaneBoundaryType.SOLID_LINE))
    boundaries.append(lane_boundary(131, x_ramp, y_ramp - LANE_WIDTH / 2, LaneBoundaryType.SOLID_LINE))
    lanes.append(lane(30, x_ramp, y_ramp, (130, 131), LaneSubtype.ONRAMP, successor=31))

    x_acc = sample_x(X_JOIN, X_TAPER_END)
    closing = np.clip((x_acc - X_ACC_END) / (X_TAPER_END - X_ACC_END), 0.0, 1.0)
    right_edge = Y_ACC - LANE_WIDTH / 2 + LANE_WIDTH * closing
    left_edge = np.full_like(x_acc, Y_ACC + LANE_WIDTH / 2)
    boundaries.append(lane_boundary(132, x_acc, right_edge, LaneBoundaryType.SOLID_LINE))
    lanes.append(lane(31, x_acc, (left_edge + right_edge) / 2, (113, 132), LaneSubtype.ENTRY, predecessor=30))
    return omega_prime.MapOsi.create(betterosi.GroundTruth(lane_boundary=boundaries, lane=lanes))


# --- entry point -------------------------------------------------------------------------
def write_recording(path: Path) -> omega_prime.Recording:
    """Build, check and write the scenario to ``path`` (an ``.mcap`` file)."""
    df = build_table()
    check_no_overlap(df)
    recording = omega_prime.Recording(df, map=build_map(), validate=True, host_vehicle_idx=0)
    path.parent.mkdir(parents=True, exist_ok=True)
    with real_heights():
        recording.to_mcap(path)
    return recording


@contextmanager
def real_heights():
    """Write each object's own height into the MCAP file.

    omega-prime 0.3.7's ``Recording.get_moving_object_ground_truth`` (which ``to_mcap`` calls once per frame)
    builds each object's ``Dimension3D`` with ``height=row["width"]``. While this context is open, each
    object's height in the frame's ground truth is set from the table's ``height`` column after the fact. Remove
    this once omega-prime writes heights itself (the check in ``main`` then still passes).
    """
    original = omega_prime.Recording.get_moving_object_ground_truth

    def with_heights(nanos, df, host_vehicle_idx=None, validate=False):
        ground_truth = original(nanos, df, host_vehicle_idx=host_vehicle_idx, validate=validate)
        heights = dict(zip(df["idx"].to_list(), df["height"].to_list(), strict=True))
        for moving in ground_truth.moving_object:
            moving.base.dimension.height = heights[moving.id.value]
        return ground_truth

    omega_prime.Recording.get_moving_object_ground_truth = staticmethod(with_heights)
    try:
        yield
    finally:
        omega_prime.Recording.get_moving_object_ground_truth = staticmethod(original)


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """Command-line options."""
    default = Path(__file__).resolve().parent.parent / "highway_merge.mcap"
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=default, help=f"output file (default: {default})")
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> None:
    """Write the scenario and print a one-line summary."""
    path = parse_args(argv).output
    recording = write_recording(path)
    df = recording.df
    written = omega_prime.Recording.from_file(path)._df.group_by("idx").agg(pl.col("height").first()).sort("idx")
    expected = df.group_by("idx").agg(pl.col("height").first()).sort("idx")
    if not written.equals(expected):
        raise SystemExit(f"{path}: the heights read back are not the scenario's: {written.rows()}")
    print(f"wrote {path}: {df['total_nanos'].n_unique()} frames, {df['idx'].n_unique()} objects")


if __name__ == "__main__":
    main()
