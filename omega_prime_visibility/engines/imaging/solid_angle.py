"""Exact solid angles of convex bodies, whole and inside a pyramid of planes through the eye (a camera's
frustum): the truncation of a target by the image border.

A convex body seen from outside fills a convex cone of directions, which lies on the far side of one of its
face planes; drawn on the plane at unit distance beyond that face (a gnomonic chart), the cone is the convex
hull of the body's vertices' images, and each plane through the eye is a line. The solid angle of a convex
chart polygon is the sum of its fan's spherical triangles (Van Oosterom and Strackee's formula), exact to
rounding; nothing is sampled.

>>> import math, numpy as np
>>> from omega_prime_visibility.threed.bodies import bodies_from_boxes
>>> cube = bodies_from_boxes(np.array([[0.0, 0, 10, 2, 2, 2, 0, 0, 0]]))  # a 2 m cube 10 m above the eye
>>> whole, _ = body_solid_angles(cube.vertices, np.array([0, 8]), cube.normals, cube.offsets, np.zeros((0, 3)))
>>> round(float(whole[0]), 12) == round(4 * math.asin(1 / 82), 12)  # its near face, 2 x 2 m at 9 m
True
"""

from __future__ import annotations

import math

import numpy as np

from ..._compiled.kernel import njit


@njit(cache=True, inline="always")
def _triangle(ax, ay, az, bx, by, bz, cx, cy, cz):
    """Steradians of the spherical triangle with corners along ``a``, ``b``, ``c``."""
    la = math.sqrt(ax * ax + ay * ay + az * az)
    lb = math.sqrt(bx * bx + by * by + bz * bz)
    lc = math.sqrt(cx * cx + cy * cy + cz * cz)
    det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (ax * cx + ay * cy + az * cz) * lb
    den += (bx * cx + by * cy + bz * cz) * la
    return 2.0 * math.atan2(abs(det), den)


@njit(cache=True)
def _hull(points, n):
    """Indices of the convex hull of ``points[:n]`` (shape (k, 2)), counter-clockwise (Andrew's monotone chain)."""
    order = np.arange(n)
    for i in range(1, n):  # by x, then y (insertion sort: a dozen points)
        j = i
        while j > 0:
            p, q = order[j - 1], order[j]
            if points[p, 0] > points[q, 0] or (points[p, 0] == points[q, 0] and points[p, 1] > points[q, 1]):
                order[j - 1], order[j] = q, p
                j -= 1
            else:
                break
    hull = np.empty(2 * n + 1, dtype=np.int64)
    k = 0
    for pass_ in range(2):
        start = k
        for r in range(n):
            i = order[r] if pass_ == 0 else order[n - 1 - r]
            while k >= start + 2:
                o, p = hull[k - 2], hull[k - 1]
                cross = (points[p, 0] - points[o, 0]) * (points[i, 1] - points[o, 1]) - (
                    points[p, 1] - points[o, 1]
                ) * (points[i, 0] - points[o, 0])
                if cross <= 0.0:
                    k -= 1
                else:
                    break
            hull[k] = i
            k += 1
        k -= 1  # the last point of each chain starts the other
    return hull[: max(k, 0)]


@njit(cache=True)
def _polygon_solid_angle(poly, n, sx, sy, sz, ux, uy, uz, wx, wy, wz):
    """Steradians of the chart polygon ``poly[:n]`` (convex, points ``s + x u + y w``)."""
    if n < 3:
        return 0.0
    total = 0.0
    p0x = sx + poly[0, 0] * ux + poly[0, 1] * wx
    p0y = sy + poly[0, 0] * uy + poly[0, 1] * wy
    p0z = sz + poly[0, 0] * uz + poly[0, 1] * wz
    for i in range(1, n - 1):
        bx = sx + poly[i, 0] * ux + poly[i, 1] * wx
        by = sy + poly[i, 0] * uy + poly[i, 1] * wy
        bz = sz + poly[i, 0] * uz + poly[i, 1] * wz
        cx = sx + poly[i + 1, 0] * ux + poly[i + 1, 1] * wx
        cy = sy + poly[i + 1, 0] * uy + poly[i + 1, 1] * wy
        cz = sz + poly[i + 1, 0] * uz + poly[i + 1, 1] * wz
        total += _triangle(p0x, p0y, p0z, bx, by, bz, cx, cy, cz)
    return total


