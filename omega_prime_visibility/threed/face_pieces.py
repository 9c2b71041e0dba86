"""The exact 3D engine's common case in compiled loops: on one cube face (:mod:`.cube`), every body's silhouette,
and every target's silhouette minus the directions along which other bodies are entered first, as disjoint convex
pieces measured in steradians.

The same geometry as the polygon path of :func:`..engines.silhouette3d.convex_visibility` (which takes a face
whose buffers overflow, and the pictures' pieces), drawn with convex clipping (:mod:`..geometry.convex_clip`):

- a silhouette is the convex hull of a body's vertices in the face's frustum, its edges' crossings of the
  frustum's four planes and the face's corners the body covers;
- a body wholly nearer than the target (its farthest vertex before the target's nearest point, by the tie rule's
  margin) hides its whole silhouette; one whose depths overlap the target's hides, for each face plane of the
  target turned to the eye, the convex region where every face plane of the body turned to the eye is entered
  before it (:mod:`.order`), each within the body's silhouette;
- a body is an occluder of the target where what it hides of the target's silhouette exceeds
  :data:`.cube.MIN_SOLID_ANGLE`, and only then is it subtracted.

Coordinates are the face's ``(u, v)`` (:mod:`.cube`), the eye at the origin, metres for the bodies.
"""

from __future__ import annotations

import math

import numpy as np

from .._compiled.kernel import njit
from ..geometry.convex_clip import clip_convex, clip_half_plane, convex_hull, drop_repeats, subtract
from ..geometry.kernels import copy_rows, push_pair, reserve, reserve_rows
from ..geometry.occlusion import RELATIVE_TOLERANCE, TIE_PARALLEL
from .cube import MIN_SOLID_ANGLE
from .order import SQUARE

MAX_PIECES = 512
"""Convex pieces one target's visible part may be cut into before the polygon path takes the face."""
MAX_VERTICES = 64
"""Vertices of one silhouette or piece at most (a box's silhouette has at most 6 plus the face's edges)."""
VISIBLE, HIDDEN = 0, 1
"""Kinds of the pieces :func:`face_pieces` hands back: a target's visible part, or what one occluder hides of it."""


@njit(cache=True, inline="always")
def _edge_term(u0, v0, u1, v1):
    """Signed solid angle (steradians) of the triangle (face centre, a, b) on a face at distance 1."""
    nb, nc = math.sqrt(u0 * u0 + v0 * v0 + 1.0), math.sqrt(u1 * u1 + v1 * v1 + 1.0)
    return 2.0 * math.atan2(u0 * v1 - v0 * u1, nb * nc + nb + nc + u0 * u1 + v0 * v1 + 1.0)


@njit(cache=True)
def polygon_solid_angle(poly, n):
    """Solid angle (steradians) of the polygon ``poly[:n]`` in face coordinates (either orientation).

    >>> square = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    >>> round(polygon_solid_angle(square, 4) / (4 * math.pi / 6), 12)
    1.0
    """
    total = 0.0
    for i in range(n):
        j = (i + 1) % n
        total += _edge_term(poly[i, 0], poly[i, 1], poly[j, 0], poly[j, 1])
    return abs(total)


@njit(cache=True, inline="always")
def _enters(normals, offsets, b, x, y, z):
    """Whether the ray from the origin along ``(x, y, z)`` meets body ``b`` (planes ``normals . p <= offsets``)."""
    t0, t1 = 0.0, math.inf
    for p in range(normals.shape[1]):
        nd = normals[b, p, 0] * x + normals[b, p, 1] * y + normals[b, p, 2] * z
        c = offsets[b, p]
        if nd < 0.0:
            t0 = max(t0, c / nd)
        elif nd > 0.0:
            t1 = min(t1, c / nd)
        elif c < 0.0:
            return False
    return t0 <= t1


