"""A chunk of frames through VisiLibity with the Python left to VisiLibity's own calls, for viewpoints that see
all around without range.

Frame by frame, the numpy and Python around VisiLibity (angular extents, occluding pairs, bounding boxes, grouping
the pairs) cost more than VisiLibity's visibility polygon on small scenes. Here they run over the whole chunk in
compiled loops, with numpy's ``arctan2`` and ``mod`` applied once to all their arguments (the numbers must be
numpy's, as frame by frame, to be the same to the bit):

1. :func:`.chunk_geometry.angular_extents`: every target's angular extent;
2. :func:`occlusion_by_view`: the occluding pairs as CSR over the chunk's targets, reason codes, and the bodies
   left in each environment;
3. per viewpoint: the environment (:func:`.plain.plain_environment` in one compiled call where no two bodies meet;
   otherwise the engine's general construction) and VisiLibity's visibility polygon, read in one call;
4. :func:`checked_visible_angles`: the polygon check and the attribution.

A polygon that fails the check is computed again by the engine frame by frame (:meth:`.VisiLibityEngine.observe`
splits the holes); its numbers are the same by construction.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.candidates import candidate_pairs
from ...geometry.kernels import copy_into, reserve
from ...geometry.object_pairs import objects_occluded
from ...geometry.occlusion import _occludes_pairs
from ...geometry.rings import Rings
from ...inputs.objects import ObjectTable
from .. import ChunkObservation, ChunkViewpoints, Observation, Viewpoint, reason_of
from .attribution import attribute_visible_angles
from .chunk_geometry import angular_extents, static_blocking, view_segments
from .conversion import grid_origin, visibility_polygon_coords, visibility_polygon_flat
from .plain import plain_environments
from .polygon_check import CHECK_ABSOLUTE, CHECK_RELATIVE, ON_EDGE, polygon_fails


@njit(cache=True)
def occlusion_by_view(
    coords,
    offsets,
    frame_starts,
    view_starts,
    target_offsets,
    origins,
    eyes,
    transparent,
    static_offsets,
    static_inside,
    st_seg,
    st_source,
    n_sources,
    start,
    width,
):
    """What :meth:`.VisiLibityEngine.observe` finds before VisiLibity, for every viewpoint of a chunk.

    Parameters
    ----------
    coords, offsets, frame_starts, view_starts, target_offsets, origins, eyes
        As :func:`extent_arguments` takes them.
    transparent : ndarray of bool, shape (t,)
        Per target: neither blocks nor occludes.
    static_offsets, static_inside : ndarray, int64
        Static sources containing viewpoint ``v``: ``static_inside[static_offsets[v]:static_offsets[v + 1]]``.
    st_seg : ndarray, shape (s, 2, 2)
        Every static edge, world frame, grouped by source; ``st_source`` (shape (s,)) is its source.
    start, width : ndarray, shape (t,)
        Every target's angular extent, radians.

    Returns
    -------
    reason : ndarray, shape (t,), int8
    occ_offsets, occ, st_offsets, st : ndarray, int64
        The occluders (row numbers in the frame) and static occluders (sources) of each target, CSR over the
        targets, ascending.
    in_env : ndarray of bool, shape (t,)
        Targets that are holes of the viewpoint's environment (blocking, and not hidden behind one object).
    blocked : ndarray of bool, shape (v,)
        Viewpoints for which something blocks the view (the others see every target whole).
    """
    n_views = len(eyes)
    n_targets = target_offsets[-1]
    reason = np.empty(n_targets, dtype=np.int8)
    occ_offsets = np.zeros(n_targets + 1, dtype=np.int64)
    st_offsets = np.zeros(n_targets + 1, dtype=np.int64)
    occ = np.empty(0, dtype=np.int64)
    st = np.empty(0, dtype=np.int64)
    n_occ = 0
    n_st = 0
    in_env = np.zeros(n_targets, dtype=np.bool_)
    blocked = np.zeros(n_views, dtype=np.bool_)
    for f in range(len(frame_starts) - 1):
        s, e = frame_starts[f], frame_starts[f + 1]
        n = e - s
        for v in range(view_starts[f], view_starts[f + 1]):
            gx, gy, ox, oy = origins[v, 0], origins[v, 1], eyes[v, 0], eyes[v, 1]
            t0 = target_offsets[v]
            seg, seg_body, seg_offsets = view_segments(coords, offsets, s, e, gx, gy, st_seg, st_source, n_sources)
            blocking = np.empty(n + n_sources, dtype=np.bool_)
            for i in range(n):
                blocking[i] = not transparent[t0 + i]
            copy_into(blocking, n, static_blocking(static_offsets, static_inside, v, n_sources))
            targets = np.flatnonzero(blocking[:n])
            hidden = np.zeros(n + n_sources, dtype=np.bool_)
            codes = np.empty(0, dtype=np.int64)
            if len(targets) and len(seg):
                body, target, certain, hidden = candidate_pairs(
                    ox, oy, seg, seg_body, blocking, targets, start[t0 : t0 + n], width[t0 : t0 + n], n
                )
                # the exact test: pairs of objects all at once (grouped by target), static bodies pair by pair
                check = np.flatnonzero(~certain & (body < n))
                occluding = objects_occluded(
                    seg, seg_offsets[: n + 1], start[t0 : t0 + n], width[t0 : t0 + n], target[check], body[check],
                    ox, oy,
                )  # fmt: skip
                for q in range(len(check)):
                    certain[check[q]] = occluding[q]
                check = np.flatnonzero(~certain & (body >= n))
                occluding = _occludes_pairs(
                    ox, oy, seg, seg_offsets, body[check], target[check], start[t0 : t0 + n], width[t0 : t0 + n]
                )
                for q in range(len(check)):
                    certain[check[q]] = occluding[q]
                codes = _occluder_codes(body, target, certain, n + n_sources)
            occ = reserve(occ, n_occ, n_occ + len(codes))
            st = reserve(st, n_st, n_st + len(codes))
            q = 0
            for i in range(n):
                while q < len(codes) and codes[q] // (n + n_sources) == i:
                    b = codes[q] % (n + n_sources)
                    if b < n:
                        occ[n_occ] = b
                        n_occ += 1
                    else:
                        st[n_st] = b - n
                        n_st += 1
                    q += 1
                occ_offsets[t0 + i + 1] = n_occ
                st_offsets[t0 + i + 1] = n_st
                counts_occ = occ_offsets[t0 + i + 1] - occ_offsets[t0 + i]
                counts_st = st_offsets[t0 + i + 1] - st_offsets[t0 + i]
                reason[t0 + i] = reason_of(transparent[t0 + i], counts_occ, counts_st)
                in_env[t0 + i] = blocking[i] and not hidden[i]
            blocked[v] = blocking.any()
    return reason, occ_offsets, occ[:n_occ], st_offsets, st[:n_st], in_env, blocked


@njit(cache=True)
def _occluder_codes(body, target, occluding, n_bodies):
    """``target * n_bodies + body`` of the occluding pairs, grouped by target and ascending within (objects first,
    static sources after): the pairs come grouped by target, ascending, each once, so each group is sorted by
    insertion (a few each) rather than all of them at once."""
    codes = np.empty(len(body), dtype=np.int64)
    n_codes = 0
    group = 0
    for p in range(len(body)):
        if not occluding[p]:
            continue
        code = target[p] * n_bodies + body[p]
        if n_codes and codes[n_codes - 1] // n_bodies != target[p]:
            group = n_codes
        a = n_codes
        while a > group and codes[a - 1] > code:
            codes[a] = codes[a - 1]
            a -= 1
        codes[a] = code
        n_codes += 1
    return codes[:n_codes]


@njit(cache=True)
def checked_visible_angles(
    coords,
    offsets,
    frame_starts,
    view_starts,
    target_offsets,
    origins,
    eyes,
    transparent,
    static_offsets,
    static_inside,
    st_seg,
    st_source,
    n_sources,
    start,
    width,
    in_env,
    blocked,
    occ_offsets,
    occ,
    st_offsets,
    st,
    polygon_offsets,
    polygons,
    check_absolute,
    check_relative,
):
    """Every target's visible angle (radians) from the visibility polygons of a chunk's viewpoints.

    ``polygons[polygon_offsets[v]:polygon_offsets[v + 1]]`` are VisiLibity's vertices for viewpoint ``v``
    (relative to its origin; none where it computed none); the other arguments as :func:`occlusion_by_view` takes
    and returns them. A viewpoint with nothing blocking sees each target's whole extent. Each polygon is checked
    (:func:`.polygon_check.polygon_fails` on the edges of the environment's bodies) and attributed
    (:func:`.attribution.attribute_visible_angles`).

    Returns
    -------
    visible : ndarray, shape (t,)
        Zero for targets of viewpoints without a polygon or failing the check.
    failed : ndarray of bool, shape (v,)
        Viewpoints whose polygon fails the check (misses the nearest body somewhere).
    """
    visible = np.zeros(target_offsets[-1])
    failed = np.zeros(len(eyes), dtype=np.bool_)
    for f in range(len(frame_starts) - 1):
        s, e = frame_starts[f], frame_starts[f + 1]
        n = e - s
        for v in range(view_starts[f], view_starts[f + 1]):
            t0 = target_offsets[v]
            if not blocked[v]:
                copy_into(visible, t0, width[t0 : t0 + n])
                continue
            p0, p1 = polygon_offsets[v], polygon_offsets[v + 1]
            if p1 == p0:
                continue
            gx, gy, ox, oy = origins[v, 0], origins[v, 1], eyes[v, 0], eyes[v, 1]
            seg, seg_body, seg_offsets = view_segments(coords, offsets, s, e, gx, gy, st_seg, st_source, n_sources)
            for j in range(len(seg)):  # relative to the viewpoint
                for p in range(2):
                    seg[j, p, 0] -= ox
                    seg[j, p, 1] -= oy
            pts = np.empty((p1 - p0, 2))
            for i in range(p1 - p0):
                pts[i, 0], pts[i, 1] = polygons[p0 + i, 0] - ox, polygons[p0 + i, 1] - oy
            statics_blocking = static_blocking(static_offsets, static_inside, v, n_sources)
            check = np.empty(len(seg), dtype=np.bool_)
            for j in range(len(seg)):
                b = seg_body[j]
                check[j] = in_env[t0 + b] if b < n else statics_blocking[b - n]
            if polygon_fails(pts, seg, check, check_absolute, check_relative, ON_EDGE):
                failed[v] = True
                continue
            targets = np.empty(n, dtype=np.int64)  # blocking, and not hidden behind a single nearer object
            k = 0
            for i in range(n):
                if in_env[t0 + i]:
                    targets[k] = i
                    k += 1
            attributed = attribute_visible_angles(
                pts, seg, seg_offsets, targets[:k], start[t0 : t0 + n], width[t0 : t0 + n], ON_EDGE,
                occ_offsets[t0 : t0 + n + 1], occ, st_offsets[t0 : t0 + n + 1], st,
            )  # fmt: skip
            copy_into(visible, t0, attributed)
    return visible, failed


def observe_chunk(engine: Any, objects: ObjectTable, views: ChunkViewpoints) -> ChunkObservation:
    """What every viewpoint of a chunk sees, all around without range (see the module docstring); the numbers of
    ``engine.observe`` frame by frame. ``engine`` is the :class:`.engine.VisiLibityEngine` calling this (its
    environments, static parts and frame-by-frame path are used)."""
    coords = np.ascontiguousarray(objects.rings.coords, dtype=np.float64)
    offsets = np.ascontiguousarray(objects.rings.offsets, dtype=np.int64)
    frame_starts = np.ascontiguousarray(objects.frame_starts, dtype=np.int64)
    view_starts = np.ascontiguousarray(views.frame_starts, dtype=np.int64)
    target_offsets = np.ascontiguousarray(views.target_offsets, dtype=np.int64)
    transparent = np.ascontiguousarray(views.transparent, dtype=np.bool_)
    static_offsets = np.ascontiguousarray(views.static_offsets, dtype=np.int64)
    static_inside = np.ascontiguousarray(views.static_inside, dtype=np.int64)
    positions = np.ascontiguousarray(views.position, dtype=np.float64).reshape(-1, 2)
    if len(positions) == 0:
        empty, no_offsets = np.zeros(0, dtype=np.int64), np.zeros(1, dtype=np.int64)
        return ChunkObservation(np.zeros(0), np.zeros(0), np.zeros(0, np.int8), no_offsets, empty, no_offsets, empty)
    origins = grid_origin(positions)
    eyes = positions - origins
    st_seg, st_offsets = engine._source_edges
    st_source = np.repeat(np.arange(engine.statics.n_sources, dtype=np.int64), np.diff(st_offsets))
    st_seg = np.ascontiguousarray(st_seg, dtype=np.float64).reshape(-1, 2, 2)

    start, width = angular_extents(coords, offsets, frame_starts, view_starts, target_offsets, origins, eyes)

    common = (coords, offsets, frame_starts, view_starts, target_offsets, origins, eyes, transparent)
    statics = (static_offsets, static_inside, st_seg, st_source, engine.statics.n_sources, start, width)
    reason, occ_offsets, occ, static_occ_offsets, static_occ, in_env, blocked = occlusion_by_view(*common, *statics)

    frame_of_view = np.repeat(np.arange(objects.n_frames), np.diff(view_starts))
    polygons = _visibility_polygons(engine, objects, views, frame_of_view, origins, eyes, in_env, blocked)
    polygon_offsets = np.zeros(len(eyes) + 1, dtype=np.int64)
    np.cumsum([len(p) for p in polygons], out=polygon_offsets[1:])
    points = np.concatenate(polygons).reshape(-1, 2) if polygons else np.zeros((0, 2))
    visible, failed = checked_visible_angles(
        *common, *statics, in_env, blocked, occ_offsets, occ, static_occ_offsets, static_occ, polygon_offsets, points,
        CHECK_ABSOLUTE, CHECK_RELATIVE,
    )  # fmt: skip
    for v in np.flatnonzero(failed).tolist():  # polygons skipping a nearer body: the engine splits the holes
        observation = _frame_observation(engine, objects, views, int(frame_of_view[v]), v)
        visible[target_offsets[v] : target_offsets[v + 1]] = observation.visible_angle
    return ChunkObservation(visible, width, reason, occ_offsets, occ, static_occ_offsets, static_occ)


def _parts_at(engine: Any, origin: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The static parts blocking a viewpoint inside none of them, in the grid cell of ``origin``, as
    :func:`.plain.plain_environment` takes them: their VisiLibity holes back to back (relative to the origin), each
    one's first vertex, and whether it has a courtyard."""
    engine._use_origin(origin)
    _, _, holes, enclosing = engine._static_parts(np.ones(engine.statics.n_sources, dtype=bool))
    part_offsets = np.zeros(len(holes) + 1, dtype=np.int64)
    np.cumsum([len(hole) for hole in holes], out=part_offsets[1:])
    vertices = np.ascontiguousarray(np.concatenate(holes), dtype=np.float64) if holes else np.zeros((0, 2))
    encloses = np.zeros(len(holes), dtype=np.bool_)
    encloses[list(enclosing)] = True
    return vertices, part_offsets, encloses


def _visibility_polygons(engine, objects, views, frame_of_view, origins, eyes, in_env, blocked) -> list[np.ndarray]:
    """VisiLibity's visibility polygon of every blocked viewpoint (relative to its origin; empty where none), in the
    plain environment where it applies (:mod:`.plain`, a batch of viewpoints of a grid cell at a time), else in the
    engine's general construction."""
    coords = np.ascontiguousarray(objects.rings.coords, dtype=np.float64)
    offsets = np.ascontiguousarray(objects.rings.offsets, dtype=np.int64)
    frame_starts = np.ascontiguousarray(objects.frame_starts, dtype=np.int64)
    target_offsets = np.ascontiguousarray(views.target_offsets, dtype=np.int64)
    polygons = [_NO_POLYGON] * len(eyes)
    blocked_views = np.flatnonzero(blocked)
    inside_static = views.static_offsets[blocked_views + 1] > views.static_offsets[blocked_views]
    general = blocked_views[inside_static].tolist()
    candidates = blocked_views[~inside_static]
    keys, key_of = np.unique(origins[candidates], axis=0, return_inverse=True)
    eye = eyes.tolist()
    for key, origin in enumerate(keys):
        parts = _parts_at(engine, origin)
        in_cell = candidates[key_of.ravel() == key]
        for first in range(0, len(in_cell), PLAIN_BATCH):
            batch = np.ascontiguousarray(in_cell[first : first + PLAIN_BATCH], dtype=np.int64)
            plain, vertex_offsets, vertices, count_offsets, counts = plain_environments(
                batch, frame_of_view, frame_starts, target_offsets, in_env, coords, offsets, origins, eyes, *parts,
                engine.box_margin,
            )  # fmt: skip
            vertex_offsets, count_offsets, plain = vertex_offsets.tolist(), count_offsets.tolist(), plain.tolist()
            for i, v in enumerate(batch.tolist()):
                if not plain[i]:
                    general.append(v)
                    continue
                own = vertices[vertex_offsets[i] : vertex_offsets[i + 1]]
                polygons[v] = visibility_polygon_flat(own, counts[count_offsets[i] : count_offsets[i + 1]], *eye[v],
                                                      engine.epsilon)  # fmt: skip
    for v in general:  # groups of bodies that meet, enclosures, viewpoints inside static occluders
        f = int(frame_of_view[v])
        s, e = int(frame_starts[f]), int(frame_starts[f + 1])
        env = in_env[target_offsets[v] : target_offsets[v] + e - s]
        rel = coords[offsets[s] : offsets[e]] - origins[v]
        local = offsets[s : e + 1] - offsets[s]
        engine._use_origin(views.position[v])
        static_blocking = ~_static_transparent(views, engine.statics.n_sources, v)
        polys = engine._build_environment(Rings(rel, local), env, static_blocking, eyes[v])
        polygons[v] = visibility_polygon_coords(polys, *eyes[v].tolist(), engine.epsilon)
    return polygons


PLAIN_BATCH = 256
"""Viewpoints whose plain environments are built in one call (their vertices held at once)."""


_NO_POLYGON = np.zeros((0, 2))


def _static_transparent(views: ChunkViewpoints, n_sources: int, v: int) -> np.ndarray:
    """The static sources containing viewpoint ``v``, shape (n_sources,) bool."""
    inside = np.zeros(n_sources, dtype=bool)
    inside[views.static_inside[views.static_offsets[v] : views.static_offsets[v + 1]]] = True
    return inside


def _frame_observation(engine: Any, objects: ObjectTable, views: ChunkViewpoints, f: int, v: int) -> Observation:
    """Viewpoint ``v`` (of frame position ``f``) observed frame by frame (:meth:`.VisiLibityEngine.observe`)."""
    static_transparent = _static_transparent(views, engine.statics.n_sources, v)
    t0, t1 = views.target_offsets[v], views.target_offsets[v + 1]
    viewpoint = Viewpoint(views.position[v], 0.0, int(views.own[v]), views.transparent[t0:t1], static_transparent)
    return engine.observe(objects.frame_objects(f), [viewpoint])[0]
