"""``occluders=`` and ``targets=`` through any engine, exactly, by the engine contract's transparency masks.

Each viewpoint becomes one or more *views* at the same place, each with its own transparency, and keeps only the
rows it is responsible for:

- the **main view**, where every object that may not block is transparent: it gives the rows of the wanted
  targets that may block (and of those that contain the viewpoint), and of the wanted targets that may not block
  but that can hide no row of the view (in front of none of its targets, and none of them in front of another);
- one view per **group** of the other wanted targets that may not block, the members of a group being chosen so
  that no two share a direction from the viewpoint (so they cannot hide each other): each sees the blocking
  objects and its own members only, and gives their rows.

An engine that measures such targets itself (:attr:`..engines.Engine.passive_targets`, the sweep) gets the main
view alone, every wanted target in it, those that may not block marked *passive* (:attr:`..engines.Viewpoint.passive`).

Each view is handed to the engine as a scene of its own holding only the bodies it needs: its targets, the observer
and the blocking bodies that may be in front of one of its targets (sharing a direction with it and not farther
than all of it: :mod:`..geometry.spans`). A body that cannot be in front of a target changes neither its visibility
nor its occluder lists, so the rows are those of the whole scene, and work for targets not asked for is skipped,
not computed and dropped.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .._compiled.kernel import njit
from ..engines import ChunkViewpoints, Viewpoint
from ..geometry.sorting import argsort_stable
from ..geometry.spans import angular_spans, may_be_in_front, spans_share
from ..inputs.objects import FrameObjects, ObjectTable
from .schema import LIST_COLUMNS, Columns


@dataclass(frozen=True, slots=True)
class Views:
    """Viewpoints expanded into views (see the module docstring), each with the objects of its own scene.

    Attributes
    ----------
    base : ndarray, shape (e,), int64
        The viewpoint each view belongs to (views of a viewpoint are consecutive).
    object_offsets : ndarray, shape (e + 1,), int64
        View ``e``'s scene is ``rows[object_offsets[e]:object_offsets[e + 1]]``, in the frame's order.
    rows : ndarray, shape (t,), int64
        Row numbers in the loaded objects (the chunk's or the frame's).
    transparent : ndarray, shape (t,), bool
        Per object of a scene: transparent in that view.
    keep : ndarray, shape (t,), bool
        Per object of a scene: this view gives its row.
    own : ndarray, shape (e,), int64
        Position of the observer within each view's scene.
    passive : ndarray, shape (t,), bool, or None
        Per object of a scene: a target that may not block, measured by the engine itself (None: the engine
        does not measure such targets, they have views of their own).
    """

    base: np.ndarray
    object_offsets: np.ndarray
    rows: np.ndarray
    transparent: np.ndarray
    keep: np.ndarray
    own: np.ndarray
    passive: np.ndarray | None


def expand(
    positions: np.ndarray,
    own: np.ndarray,
    target_offsets: np.ndarray,
    transparent: np.ndarray,
    first_row: np.ndarray,
    objects: ObjectTable | FrameObjects,
    passive_targets: bool = False,
) -> Views:
    """The views of viewpoints ``v`` at ``positions[v]`` (metres) whose targets are the objects ``first_row[v]``
    onwards of ``objects`` (their frame's, one slot each, ``target_offsets`` as in
    :class:`..engines.ChunkViewpoints`), with base transparency ``transparent`` per slot and observer ``own[v]``
    (position within its frame); with ``passive_targets``, a single view per viewpoint with passive targets."""
    n_views = len(own)
    sizes = np.diff(target_offsets)
    slot_view = np.repeat(np.arange(n_views), sizes)
    slot_row = np.repeat(first_row, sizes) + np.arange(target_offsets[-1]) - np.repeat(target_offsets[:-1], sizes)
    blocks = np.ones(len(slot_row), dtype=bool) if objects.blocks is None else objects.blocks[slot_row]
    wanted = np.ones(len(slot_row), dtype=bool) if objects.wanted is None else objects.wanted[slot_row].copy()
    own_slot = target_offsets[:-1] + own
    wanted[own_slot] = False
    centre, half, near, far = angular_spans(positions[slot_view], objects.rings, slot_row)
    group, counts = _assign_groups(
        target_offsets, transparent, blocks, wanted, centre, half, near, far, passive_targets
    )
    base, offsets, clear, keep = _fill_views(
        target_offsets, transparent, blocks, group, counts, centre, half, near, far
    )
    # each view's scene: what it sees, what it reports and its observer
    local = np.arange(offsets[-1]) - np.repeat(offsets[:-1], np.diff(offsets))
    full_slot = np.repeat(target_offsets[base], np.diff(offsets)) + local
    inside = ~clear | keep
    inside[offsets[:-1] + own[base]] = True
    object_offsets = np.zeros(len(base) + 1, dtype=np.int64)
    np.cumsum(np.add.reduceat(inside.astype(np.int64), offsets[:-1]) if len(base) else [], out=object_offsets[1:])
    own_in_scene = np.cumsum(inside)[offsets[:-1] + own[base]] - 1 - object_offsets[:-1]
    kept = full_slot[inside]
    passive = ~blocks[kept] & ~clear[inside] if passive_targets and objects.blocks is not None else None
    return Views(base, object_offsets, slot_row[kept], clear[inside], keep[inside], own_in_scene, passive)


@njit(cache=True)
def _assign_groups(target_offsets, transparent, blocks, wanted, centre, half, near, far, all_main):
    """Per slot, the view that gives its row: 0 the main view, ``k >= 1`` the ``k``-th group of wanted targets
    that may not block (greedily by direction, no two members of a group sharing a direction), -1 none; and per
    viewpoint, its number of views (the main view counted when it gives rows). With ``all_main``, every wanted
    target is in the main view (the engine measures those that may not block as passive targets).

    A wanted target that may not block joins the main view, opaque, when it may be in front of none of the main
    view's opaque targets and none of the main view's other non-blocking targets may be in front of it: there it
    hides no row but its own, and only blocking bodies can hide it."""
    group = np.full(len(transparent), -1, dtype=np.int64)
    counts = np.zeros(len(target_offsets) - 1, dtype=np.int64)
    for v in range(len(target_offsets) - 1):
        t0, t1 = target_offsets[v], target_offsets[v + 1]
        has_main = False
        free = np.zeros(t1 - t0, dtype=np.int64)
        n_free = 0
        for s in range(t0, t1):
            if not wanted[s]:
                continue
            if blocks[s] or transparent[s] or all_main:
                group[s] = 0
                has_main = True
            else:
                free[n_free] = s
                n_free += 1
        order = free[:n_free][argsort_stable(centre[free[:n_free]])]
        n_left = 0
        for m in order:  # first into the main view, where it hides no row
            joins = True
            for s in range(t0, t1):
                if group[s] != 0 or transparent[s]:
                    continue
                if may_be_in_front(centre[m], half[m], near[m], centre[s], half[s], far[s]) or (
                    not blocks[s] and may_be_in_front(centre[s], half[s], near[s], centre[m], half[m], far[m])
                ):
                    joins = False
                    break
            if joins:
                group[m] = 0
                has_main = True
            else:
                order[n_left] = m
                n_left += 1
        n_groups = 0
        for m in order[:n_left]:
            chosen = n_groups + 1
            for g in range(1, n_groups + 1):
                fits = True
                for s in range(t0, t1):
                    if group[s] == g and spans_share(centre[s], half[s], centre[m], half[m]):
                        fits = False
                        break
                if fits:
                    chosen = g
                    break
            group[m] = chosen
            n_groups = max(n_groups, chosen)
        counts[v] = n_groups + (1 if has_main else 0)
    return group, counts


@njit(cache=True)
def _fill_views(target_offsets, transparent, blocks, group, counts, centre, half, near, far):
    """The fields of :class:`Views` from :func:`_assign_groups`: in each view, its targets and the blocking
    bodies that may be in front of one of them (sharing a direction, not farther than all of it) are seen."""
    n_views = counts.sum()
    base = np.empty(n_views, dtype=np.int64)
    offsets = np.zeros(n_views + 1, dtype=np.int64)
    e = 0
    for v in range(len(counts)):
        for _ in range(counts[v]):
            base[e] = v
            offsets[e + 1] = offsets[e] + target_offsets[v + 1] - target_offsets[v]
            e += 1
    clear = np.ones(offsets[-1], dtype=np.bool_)
    keep = np.zeros(offsets[-1], dtype=np.bool_)
    e = 0
    for v in range(len(counts)):
        t0, t1 = target_offsets[v], target_offsets[v + 1]
        has_main = False
        n_groups = 0
        for s in range(t0, t1):
            if group[s] == 0:
                has_main = True
            n_groups = max(n_groups, group[s])
        for g in range(0 if has_main else 1, n_groups + 1):
            at = offsets[e] - t0
            for s in range(t0, t1):
                if group[s] != g:
                    continue
                keep[at + s] = True
                if transparent[s]:
                    continue
                clear[at + s] = False
                for b in range(t0, t1):
                    if clear[at + b] and blocks[b] and not transparent[b]:
                        if may_be_in_front(centre[b], half[b], near[b], centre[s], half[s], far[s]):
                            clear[at + b] = False
            e += 1
    return base, offsets, clear, keep


def passive_in_place(objects: ObjectTable | FrameObjects, engine: type | object) -> bool:
    """Whether the choices are ``occluders=`` alone and the engine measures passive targets itself: then the
    viewpoints go to it as they are (:func:`with_passive_targets`), with no views."""
    return objects.wanted is None and objects.blocks is not None and bool(engine.passive_targets)


def with_passive_targets(views: ChunkViewpoints, owners: np.ndarray, objects: ObjectTable) -> ChunkViewpoints:
    """A chunk's viewpoints as they are, the targets that may not block marked passive: for ``occluders=``
    alone (every target wanted) through an engine that measures passive targets itself."""
    sizes = np.diff(views.target_offsets)
    slot_row = np.repeat(owners - views.own, sizes) + _ranks(sizes)
    passive = ~objects.blocks[slot_row] & ~views.transparent
    return ChunkViewpoints(
        views.frame_starts, views.position, views.own, views.target_offsets, views.transparent,
        views.static_offsets, views.static_inside, passive,
    )  # fmt: skip


def frame_with_passive_targets(objects: FrameObjects, viewpoints: list[Viewpoint]) -> list[Viewpoint]:
    """:func:`with_passive_targets` for one frame's viewpoints."""
    return [replace(v, passive=~objects.blocks & ~np.asarray(v.transparent, dtype=bool)) for v in viewpoints]