@njit(cache=True)
def face_silhouettes(vertices, vertex_start, edges, edge_start, normals, offsets, face, out, counts, angles):
    """Every body's silhouette on cube face ``face`` (its rows forward, eu, ev) into ``out[b, :counts[b]]``
    (counter-clockwise, face coordinates; count 0 where it is not seen through the face) and its solid angle into
    ``angles``; the bodies' vertices ``vertices[vertex_start[b]:vertex_start[b + 1]]`` and edges likewise,
    relative to the eye. False where a silhouette has more than ``out.shape[1]`` vertices."""
    n = len(vertex_start) - 1
    fx, fy, fz = face[0, 0], face[0, 1], face[0, 2]
    ex, ey, ez = face[1, 0], face[1, 1], face[1, 2]
    gx, gy, gz = face[2, 0], face[2, 1], face[2, 2]
    most = 4
    for b in range(n):
        most = max(most, vertex_start[b + 1] - vertex_start[b] + 4 * (edge_start[b + 1] - edge_start[b]) + 4)
    points = np.empty((most, 2))
    hull = np.empty((2 * most, 2))
    for b in range(n):
        k = 0
        for i in range(vertex_start[b], vertex_start[b + 1]):
            x, y, z = vertices[i, 0], vertices[i, 1], vertices[i, 2]
            d, u, v = x * fx + y * fy + z * fz, x * ex + y * ey + z * ez, x * gx + y * gy + z * gz
            tol = 1e-12 * max(abs(d), 1.0)
            if d > 0.0 and abs(u) <= d + tol and abs(v) <= d + tol:
                points[k, 0], points[k, 1] = u / d, v / d
                k += 1
        for e in range(edge_start[b], edge_start[b + 1]):
            a, c = edges[e, 0], edges[e, 1]
            xa, ya, za = vertices[a, 0], vertices[a, 1], vertices[a, 2]
            xc, yc, zc = vertices[c, 0], vertices[c, 1], vertices[c, 2]
            da, ua, va = xa * fx + ya * fy + za * fz, xa * ex + ya * ey + za * ez, xa * gx + ya * gy + za * gz
            dc, uc, vc = xc * fx + yc * fy + zc * fz, xc * ex + yc * ey + zc * ez, xc * gx + yc * gy + zc * gz
            for s in range(4):  # the frustum's planes d - u, d + u, d - v, d + v
                if s == 0:
                    ga, gc = da - ua, dc - uc
                elif s == 1:
                    ga, gc = da + ua, dc + uc
                elif s == 2:
                    ga, gc = da - va, dc - vc
                else:
                    ga, gc = da + va, dc + vc
                if ga * gc < 0.0:
                    t = ga / (ga - gc)
                    dd, uu, vv = da + t * (dc - da), ua + t * (uc - ua), va + t * (vc - va)
                    if dd > 0.0 and abs(uu) <= dd * (1 + 1e-9) and abs(vv) <= dd * (1 + 1e-9):
                        points[k, 0] = min(max(uu / dd, -1.0), 1.0)
                        points[k, 1] = min(max(vv / dd, -1.0), 1.0)
                        k += 1
        for cu, cv in ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)):
            if _enters(normals, offsets, b, fx + cu * ex + cv * gx, fy + cu * ey + cv * gy, fz + cu * ez + cv * gz):
                points[k, 0], points[k, 1] = cu, cv
                k += 1
        counts[b], angles[b] = 0, 0.0
        if k < 3:
            continue
        m = drop_repeats(hull, convex_hull(points, k, hull))
        if m < 3:
            continue
        angle = polygon_solid_angle(hull, m)
        if angle <= MIN_SOLID_ANGLE:
            continue
        if m > out.shape[1]:
            return False
        copy_rows(out[b], 0, hull[:m])
        counts[b], angles[b] = m, angle
    return True


