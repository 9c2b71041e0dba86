"""The lanes of an OSI ground truth as omega-prime's ``MapOsiCenterline`` has them (centre lines only), decoded
with ASAM's ``osi-python`` without importing omega-prime: what a picture draws of a recording whose MCAP file
carries no OpenDRIVE map (importing omega-prime for them took 2.5 s of a first picture)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely


@dataclass(frozen=True)
class CentreLine:
    """One lane: its centre line (metres, the driving direction), as ``LaneOsiCenterline.centerline``."""

    centerline: shapely.LineString


@dataclass(frozen=True)
class CentreLines:
    """A ground truth's lanes by OSI lane id, as ``MapOsiCenterline.lanes`` holds them (centre lines only)."""

    lanes: dict[int, CentreLine]


def centre_lines(ground_truth: bytes) -> CentreLines | None:
    """The lanes of one serialised ``osi3.GroundTruth`` message, or None if it has none (omega-prime then has no
    map either).

    Examples
    --------
    >>> from osi3.osi_groundtruth_pb2 import GroundTruth
    >>> gt = GroundTruth()
    >>> lane = gt.lane.add()
    >>> lane.id.value = 7
    >>> for x in (0.0, 10.0, 20.0):
    ...     point = lane.classification.centerline.add()
    ...     point.x, point.y = x, 1.5
    >>> centre_lines(gt.SerializeToString()).lanes[7].centerline.coords[-1]  # not the driving direction: reversed
    (0.0, 1.5)
    >>> centre_lines(GroundTruth().SerializeToString()) is None
    True
    """
    from osi3.osi_groundtruth_pb2 import GroundTruth  # type: ignore[import-not-found]

    message = GroundTruth.FromString(ground_truth)
    if len(message.lane) == 0:
        return None
    lanes = {}
    for lane in message.lane:
        points = np.array([(p.x, p.y) for p in lane.classification.centerline], dtype=np.float64).reshape(-1, 2)
        if not lane.classification.centerline_is_driving_direction:
            points = points[::-1]
        try:
            lanes[int(lane.id.value)] = CentreLine(shapely.LineString(points))
        except (ValueError, shapely.errors.GEOSException):  # a centre line of one point: omega-prime reads no map
            return None
    return CentreLines(lanes)