def chunk_scenes(
    views: ChunkViewpoints, owners: np.ndarray, objects: ObjectTable, passive_targets: bool = False
) -> tuple[ObjectTable, ChunkViewpoints, Views]:
    """A chunk's viewpoints expanded into views, each view's scene one frame of a new table (the views as
    viewpoints the engines take, one per frame); ``passive_targets`` as for :func:`expand`."""
    first_row = owners - views.own
    expanded = expand(
        views.position, views.own, views.target_offsets, views.transparent, first_row, objects, passive_targets
    )
    b, rows = expanded.base, expanded.rows
    scenes = ObjectTable(
        objects.frame[rows],
        objects.total_nanos[rows],
        objects.idx[rows],
        objects.position[rows],
        objects.yaw[rows],
        objects.rings.take(rows),
        expanded.object_offsets,
        None if objects.boxes3d is None else objects.boxes3d[rows],
    )
    inside = np.diff(views.static_offsets)[b]
    static_offsets = np.zeros(len(b) + 1, dtype=np.int64)
    np.cumsum(inside, out=static_offsets[1:])
    static_inside = views.static_inside[np.repeat(views.static_offsets[b], inside) + _ranks(inside)]
    chunk = ChunkViewpoints(
        np.arange(len(b) + 1, dtype=np.int64),
        views.position[b],
        expanded.own,
        expanded.object_offsets,
        expanded.transparent,
        static_offsets,
        static_inside,
        expanded.passive,
    )
    return scenes, chunk, expanded


