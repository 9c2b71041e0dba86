"""Which of two convex bodies an eye meets first, direction by direction, drawn on the faces of the cube around the
eye (:mod:`.cube`): exact also for bodies that overlap (a double detection, a railing through a car).

Bodies are given relative to the eye, as :class:`.bodies.ConvexBodies` (``normals . x <= offsets``, metres). A face
plane that the eye lies outside of (``offset < 0``) faces the eye; along every direction ``d`` that meets the body,
each such plane has ``normal . d < 0`` (else the ray could never enter its half-space), and the ray enters the body
at ``t = max over those planes of offset / (normal . d)``. So body ``B`` is entered before body ``A`` along ``d``
exactly when, for some plane ``a`` of ``A`` and every plane ``b`` of ``B``, ``offset_b / (normal_b . d) <
offset_a / (normal_a . d)``; both denominators being negative, that is the linear condition
``(offset_b normal_a - offset_a normal_b) . d < 0``: a half-plane on each cube face. The region where ``B`` is in
front of ``A`` is therefore a union of convex polygons, exactly.

Ties are visible, by the rule of the 2D engines (:mod:`..geometry.occlusion`): where two face planes are nearly
parallel (the sine of the angle between their normals under ``TIE_PARALLEL``), ``B`` is in front only where it is
entered nearer by more than ``RELATIVE_TOLERANCE`` of the distance, ``offset_b / (normal_b . d) < (1 -
RELATIVE_TOLERANCE) offset_a / (normal_a . d)``; so the shared face plane of a double detection, or the roofs of two
cars of equal height, hide nothing of each other, and each body is the first thing hit there. Planes at a wider
angle (the faces meeting at an edge or corner two bodies share) are ordered exactly.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..geometry.occlusion import RELATIVE_TOLERANCE, TIE_PARALLEL
from .bodies import ConvexBodies
from .cube import FACES, clip_plane

SQUARE = 1.5
"""Half the side of the square drawn for a whole half-plane: beyond the cube face's own square [-1, 1]²."""


def nearest_bound(bodies: ConvexBodies) -> np.ndarray:
    """A lower bound (metres) of the distance from the origin to each body: its farthest face plane that the
    origin lies outside of (exact where the nearest point lies inside that face)."""
    return np.maximum(-bodies.offsets, 0.0).max(axis=1, initial=0.0)


def nearest(bodies: ConvexBodies, which: np.ndarray) -> np.ndarray:
    """Distance (metres) from the origin to the nearest point of each body ``which`` (convex polytopes: the
    nearest point lies on a face, an edge or at a vertex)."""
    out = np.full(len(which), np.inf)
    for k, b in enumerate(which):
        ids = np.flatnonzero(bodies.vertex_body == b)
        points = bodies.vertices[ids]
        best = float(np.linalg.norm(points, axis=1).min())
        edges = bodies.edges[bodies.edge_body == b]
        if len(edges):
            a, c = bodies.vertices[edges[:, 0]], bodies.vertices[edges[:, 1]]
            d = c - a
            t = np.clip(-(a * d).sum(1) / np.maximum((d * d).sum(1), 1e-300), 0.0, 1.0)
            best = min(best, float(np.linalg.norm(a + t[:, None] * d, axis=1).min()))
        for p in range(bodies.normals.shape[1]):
            c = bodies.offsets[b, p]
            normal = bodies.normals[b, p]
            if c >= 0 or not normal.any():
                continue
            foot = c * normal  # the plane's nearest point: on the face if inside every other plane
            if (bodies.normals[b] @ foot <= bodies.offsets[b] + 1e-9).all():
                best = min(best, -c)
        out[k] = best
    return out


def facing_planes(bodies: ConvexBodies, body: int) -> tuple[np.ndarray, np.ndarray]:
    """Normals (k, 3) and offsets (k,) of the face planes of ``body`` that the eye (the origin) lies outside of."""
    normals, offsets = bodies.normals[body], bodies.offsets[body]
    facing = (offsets < 0) & normals.any(axis=1)
    return normals[facing], offsets[facing]


def tie_factors(normals_a: np.ndarray, normals_b: np.ndarray) -> np.ndarray:
    """Per pair of face planes (rows of ``normals_a`` (k, 3) and ``normals_b`` (m, 3)), the factor of the target's
    entry distance that the blocker's must be below to be in front: ``1 - RELATIVE_TOLERANCE`` for nearly parallel
    planes (they tie where they nearly coincide), 1 for the others (ordered exactly).

    >>> tie_factors(np.array([[-1.0, 0, 0]]), np.array([[-1.0, 0, 0], [0, -1.0, 0]])).tolist()
    [[0.999999999, 1.0]]
    """
    cross = np.cross(normals_a[:, None, :], normals_b[None, :, :])
    lengths = (normals_a * normals_a).sum(1)[:, None] * (normals_b * normals_b).sum(1)[None, :]
    nearly_parallel = (cross * cross).sum(2) <= TIE_PARALLEL * TIE_PARALLEL * lengths
    return np.where(nearly_parallel, 1.0 - RELATIVE_TOLERANCE, 1.0)


def entered_before(bodies: ConvexBodies, blocker: int, target: int, face: int) -> shapely.Geometry:
    """The directions on cube face ``face`` (its ``(u, v)`` coordinates) along which ``blocker`` is entered before
    ``target``, wherever both are met (intersect it with both silhouettes); see the module docstring.

    Examples
    --------
    Two 2 m planks crossing in an X 10 m ahead (x = 10), seen on the cube face +x (``u = y / x``): plank 0 runs
    from (9, -1) to (11, 1), plank 1 from (11, -1) to (9, 1); left of the crossing (y > 0) plank 1 is nearer.

    >>> from omega_prime_visibility.threed.bodies import bodies_from_boxes
    >>> planks = np.array([[10, 0, 0, 2.83, 0.02, 2, 0, 0, np.pi / 4], [10, 0, 0, 2.83, 0.02, 2, 0, 0, -np.pi / 4]])
    >>> bodies = bodies_from_boxes(planks)
    >>> region = entered_before(bodies, 1, 0, 0).intersection(shapely.box(-0.2, -0.2, 0.2, 0.2))
    >>> [round(v, 6) for v in region.bounds]
    [0.0, -0.2, 0.2, 0.2]
    """
    normals_a, offsets_a = facing_planes(bodies, target)
    normals_b, offsets_b = facing_planes(bodies, blocker)
    # the square lifted to (1, u, v): its direction is FACES[face].T @ (1, u, v)
    square = np.array([[1.0, -SQUARE, -SQUARE], [1.0, SQUARE, -SQUARE], [1.0, SQUARE, SQUARE], [1.0, -SQUARE, SQUARE]])
    pieces = []
    keep = tie_factors(normals_a, normals_b)
    for a, (normal_a, offset_a) in enumerate(zip(normals_a, offsets_a, strict=True)):
        polygon = square
        for b, (normal_b, offset_b) in enumerate(zip(normals_b, offsets_b, strict=True)):
            # w . d > 0: entered through b before (keep times) the entry through a
            w = keep[a, b] * offset_a * normal_b - offset_b * normal_a
            polygon = clip_plane(polygon, FACES[face] @ w)
            if len(polygon) < 3:
                break
        if len(polygon) >= 3:
            pieces.append(shapely.Polygon(polygon[:, 1:]))
    return shapely.union_all(pieces) if pieces else shapely.Polygon()
