"""Adaptive sampling of a target's directions: patches, grids of rays, labels, and cells refined where they disagree.

Every (viewpoint, target) pair is a *slot*. A slot is sampled on one or more *patches*: planes at distance 1
from the eye (a central projection, so the target's directions form a convex polygon there and straight lines
stay straight), each with axes ``forward, u, v`` and a rectangle ``[u0, u1] x [v0, v1]`` that holds the target's
projected corners. A target seen within about 80° of its centre direction has one patch; one that wraps around the
eye (very near) is sampled on the faces of a cube around the eye, each patch around its part on that face.

Each patch starts as a grid of ``n x n`` cells (``(n + 1)^2`` rays, so at least ``n + 1`` rays across the target's
angular width and height however small or far it is). A ray that hits the target is labelled by what it meets
first (the target or the body in front of it) and whether it lies in the view and range; a cell whose
target-hitting corners disagree is split into four, up to a depth. Leaves are weighted by their exact solid angle
(the rectangle formula of the central projection) and counted by the share of their four corners that hit the
target, and that see it.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from ..._compiled.kernel import njit
from ...geometry.kernels import push_pair
from ...threed.bodies import bodies_from_boxes
from ...threed.boxes import _slab
from ...threed.cube import FACES, silhouettes

MISS = -1
"""Label of a ray that misses the target (it matches any label when cells are compared)."""


def patches(corners_rel: np.ndarray, centres_rel: np.ndarray, boxes_rel: np.ndarray) -> tuple[np.ndarray, ...]:
    """Sampling patches of targets seen from the origin.

    Parameters
    ----------
    corners_rel : ndarray, shape (m, 8, 3)
        Corners of the targets, relative to the eye, metres.
    centres_rel : ndarray, shape (m, 3)
        Their centres, relative to the eye.
    boxes_rel : ndarray, shape (m, 9)
        The targets as boxes (:mod:`...threed.boxes`), centres relative to the eye.

    Returns
    -------
    axes : ndarray, shape (p, 3, 3)
        ``forward, u, v`` of each patch (orthonormal).
    rect : ndarray, shape (p, 4)
        ``u0, u1, v0, v1`` on the patch's plane at distance 1.
    target : ndarray, shape (p,), int64
        Which of the ``m`` targets each patch samples.
    hull_offsets, hull_uv : ndarray
        CSR: the target's silhouette on each patch (the convex hull of its projected corners, or of its part on a
        cube face), counter-clockwise.
    """
    dist = np.linalg.norm(centres_rel, axis=1)
    forward = centres_rel / np.where(dist > 0, dist, 1.0)[:, None]
    side = np.cross(np.array([0.0, 0.0, 1.0]), forward)
    flat = np.linalg.norm(side, axis=1) < 1e-6
    side[flat] = np.cross(np.array([0.0, 1.0, 0.0]), forward[flat])
    side /= np.linalg.norm(side, axis=1)[:, None]
    up = np.cross(forward, side)
    depth = np.einsum("mkj,mj->mk", corners_rel, forward)
    reach = np.linalg.norm(corners_rel, axis=2).max(axis=1)
    good = (depth.min(axis=1) > 0.2 * reach) & (dist > 0)
    u = np.einsum("mkj,mj->mk", corners_rel, side) / np.where(good[:, None], depth, 1.0)
    v = np.einsum("mkj,mj->mk", corners_rel, up) / np.where(good[:, None], depth, 1.0)
    hull_offsets, hull_uv = convex_hulls(u[good], v[good])
    axes = [np.stack([forward[good], side[good], up[good]], axis=1)]
    rects = [np.stack([u.min(1), u.max(1), v.min(1), v.max(1)], axis=1)[good]]
    targets = [np.flatnonzero(good)]
    near = np.flatnonzero(~good)
    if len(near):  # wraps around the eye: its silhouette on each face of a cube around the eye
        faces = [silhouettes(bodies_from_boxes(boxes_rel[near]), f) for f in range(6)]
        extra_offsets, extra_uv = [], []
        at = len(hull_uv)
        for k, target in enumerate(near):
            for f in range(6):
                polygon = faces[f][k]
                if polygon is None:
                    continue
                ring = np.asarray(polygon.exterior.coords)[:-1]
                ring = ring[::-1] if shapely.is_ccw(polygon.exterior) is False else ring
                u0, v0, u1, v1 = polygon.bounds
                axes.append(FACES[f][None])
                rects.append(np.array([[u0, u1, v0, v1]]))
                targets.append(np.array([target]))
                extra_uv.append(ring)
                at += len(ring)
                extra_offsets.append(at)
        hull_offsets = np.concatenate([hull_offsets, np.asarray(extra_offsets, dtype=np.int64)])
        hull_uv = np.concatenate([hull_uv, *extra_uv]) if extra_uv else hull_uv
    return np.concatenate(axes), np.concatenate(rects), np.concatenate(targets).astype(np.int64), hull_offsets, hull_uv


@njit(cache=True)
def grid(rect, n):
    """Level 0: nodes ``(patch, u, v)`` of an ``n x n`` grid on every patch, and its cells as
    ``(patch, u0, u1, v0, v1)`` with their four corner nodes (``u0v0, u1v0, u0v1, u1v1``)."""
    p = len(rect)
    k = n + 1
    node_patch = np.empty(p * k * k, np.int64)
    node_uv = np.empty((p * k * k, 2))
    cell_patch = np.empty(p * n * n, np.int64)
    cell_box = np.empty((p * n * n, 4))
    cell_nodes = np.empty((p * n * n, 4), np.int64)
    for q in range(p):
        du = (rect[q, 1] - rect[q, 0]) / n
        dv = (rect[q, 3] - rect[q, 2]) / n
        for i in range(k):
            for j in range(k):
                a = q * k * k + i * k + j
                node_patch[a] = q
                node_uv[a, 0] = rect[q, 0] + i * du
                node_uv[a, 1] = rect[q, 2] + j * dv
        for i in range(n):
            for j in range(n):
                c = q * n * n + i * n + j
                cell_patch[c] = q
                cell_box[c, 0] = rect[q, 0] + i * du
                cell_box[c, 1] = rect[q, 0] + (i + 1) * du
                cell_box[c, 2] = rect[q, 2] + j * dv
                cell_box[c, 3] = rect[q, 2] + (j + 1) * dv
                base = q * k * k + i * k + j
                cell_nodes[c, 0] = base
                cell_nodes[c, 1] = base + k
                cell_nodes[c, 2] = base + 1
                cell_nodes[c, 3] = base + k + 1
    return node_patch, node_uv, cell_patch, cell_box, cell_nodes


@njit(cache=True)
def directions(axes, node_patch, node_uv):
    """Unit direction of every node, shape (m, 3)."""
    m = len(node_patch)
    out = np.empty((m, 3))
    for a in range(m):
        ax = axes[node_patch[a]]
        s = 0.0
        for j in range(3):
            out[a, j] = ax[0, j] + node_uv[a, 0] * ax[1, j] + node_uv[a, 1] * ax[2, j]
            s += out[a, j] * out[a, j]
        s = math.sqrt(s)
        for j in range(3):
            out[a, j] /= s
    return out


@njit(cache=True)
def _in_view(d, heading, half_fov, low, high):
    if half_fov < math.pi:
        rel = math.atan2(d[1], d[0]) - heading
        rel = (rel + math.pi) % (2 * math.pi) - math.pi
        if abs(rel) > half_fov:
            return False
    elevation = math.asin(min(1.0, max(-1.0, d[2])))
    return low <= elevation <= high


@njit(cache=True)
def label(dirs, node_slot, eyes, slot_view, slot_target, view, centres, rots, halves, padded, prim, tfar, owner,
          cand_offsets, cand, cand_cone, n_boxes):  # fmt: skip
    """What every ray meets, for the slot it samples (the target's own test uses its ``padded`` half-extents).

    Returns ``code`` (``MISS``, or the target's row when nothing is hit before it, or the row of the first body
    hit before it: a box row, or ``n_boxes + k`` for static occluder ``k``), ``in_fov`` and ``in_range`` flags,
    and the (slot, occluder) pairs: every candidate box entered before the target along an in-view ray, and the
    first static occluder hit before it. ``cand_cone[c]`` is the unit direction of candidate ``c``'s bounding
    sphere from the slot's eye and the cosine of its angular radius: rays outside it cannot meet the candidate.
    """
    m = len(dirs)
    code = np.empty(m, np.int64)
    in_fov = np.zeros(m, np.bool_)
    in_range = np.zeros(m, np.bool_)
    pair_slot = np.empty(16, np.int64)
    pair_occ = np.empty(16, np.int64)
    k = 0
    size = n_boxes
    for o in owner:
        size = max(size, o + 1)
    listed = np.full(size, -1, np.int64)  # the slot each occluder was last listed for (slots come in runs)
    for a in range(m):
        s = node_slot[a]
        vi = slot_view[s]
        t = slot_target[s]
        eye = eyes[vi]
        tt = _slab(eye, dirs[a], centres[t], rots[t], padded[t])[0]
        if not math.isfinite(tt):
            code[a] = MISS
            continue
        in_fov[a] = _in_view(dirs[a], view[vi, 0], view[vi, 1], view[vi, 2], view[vi, 3])
        in_range[a] = tt <= view[vi, 4]
        first = owner[prim[a]] if prim[a] >= 0 else -1
        if first >= 0 and first != t and tfar[a] < tt - 1e-4 - 1e-5 * tt:
            code[a] = first
        else:
            code[a] = t
        if code[a] == t or not (in_fov[a] and in_range[a]):
            continue  # where the target is seen first, nothing lies in front of it
        if first >= n_boxes and code[a] == first and listed[first] != s:
            listed[first] = s
            pair_slot, pair_occ, k = push_pair(pair_slot, pair_occ, k, s, first)
        for c in range(cand_offsets[s], cand_offsets[s + 1]):
            cone = cand_cone[c]
            if dirs[a, 0] * cone[0] + dirs[a, 1] * cone[1] + dirs[a, 2] * cone[2] < cone[3]:
                continue
            b = cand[c]
            if listed[b] == s:
                continue
            tb = _slab(eye, dirs[a], centres[b], rots[b], halves[b])[0]
            if tb < tt - 1e-9:
                listed[b] = s
                pair_slot, pair_occ, k = push_pair(pair_slot, pair_occ, k, s, b)
    return code, in_fov, in_range, pair_slot[:k], pair_occ[:k]


@njit(cache=True, inline="always")
def _rect_solid_angle(u0, u1, v0, v1):
    f11 = math.atan(u1 * v1 / math.sqrt(1 + u1 * u1 + v1 * v1))
    f01 = math.atan(u0 * v1 / math.sqrt(1 + u0 * u0 + v1 * v1))
    f10 = math.atan(u1 * v0 / math.sqrt(1 + u1 * u1 + v0 * v0))
    f00 = math.atan(u0 * v0 / math.sqrt(1 + u0 * u0 + v0 * v0))
    return f11 - f01 - f10 + f00


@njit(cache=True)
def _clipped_solid_angle(box, hull, pu, pv, qu, qv):
    """Solid angle of the rectangle ``box`` (u0, u1, v0, v1) inside the convex counter-clockwise ``hull``
    (``pu, pv, qu, qv``: scratch space of at least ``4 + len(hull)`` entries)."""
    pu[0], pv[0], pu[1], pv[1] = box[0], box[2], box[1], box[2]
    pu[2], pv[2], pu[3], pv[3] = box[1], box[3], box[0], box[3]
    k = 4
    h = len(hull)
    for e in range(h):
        ax, ay = hull[e, 0], hull[e, 1]
        bx, by = hull[(e + 1) % h, 0], hull[(e + 1) % h, 1]
        m = 0
        for i in range(k):
            j = (i + 1) % k
            fi = (bx - ax) * (pv[i] - ay) - (by - ay) * (pu[i] - ax)
            fj = (bx - ax) * (pv[j] - ay) - (by - ay) * (pu[j] - ax)
            if fi >= 0:
                qu[m], qv[m] = pu[i], pv[i]
                m += 1
            if (fi >= 0) != (fj >= 0):
                r = fi / (fi - fj)
                qu[m], qv[m] = pu[i] + r * (pu[j] - pu[i]), pv[i] + r * (pv[j] - pv[i])
                m += 1
        k = m
        pu[:k], pv[:k] = qu[:k], qv[:k]
        if k < 3:
            return 0.0
    total = 0.0
    for i in range(k):
        j = (i + 1) % k
        u0, v0, u1, v1 = pu[i], pv[i], pu[j], pv[j]
        nb = math.sqrt(u0 * u0 + v0 * v0 + 1)
        nc = math.sqrt(u1 * u1 + v1 * v1 + 1)
        total += 2 * math.atan2(u0 * v1 - v0 * u1, nb * nc + nb + nc + u0 * u1 + v0 * v1 + 1)
    return abs(total)


@njit(cache=True)
def convex_hulls(u, v):
    """Counter-clockwise convex hulls of the rows of points ``(u[i], v[i])`` (monotone chain); CSR
    ``(offsets, coords)``."""
    m, k = u.shape
    offsets = np.zeros(m + 1, np.int64)
    coords = np.empty((m * (k + 1), 2))
    at = 0
    hull = np.empty((2 * k, 2))
    for i in range(m):
        order = np.arange(k)
        for q in range(1, k):  # insertion sort by (u, v)
            j = q
            while j > 0 and (u[i, order[j - 1]], v[i, order[j - 1]]) > (u[i, order[j]], v[i, order[j]]):
                order[j - 1], order[j] = order[j], order[j - 1]
                j -= 1
        size = 0
        for rep in range(2):
            start = size
            for q in range(k):
                j = order[q] if rep == 0 else order[k - 1 - q]
                x, y = u[i, j], v[i, j]
                while size >= start + 2:
                    ox, oy = hull[size - 2, 0], hull[size - 2, 1]
                    ax, ay = hull[size - 1, 0], hull[size - 1, 1]
                    if (ax - ox) * (y - oy) - (ay - oy) * (x - ox) > 0:
                        break
                    size -= 1
                hull[size, 0], hull[size, 1] = x, y
                size += 1
            size -= 1  # the last point is the first of the other chain
        coords[at : at + size] = hull[:size]
        at += size
        offsets[i + 1] = at
    return offsets, coords[:at]


@njit(cache=True)
def refine(cell_patch, cell_box, cell_nodes, code, in_fov, in_range, patch_slot, slot_target, sums, n_nodes, split,
           hull_offsets, hull_uv):  # fmt: skip
    """Split the cells whose target-hitting corners disagree (when ``split``); add the others to ``sums``.

    ``sums[s]`` accumulates, in steradians, ``(hit, seen, hit in the field of view, hit in view and range)``. A
    leaf on the target's border weighs the exact solid angle of its part inside the target's silhouette (the
    patch's convex hull ``hull_uv[hull_offsets[p]:hull_offsets[p + 1]]``; without one, the share of its corners
    that hit), shared out among its corners that hit. Returns the new nodes ``(patch, u, v)`` (numbered from
    ``n_nodes``) and the new cells.
    """
    c_n = len(cell_patch)
    todo = np.zeros(c_n, np.bool_)
    longest = 0
    for p in range(len(hull_offsets) - 1):
        longest = max(longest, hull_offsets[p + 1] - hull_offsets[p])
    pu, pv, qu, qv = np.empty(longest + 8), np.empty(longest + 8), np.empty(longest + 8), np.empty(longest + 8)
    for c in range(c_n):
        s = patch_slot[cell_patch[c]]
        t = slot_target[s]
        first = -2
        mixed = False
        hits = 0
        for corner in range(4):
            a = cell_nodes[c, corner]
            if code[a] == MISS:
                continue
            hits += 1
            key = code[a] * 4 + 2 * in_fov[a] + in_range[a]
            if first == -2:
                first = key
            elif key != first:
                mixed = True
        if split and mixed:
            todo[c] = True
            continue
        if hits == 0:
            continue
        b = cell_box[c]
        p = cell_patch[c]
        h0, h1 = hull_offsets[p], hull_offsets[p + 1]
        if hits == 4 or h1 - h0 < 3:
            w = _rect_solid_angle(b[0], b[1], b[2], b[3]) / 4
        else:
            w = _clipped_solid_angle(b, hull_uv[h0:h1], pu, pv, qu, qv) / hits
        for corner in range(4):
            a = cell_nodes[c, corner]
            if code[a] == MISS:
                continue
            sums[s, 0] += w
            if in_fov[a]:
                sums[s, 2] += w
                if in_range[a]:
                    sums[s, 3] += w
                    if code[a] == t:
                        sums[s, 1] += w
    k = int(todo.sum())
    node_patch = np.empty(5 * k, np.int64)
    node_uv = np.empty((5 * k, 2))
    new_patch = np.empty(4 * k, np.int64)
    new_box = np.empty((4 * k, 4))
    new_nodes = np.empty((4 * k, 4), np.int64)
    r = 0
    for c in range(c_n):
        if not todo[c]:
            continue
        u0, u1, v0, v1 = cell_box[c, 0], cell_box[c, 1], cell_box[c, 2], cell_box[c, 3]
        um, vm = (u0 + u1) / 2, (v0 + v1) / 2
        # new nodes: bottom middle, left middle, centre, right middle, top middle
        y = 5 * r
        node_patch[y : y + 5] = cell_patch[c]
        node_uv[y, 0], node_uv[y, 1], node_uv[y + 1, 0], node_uv[y + 1, 1] = um, v0, u0, vm
        node_uv[y + 2, 0], node_uv[y + 2, 1], node_uv[y + 3, 0], node_uv[y + 3, 1] = um, vm, u1, vm
        node_uv[y + 4, 0], node_uv[y + 4, 1] = um, v1
        first_new = n_nodes + 5 * r
        bm, lm, cc, rm, tm = first_new, first_new + 1, first_new + 2, first_new + 3, first_new + 4
        c00, c10, c01, c11 = cell_nodes[c, 0], cell_nodes[c, 1], cell_nodes[c, 2], cell_nodes[c, 3]
        z = 4 * r
        new_patch[z : z + 4] = cell_patch[c]
        new_box[z, 0], new_box[z, 1], new_box[z, 2], new_box[z, 3] = u0, um, v0, vm
        new_box[z + 1, 0], new_box[z + 1, 1], new_box[z + 1, 2], new_box[z + 1, 3] = um, u1, v0, vm
        new_box[z + 2, 0], new_box[z + 2, 1], new_box[z + 2, 2], new_box[z + 2, 3] = u0, um, vm, v1
        new_box[z + 3, 0], new_box[z + 3, 1], new_box[z + 3, 2], new_box[z + 3, 3] = um, u1, vm, v1
        new_nodes[z, 0], new_nodes[z, 1], new_nodes[z, 2], new_nodes[z, 3] = c00, bm, lm, cc
        new_nodes[z + 1, 0], new_nodes[z + 1, 1], new_nodes[z + 1, 2], new_nodes[z + 1, 3] = bm, c10, cc, rm
        new_nodes[z + 2, 0], new_nodes[z + 2, 1], new_nodes[z + 2, 2], new_nodes[z + 2, 3] = lm, cc, c01, tm
        new_nodes[z + 3, 0], new_nodes[z + 3, 1], new_nodes[z + 3, 2], new_nodes[z + 3, 3] = cc, rm, tm, c11
        r += 1
    return node_patch, node_uv, new_patch, new_box, new_nodes