def _ranks(sizes: np.ndarray) -> np.ndarray:
    """0, 1, ... within each of consecutive groups of ``sizes``."""
    starts = np.zeros(len(sizes) + 1, dtype=np.int64)
    np.cumsum(sizes, out=starts[1:])
    return np.arange(starts[-1]) - np.repeat(starts[:-1], sizes)


def frame_scenes(
    objects: FrameObjects, viewpoints: list[Viewpoint], passive_targets: bool = False
) -> tuple[list[tuple[FrameObjects, Viewpoint]], Views]:
    """One frame's viewpoints expanded into views: each view's scene and its viewpoint in that scene
    (``passive_targets`` as for :func:`expand`)."""
    n = len(objects)
    own = np.array([v.own for v in viewpoints], dtype=np.int64)
    offsets = np.arange(len(viewpoints) + 1, dtype=np.int64) * n
    positions = np.array([v.position for v in viewpoints], dtype=np.float64).reshape(-1, 2)
    transparent = np.concatenate([v.transparent for v in viewpoints]) if viewpoints else np.zeros(0, dtype=bool)
    first_row = np.zeros(len(viewpoints), dtype=np.int64)
    expanded = expand(positions, own, offsets, transparent, first_row, objects, passive_targets)
    out = []
    for e, b in enumerate(expanded.base.tolist()):
        at = slice(expanded.object_offsets[e], expanded.object_offsets[e + 1])
        rows = expanded.rows[at]
        scene = FrameObjects(
            objects.frame,
            objects.total_nanos,
            objects.idx[rows],
            objects.position[rows],
            objects.yaw[rows],
            objects.rings.take(rows),
            None if objects.boxes3d is None else objects.boxes3d[rows],
        )
        v = viewpoints[b]
        view = Viewpoint(
            v.position, v.heading, int(expanded.own[e]), expanded.transparent[at], v.static_transparent, v.fov,
            v.range, v.height, v.vertical_fov, v.pitch, None if expanded.passive is None else expanded.passive[at],
        )  # fmt: skip
        out.append((scene, view))
    return out, expanded