@njit(cache=True)
def body_solid_angles(vertices, vstart, normals, offsets, planes):
    """Per body (vertices ``vertices[vstart[k]:vstart[k + 1]]``, faces ``normals . x <= offsets``, the eye at
    the origin and outside each): the steradians of its directions, and of those with ``planes @ d >= 0`` for
    every row of ``planes`` (shape (p, 3): inward normals of planes through the eye; none: the whole)."""
    n = len(vstart) - 1
    whole = np.zeros(n)
    inside = np.zeros(n)
    points = np.empty((64, 2))
    poly = np.empty((128, 2))
    clipped = np.empty((128, 2))
    for k in range(n):
        # the face the eye lies farthest outside of: the body is beyond it
        best = 0
        for p in range(normals.shape[1]):
            if offsets[k, p] < offsets[k, best]:
                best = p
        if offsets[k, best] >= 0.0:
            continue  # the eye touches or is inside it
        sx, sy, sz = -normals[k, best, 0], -normals[k, best, 1], -normals[k, best, 2]
        # an orthonormal chart basis u, w across s
        if abs(sx) < 0.9:
            ux, uy, uz = 0.0, -sz, sy
        else:
            ux, uy, uz = sz, 0.0, -sx
        norm = math.sqrt(ux * ux + uy * uy + uz * uz)
        ux, uy, uz = ux / norm, uy / norm, uz / norm
        wx, wy, wz = sy * uz - sz * uy, sz * ux - sx * uz, sx * uy - sy * ux
        count = 0
        for i in range(vstart[k], vstart[k + 1]):
            x, y, z = vertices[i, 0], vertices[i, 1], vertices[i, 2]
            depth = x * sx + y * sy + z * sz
            points[count, 0] = (x * ux + y * uy + z * uz) / depth
            points[count, 1] = (x * wx + y * wy + z * wz) / depth
            count += 1
        hull = _hull(points, count)
        m = len(hull)
        for i in range(m):
            poly[i, 0], poly[i, 1] = points[hull[i], 0], points[hull[i], 1]
        whole[k] = _polygon_solid_angle(poly, m, sx, sy, sz, ux, uy, uz, wx, wy, wz)
        for p in range(len(planes)):  # clip by each plane: c0 + c1 x + c2 y >= 0 in the chart
            c0 = planes[p, 0] * sx + planes[p, 1] * sy + planes[p, 2] * sz
            c1 = planes[p, 0] * ux + planes[p, 1] * uy + planes[p, 2] * uz
            c2 = planes[p, 0] * wx + planes[p, 1] * wy + planes[p, 2] * wz
            out = 0
            for i in range(m):
                j = (i + 1) % m
                fi = c0 + c1 * poly[i, 0] + c2 * poly[i, 1]
                fj = c0 + c1 * poly[j, 0] + c2 * poly[j, 1]
                if fi >= 0.0:
                    clipped[out, 0], clipped[out, 1] = poly[i, 0], poly[i, 1]
                    out += 1
                if (fi >= 0.0) != (fj >= 0.0):
                    w = fi / (fi - fj)
                    clipped[out, 0] = poly[i, 0] + w * (poly[j, 0] - poly[i, 0])
                    clipped[out, 1] = poly[i, 1] + w * (poly[j, 1] - poly[i, 1])
                    out += 1
            m = out
            for i in range(m):
                poly[i, 0], poly[i, 1] = clipped[i, 0], clipped[i, 1]
            if m == 0:
                break
        inside[k] = _polygon_solid_angle(poly, m, sx, sy, sz, ux, uy, uz, wx, wy, wz)
    return whole, inside