@njit(cache=True)
def _tie_factor(normals, a, pa, b, pb):
    """``1 - RELATIVE_TOLERANCE`` where face plane ``pa`` of body ``a`` and ``pb`` of ``b`` are nearly parallel
    (they tie where they nearly coincide), else 1 (:func:`.order.tie_factors`)."""
    ax, ay, az = normals[a, pa, 0], normals[a, pa, 1], normals[a, pa, 2]
    bx, by, bz = normals[b, pb, 0], normals[b, pb, 1], normals[b, pb, 2]
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    lengths = (ax * ax + ay * ay + az * az) * (bx * bx + by * by + bz * bz)
    if cx * cx + cy * cy + cz * cz <= TIE_PARALLEL * TIE_PARALLEL * lengths:
        return 1.0 - RELATIVE_TOLERANCE
    return 1.0


@njit(cache=True)
def entered_before(normals, offsets, blocker, target, face, silhouette, k, fronts, front_counts, scratch):
    """The directions on the face where ``blocker`` is entered before ``target`` (:func:`.order.entered_before`),
    within the blocker's ``silhouette[:k]``, as convex pieces into ``fronts``/``front_counts``; their number, -1
    on overflow."""
    made = 0
    a_buf, b_buf = scratch[0], scratch[1]
    for pa in range(normals.shape[1]):
        oa = offsets[target, pa]
        if not (oa < 0.0) or (normals[target, pa, 0] == 0.0 and normals[target, pa, 1] == 0.0
                              and normals[target, pa, 2] == 0.0):  # fmt: skip
            continue
        a_buf[0, 0], a_buf[0, 1] = -SQUARE, -SQUARE
        a_buf[1, 0], a_buf[1, 1] = SQUARE, -SQUARE
        a_buf[2, 0], a_buf[2, 1] = SQUARE, SQUARE
        a_buf[3, 0], a_buf[3, 1] = -SQUARE, SQUARE
        m = 4
        for pb in range(normals.shape[1]):
            ob = offsets[blocker, pb]
            if not (ob < 0.0) or (normals[blocker, pb, 0] == 0.0 and normals[blocker, pb, 1] == 0.0
                                  and normals[blocker, pb, 2] == 0.0):  # fmt: skip
                continue
            keep = _tie_factor(normals, target, pa, blocker, pb)
            wx = keep * oa * normals[blocker, pb, 0] - ob * normals[target, pa, 0]
            wy = keep * oa * normals[blocker, pb, 1] - ob * normals[target, pa, 1]
            wz = keep * oa * normals[blocker, pb, 2] - ob * normals[target, pa, 2]
            m0 = face[0, 0] * wx + face[0, 1] * wy + face[0, 2] * wz
            m1 = face[1, 0] * wx + face[1, 1] * wy + face[1, 2] * wz
            m2 = face[2, 0] * wx + face[2, 1] * wy + face[2, 2] * wz
            m = clip_half_plane(a_buf, m, m0, m1, m2, b_buf)
            if m <= 0:
                break
            copy_rows(a_buf, 0, b_buf[:m])
        if m < 0:
            return -1
        if m < 3:
            continue
        if made >= len(fronts):
            return -1
        m = clip_convex(a_buf, m, silhouette, k, fronts[made], b_buf)
        if m < 0:
            return -1
        m = drop_repeats(fronts[made], m)
        if m >= 3:
            front_counts[made] = m
            made += 1
    return made


@njit(cache=True)
def _pieces_angle(pieces, counts, n):
    total = 0.0
    for p in range(n):
        total += polygon_solid_angle(pieces[p], counts[p])
    return total


@njit(cache=True)
def _hand_back(pieces, counts, n, owner, kind, xy, n_xy, starts, owners, kinds, n_out):
    """Append ``pieces[:n]`` to the flat output (coordinates, starts, owner and kind per piece)."""
    for p in range(n):
        c = counts[p]
        xy = reserve_rows(xy, n_xy, n_xy + c)
        copy_rows(xy, n_xy, pieces[p, :c])
        starts = reserve(starts, n_out, n_out + 2)
        owners = reserve(owners, n_out, n_out + 1)
        kinds = reserve(kinds, n_out, n_out + 1)
        starts[n_out], owners[n_out], kinds[n_out] = n_xy, owner, kind
        n_xy += c
        n_out += 1
        starts[n_out] = n_xy
    return xy, n_xy, starts, owners, kinds, n_out


