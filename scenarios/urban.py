"""A synthetic town junction: buildings with courtyards and L-shapes, about 250 road users, queues at a signal,
parked cars and buses along the kerbs, pedestrians on the sidewalks.

Made for what the highway scene cannot show: occlusion in town, where buildings, parked buses and queued cars hide
pedestrians and cross traffic. Everything is closed-form and seeded, so every run gives the same table.

Layout (metres, x east, y north): two streets cross at the origin, each with two lanes per direction (3.5 m), a
parking strip (2.5 m) and a sidewalk (3 m) on either side; the junction is 2 x (7 + 2.5) = 19 m wide. Four city
blocks fill the quadrants beyond the sidewalks, each with a courtyard building (a polygon with a hole), an L-shaped
building and a row of plain ones, with gaps between them. A signal gives the east-west street green for the first
half of the recording and the north-south street for the second; a phase starts only once the last vehicle of the
other has left the junction.

Road users (``idx`` in this order):

* 0: the ego car, third in the eastbound queue on the inner lane (it waits, then drives through);
* queued cars on both lanes of the four approaches (``QUEUE`` each lane), leaving one after the other at green;
* parked cars and buses in the parking strips (standing, ``type`` vehicle, buses with their OSI subtype);
* pedestrians walking along the sidewalks, away from the junction (1.2 to 1.6 m/s).

Run from the repository root::

    uv run python scenarios/urban.py -o urban.parquet       # the object table (and urban.buildings.wkt)
    uv run python scenarios/urban.py -o urban.mcap          # an omega-prime MCAP file of OSI ground truth

From Python, :func:`urban_scene` returns the object table (omega-prime's columns) and the buildings (shapely
polygons, metres), e.g. ``get_visibility_df(table, 0, buildings)``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import polars as pl
import shapely

LANE = 3.5
PARKING = 2.5
SIDEWALK = 3.0
HALF_ROAD = 2 * LANE + PARKING  # from a street's centre line to the kerb
BLOCK_START = HALF_ROAD + SIDEWALK  # from a street's centre line to the buildings' fronts
STOP_LINE = HALF_ROAD + 1.0  # queues wait behind this distance from the junction's centre
QUEUE = 13  # vehicles queued per approach lane
GAP = 7.5  # metres between queued vehicles' centres
DEPARTURE = 1.2  # seconds between two queued vehicles leaving
SPEED = 9.0  # m/s through town
FRAMES, PERIOD = 600, 100_000_000  # 60 s at 10 Hz
CAR, PEDESTRIAN = 2, 3  # omega-prime (OSI) types
SUBTYPES = {"car": 4, "bus": 12, "van": 6}
SIZES = {"car": (4.5, 1.8, 1.5), "van": (5.2, 2.0, 2.4), "bus": (12.0, 2.55, 3.1), "pedestrian": (0.5, 0.5, 1.75)}


def buildings() -> list[shapely.Polygon]:
    """The buildings of the four blocks: per block a courtyard building, an L-shaped one and plain ones."""
    out = []
    for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):

        def place(x0, y0, x1, y1, sx=sx, sy=sy):  # a box in block coordinates (distances from the streets)
            xs, ys = sorted((sx * x0, sx * x1)), sorted((sy * y0, sy * y1))
            return shapely.box(xs[0], ys[0], xs[1], ys[1])

        b = BLOCK_START
        courtyard = place(b, b, b + 30, b + 26).difference(place(b + 8, b + 7, b + 22, b + 19))
        l_shape = shapely.union(place(b + 34, b, b + 60, b + 10), place(b + 50, b, b + 60, b + 28))
        out += [shapely.Polygon(courtyard.exterior, list(courtyard.interiors)), l_shape]
        for k in range(3):  # plain buildings along the other street, with gaps
            out.append(place(b, b + 32 + 14 * k, b + 12, b + 42 + 14 * k))
    return [shapely.geometry.polygon.orient(g, 1.0) for g in out]


def building_heights(blocks: list[shapely.Polygon]) -> list[float]:
    """Heights (metres) of the buildings, in the order :func:`buildings` gives them: courtyard blocks of 18 m,
    L-shaped ones of 15 m, and the plain ones of 9, 12 and 21 m (town houses, offices), so that some rise over
    their neighbours and a raised sensor sees over the low ones."""
    out = []
    for k in range(len(blocks)):
        place = k % 5
        out.append((18.0, 15.0, 9.0, 12.0, 21.0)[place])
    return out


def _row(idx, t, x, y, yaw, kind, vx=0.0, vy=0.0):
    length, width, height = SIZES[kind]
    is_pedestrian = kind == "pedestrian"
    return {
        "idx": idx, "t": t, "x": x, "y": y, "z": height / 2, "yaw": yaw, "vel_x": vx, "vel_y": vy, "length": length,
        "width": width, "height": height, "type": PEDESTRIAN if is_pedestrian else CAR,
        "subtype": -1 if is_pedestrian else SUBTYPES[kind], "role": -1 if is_pedestrian else 0,
    }  # fmt: skip


def _approaches() -> list[tuple[np.ndarray, np.ndarray, float]]:
    """Per approach lane: its direction (unit vector of travel), the lateral offset of its centre, and its
    phase (0: east-west, 1: north-south)."""
    out = []
    for direction, phase in (((1.0, 0.0), 0), ((-1.0, 0.0), 0), ((0.0, 1.0), 1), ((0.0, -1.0), 1)):
        d = np.array(direction)
        right = np.array([d[1], -d[0]])  # driving on the right
        for lane in (0.5, 1.5):  # inner and outer lane
            out.append((d, right * lane * LANE, phase))
    return out


def urban_scene(frames: int = FRAMES, seed: int = 7) -> tuple[pl.DataFrame, list[shapely.Polygon]]:
    """The object table (omega-prime's columns: ``frame, total_nanos, idx, x, y, z, yaw, length, width, height,
    type, subtype, role, vel_x, vel_y``, with ``roll, pitch`` 0) and the buildings."""
    rng = np.random.default_rng(seed)
    t = np.arange(frames) * PERIOD / 1e9
    lanes = _approaches()
    clear = (STOP_LINE + 2 * HALF_ROAD + 10.0) / SPEED  # seconds a leaving vehicle needs to clear the junction
    green = [0.0, (QUEUE - 1) * DEPARTURE + (QUEUE * GAP) / SPEED + clear]  # the second phase after the first cleared
    rows: list[dict] = []
    idx = 1
    for lane_number, (d, offset, phase) in enumerate(lanes):
        for k in range(QUEUE):
            ego = lane_number == 0 and k == 2
            kind = "van" if rng.random() < 0.15 else "car"
            behind = STOP_LINE + SIZES[kind][0] / 2 + k * GAP  # distance before the junction's centre
            leave = green[phase] + 2.0 + k * DEPARTURE
            travelled = SPEED * np.clip(t - leave, 0.0, None)
            along = -behind + travelled
            me = 0 if ego else idx
            yaw = float(np.arctan2(d[1], d[0]))
            moving = t > leave
            for f in range(frames):
                p = offset + d * along[f]
                v = d * (SPEED if moving[f] else 0.0)
                rows.append(_row(me, f, p[0], p[1], yaw, kind, v[0], v[1]))
            if not ego:
                idx += 1
    # parked vehicles in the parking strips, beyond the junction, with gaps; a bus every few
    for d, _, _ in lanes[::2]:
        right = np.array([d[1], -d[0]])
        kerb = right * (2 * LANE + PARKING / 2)
        s = HALF_ROAD + 6.0
        while s < 110.0:
            kind = "bus" if rng.random() < 0.18 else "car"
            length = SIZES[kind][0]
            p = kerb + d * (s + length / 2)
            yaw = float(np.arctan2(d[1], d[0]))
            rows += [_row(idx, f, p[0], p[1], yaw, kind) for f in range(frames)]
            idx += 1
            s += length + rng.uniform(1.5, 6.0)
    # pedestrians on the sidewalks, walking along the street away from the junction (they never cross a street):
    # on each half of each sidewalk five walking lines 0.55 m apart, three pedestrians per line at one pace
    for street in ("x", "y"):
        for side in (1.0, -1.0):
            for outward in (1.0, -1.0):
                for slot in range(5):
                    lateral = side * (HALF_ROAD + SIDEWALK / 2) + (slot - 2) * 0.55
                    pace = rng.uniform(1.2, 1.6)
                    first = rng.uniform(HALF_ROAD + 2.0, 60.0)
                    second = first + rng.uniform(3.0, 15.0)
                    for start in (first, second, second + rng.uniform(3.0, 15.0)):
                        along = outward * (start + pace * t)
                        vx, vy = (outward * pace, 0.0) if street == "x" else (0.0, outward * pace)
                        yaw = float(np.arctan2(vy, vx))
                        for f in range(frames):
                            x, y = (along[f], lateral) if street == "x" else (lateral, along[f])
                            rows.append(_row(idx, f, x, y, yaw, "pedestrian", vx, vy))
                        idx += 1
    table = (
        pl.DataFrame(rows)
        .with_columns(
            frame=pl.col("t").cast(pl.Int64),
            total_nanos=pl.col("t").cast(pl.Int64) * PERIOD,
            roll=pl.lit(0.0),
            pitch=pl.lit(0.0),
        )
        .drop("t")
        .sort("frame", "idx")
    )
    columns = ["frame", "total_nanos", "idx", "x", "y", "z", "yaw", "pitch", "roll", "length", "width", "height"]
    columns += ["vel_x", "vel_y", "type", "subtype", "role"]
    return table.select(columns), buildings()


def check_no_overlap(table: pl.DataFrame, blocks: list[shapely.Polygon], every: int = 20) -> None:
    """Raise if two road users overlap, or one stands in a building, in any ``every``-th frame."""
    from omega_prime_visibility.geometry.rings import box_rings

    union = shapely.union_all(blocks)
    for (frame,), rows in table.filter(pl.col("frame") % every == 0).group_by("frame"):
        rings = box_rings(*(rows[c].to_numpy() for c in ("x", "y", "length", "width", "yaw")))
        shapes = [shapely.Polygon(rings.ring(k)) for k in range(len(rows))]
        tree = shapely.STRtree(shapes)
        left, right = tree.query(shapes, predicate="intersects")
        pairs = [
            (a, b) for a, b in zip(left, right, strict=True) if a < b and shapes[a].intersection(shapes[b]).area > 1e-6
        ]
        if pairs:
            a, b = pairs[0]
            raise AssertionError(f"frame {frame}: idx {rows['idx'][int(a)]} and {rows['idx'][int(b)]} overlap")
        inside = [k for k, s in enumerate(shapes) if s.intersection(union).area > 1e-6]
        if inside:
            raise AssertionError(f"frame {frame}: idx {rows['idx'][inside[0]]} stands in a building")


def write_mcap(table: pl.DataFrame, path: Path, host: int = 0) -> None:
    """Write ``table`` as an omega-prime MCAP file: one ``osi3.GroundTruth`` a frame on the ``ground_truth`` topic,
    written with ASAM's OSI messages (omega-prime's own writer cannot write a pedestrian, whose vehicle role it
    sets to -1); a vehicle classification for vehicles only, every field omega-prime reads set."""
    from mcap_protobuf.writer import Writer
    from osi3.osi_groundtruth_pb2 import GroundTruth

    with open(path, "wb") as f:
        writer = Writer(f)
        for (nanos,), rows in table.sort("total_nanos", "idx").group_by("total_nanos", maintain_order=True):
            truth = GroundTruth()
            truth.timestamp.seconds, truth.timestamp.nanos = divmod(int(nanos), 1_000_000_000)
            truth.host_vehicle_id.value = host
            for r in rows.iter_rows(named=True):
                moving = truth.moving_object.add()
                moving.id.value, moving.type, base = r["idx"], r["type"], moving.base
                base.position.x, base.position.y, base.position.z = r["x"], r["y"], r["z"]
                base.dimension.length, base.dimension.width, base.dimension.height = (
                    r["length"],
                    r["width"],
                    r["height"],
                )
                base.orientation.roll, base.orientation.pitch, base.orientation.yaw = r["roll"], r["pitch"], r["yaw"]
                base.velocity.x, base.velocity.y, base.velocity.z = r["vel_x"], r["vel_y"], 0.0
                base.acceleration.x, base.acceleration.y, base.acceleration.z = 0.0, 0.0, 0.0
                if r["type"] == CAR:
                    moving.vehicle_classification.type = r["subtype"]
                    moving.vehicle_classification.role = max(r["role"], 0)
            writer.write_message("ground_truth", truth, log_time=int(nanos), publish_time=int(nanos))
        writer.finish()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "-o", "--output", type=Path, default=Path("urban.parquet"), help="the object table (.parquet or .mcap)"
    )
    args = parser.parse_args()
    table, blocks = urban_scene()
    check_no_overlap(table, blocks)
    if args.output.suffix == ".mcap":
        write_mcap(table, args.output)
    else:
        table.write_parquet(args.output)
    wkt = args.output.with_suffix(".buildings.wkt")
    wkt.write_text("".join(f"{g.wkt}\n" for g in blocks))
    heights = args.output.with_suffix(".heights.json")
    heights.write_text(json.dumps(building_heights(blocks)))
    per_frame = table.filter(pl.col("frame") == 0).height
    print(f"wrote {args.output} ({table.height} rows, {per_frame} road users per frame) and {wkt} ({len(blocks)})")


if __name__ == "__main__":
    main()