def kept_rows(columns: Columns, views: Views) -> Columns:
    """The rows of ``columns`` (each view's scene but its observer, view by view) that their view keeps,
    ordered by viewpoint and then ``idx``, as without the choices."""
    not_own = np.ones(len(views.keep), dtype=bool)
    not_own[views.object_offsets[:-1] + views.own] = False
    keep = views.keep[not_own]
    n_rows = len(columns["idx"])
    if len(keep) != n_rows:  # the engines' contract was broken
        raise AssertionError(f"{n_rows} rows for {len(keep)} targets")
    base = np.repeat(views.base, np.diff(views.object_offsets) - 1)[keep]
    rows = np.flatnonzero(keep)
    order = rows[np.lexsort((columns["idx"][rows], base))]
    return take_rows(columns, order)


def take_rows(columns: Columns, rows: np.ndarray) -> Columns:
    """The rows ``rows`` (positions, in that order) of named columns, list columns included."""
    out: Columns = {}
    for name, column in columns.items():
        if name in LIST_COLUMNS:
            lengths, values = column
            starts = np.zeros(len(lengths) + 1, dtype=np.int64)
            np.cumsum(lengths, out=starts[1:])
            picked = lengths[rows]
            out[name] = (picked, values[np.repeat(starts[rows], picked) + _ranks(picked)])
        else:
            out[name] = column[rows]
    return out