@njit(cache=True)
def _bounds(silhouettes, counts):
    """Bounding box ``(u0, v0, u1, v1)`` of each silhouette (rows of bodies not seen: unset)."""
    box = np.empty((len(counts), 4))
    for b in range(len(counts)):
        c = counts[b]
        if c >= 3:
            box[b, 0], box[b, 1] = silhouettes[b, :c, 0].min(), silhouettes[b, :c, 1].min()
            box[b, 2], box[b, 3] = silhouettes[b, :c, 0].max(), silhouettes[b, :c, 1].max()
    return box


@njit(cache=True)
def _fronts(silhouettes, counts, normals, offsets, lower, farthest, face, body, target, fronts, front_counts,
            scratch):  # fmt: skip
    """The directions where ``body`` is entered before ``target``, as convex pieces into ``fronts``: its whole
    silhouette where it lies wholly nearer, none where the target does, else :func:`entered_before`; their number,
    -1 on overflow."""
    if farthest[body] < lower[target] * (1.0 - RELATIVE_TOLERANCE):  # nearer by the tie rule's margin
        copy_rows(fronts[0], 0, silhouettes[body, : counts[body]])
        front_counts[0] = counts[body]
        return 1
    if farthest[target] < lower[body]:
        return 0
    return entered_before(normals, offsets, body, target, face, silhouettes[body], counts[body], fronts,
                          front_counts, scratch)  # fmt: skip


@njit(cache=True)
def _hidden(shape, k, fronts, front_counts, i, hid, hc, spare, spare_counts, scratch):
    """``shape[:k] ∩ fronts[i]`` minus ``fronts[:i]``: what front ``i`` adds to the hidden part, as disjoint convex
    pieces; their number (-1 on overflow), the buffers holding them and the spare ones (swapped as used)."""
    m = clip_convex(shape, k, fronts[i], front_counts[i], hid[0], scratch[0])
    if m < 3:
        return min(m, 0), hid, hc, spare, spare_counts
    hc[0] = m
    n_hid = 1
    for j in range(i):
        n_hid = subtract(hid, hc, n_hid, fronts[j], front_counts[j], spare, spare_counts, scratch)
        if n_hid < 0:
            return -1, hid, hc, spare, spare_counts
        hid, spare, hc, spare_counts = spare, hid, spare_counts, hc
    return n_hid, hid, hc, spare, spare_counts


@njit(cache=True)
def face_pieces(silhouettes, counts, measured, live, wanted, normals, offsets, lower, farthest, face):
    """Each live target's visible solid angle on the face and its occluders.

    Parameters
    ----------
    silhouettes, counts : ndarray
        :func:`face_silhouettes` of every body.
    measured : ndarray of int, shape (m,)
        The targets' bodies.
    live, wanted : ndarray of bool, shape (m,)
        Targets to measure (the others read 0), and those whose pieces are handed back (to clip them to a window).
    normals, offsets : ndarray
        The bodies' face planes (:class:`.bodies.ConvexBodies`), relative to the eye.
    lower, farthest : ndarray, shape (n,)
        Metres: a lower bound of each body's distance (the targets' exact nearest distance) and its farthest
        vertex's.
    face : ndarray, shape (3, 3)
        The face's forward, eu and ev.

    Returns
    -------
    visible : ndarray, shape (m,)
        Steradians along which the target is the first thing hit, on this face.
    pair_target, pair_body : ndarray of int
        Occluders: body ``pair_body[k]`` hides more than MIN_SOLID_ANGLE of target ``pair_target[k]`` (a position
        in ``measured``).
    xy, starts, owners, kinds : ndarray
        The wanted targets' pieces: piece ``p`` is ``xy[starts[p]:starts[p + 1]]``; of kind VISIBLE, part of the
        visible directions of target ``owners[p]``; of kind HIDDEN, part of what occluder pair ``owners[p]`` hides.
    ok : bool
        False where a buffer would overflow (the caller takes the polygon path for the face).
    """
    m = len(measured)
    n = len(counts)
    visible = np.zeros(m)
    pt, pb = np.empty(16, np.int64), np.empty(16, np.int64)
    n_pairs = 0
    xy = np.empty((64, 2))
    starts = np.zeros(17, np.int64)
    owners, kinds = np.empty(16, np.int64), np.empty(16, np.int64)
    n_xy, n_out = 0, 0
    box = _bounds(silhouettes, counts)
    a = np.empty((MAX_PIECES, MAX_VERTICES, 2))
    other = np.empty((MAX_PIECES, MAX_VERTICES, 2))
    ac, oc = np.zeros(MAX_PIECES, np.int64), np.zeros(MAX_PIECES, np.int64)
    hid = np.empty((MAX_PIECES, MAX_VERTICES, 2))
    hid2 = np.empty((MAX_PIECES, MAX_VERTICES, 2))
    hc, hc2 = np.zeros(MAX_PIECES, np.int64), np.zeros(MAX_PIECES, np.int64)
    n_planes = normals.shape[1]
    fronts = np.empty((max(n_planes, 1), MAX_VERTICES, 2))
    front_counts = np.zeros(max(n_planes, 1), np.int64)
    scratch = np.empty((2, MAX_VERTICES, 2))
    fail = (visible, pt[:0], pb[:0], xy[:0], starts[:1], owners[:0], kinds[:0], False)
    for t in range(m):
        target = measured[t]
        kt = counts[target]
        if not live[t] or kt < 3:
            continue
        shape = silhouettes[target]
        copy_rows(a[0], 0, shape[:kt])
        ac[0] = kt
        n_pieces = 1
        for b in range(n):
            if b == target or counts[b] < 3:
                continue
            if box[b, 0] > box[target, 2] or box[b, 2] < box[target, 0] or box[b, 1] > box[target, 3] \
                    or box[b, 3] < box[target, 1]:  # fmt: skip
                continue
            n_fronts = _fronts(silhouettes, counts, normals, offsets, lower, farthest, face, b, target, fronts,
                               front_counts, scratch)  # fmt: skip
            if n_fronts < 0:
                return fail
            hidden = 0.0
            n_hid_start = n_out
            for i in range(n_fronts):  # what the body hides of the silhouette: disjoint pieces
                n_hid, hid, hc, hid2, hc2 = _hidden(shape, kt, fronts, front_counts, i, hid, hc, hid2, hc2, scratch)
                if n_hid < 0:
                    return fail
                hidden += _pieces_angle(hid, hc, n_hid)
                if wanted[t]:
                    xy, n_xy, starts, owners, kinds, n_out = _hand_back(hid, hc, n_hid, n_pairs, HIDDEN, xy, n_xy,
                                                                        starts, owners, kinds, n_out)  # fmt: skip
            if hidden <= MIN_SOLID_ANGLE:
                n_out = n_hid_start  # not an occluder: its pieces are dropped
                n_xy = starts[n_out]
                continue
            pt, pb, n_pairs = push_pair(pt, pb, n_pairs, t, b)
            for i in range(n_fronts):
                n_pieces = subtract(a, ac, n_pieces, fronts[i], front_counts[i], other, oc, scratch)
                if n_pieces < 0:
                    return fail
                a, other, ac, oc = other, a, oc, ac
        visible[t] = _pieces_angle(a, ac, n_pieces)
        if wanted[t]:
            xy, n_xy, starts, owners, kinds, n_out = _hand_back(a, ac, n_pieces, t, VISIBLE, xy, n_xy, starts,
                                                                owners, kinds, n_out)  # fmt: skip
    return visible, pt[:n_pairs], pb[:n_pairs], xy[:n_xy], starts[: n_out + 1], owners[:n_out], kinds[:n_out], True
