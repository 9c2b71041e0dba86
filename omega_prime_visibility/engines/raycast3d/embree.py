"""Embree (through ``embreex``) as a first-hit oracle: one scene of triangles, rays cast in batches.

Embree works in float32, so every scene is built in coordinates centred on an eye point: its triangles and ray
origins are given relative to that point (relative rounding 6e-8 of the distance from it, 6 µm at 100 m).
"""

from __future__ import annotations

import os

import numpy as np

_DEVICE: dict[int, object] = {}


def device() -> object:
    """One Embree device per process (made again after a fork: a device's threads do not survive one)."""
    pid = os.getpid()
    if pid not in _DEVICE:
        from embreex import rtcore

        _DEVICE.clear()
        _DEVICE[pid] = rtcore.EmbreeDevice()
    return _DEVICE[pid]


class FirstHit:
    """The first triangle hit along rays, in a scene built once.

    Parameters
    ----------
    triangles : ndarray, shape (k, 3, 3)
        Metres, already relative to the scene's centre.

    Examples
    --------
    >>> tri = np.array([[[5.0, -1, -1], [5, 1, -1], [5, 0, 1]]])
    >>> prim, dist = FirstHit(tri).cast(np.zeros((2, 3)), np.array([[1.0, 0, 0], [-1.0, 0, 0]]))
    >>> prim.tolist(), round(float(dist[0]), 5)  # (Embree works in float32)
    ([0, -1], 5.0)
    """

    def __init__(self, triangles: np.ndarray) -> None:
        self.size = len(triangles)
        self._scene = None
        if self.size:
            from embreex import rtcore_scene
            from embreex.mesh_construction import TriangleMesh

            self._scene = rtcore_scene.EmbreeScene(device())
            TriangleMesh(self._scene, np.ascontiguousarray(triangles, dtype=np.float32))

    def cast(self, origins: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Triangle number (-1: none) and distance (inf: none) of the first hit of every ray, in one call.

        ``directions`` are unit vectors (distances are in units of their length).
        """
        m = len(directions)
        if self._scene is None or m == 0:
            return np.full(m, -1, dtype=np.int64), np.full(m, np.inf)
        result = self._scene.run(
            np.ascontiguousarray(origins, dtype=np.float32),
            np.ascontiguousarray(directions, dtype=np.float32),
            output=1,
        )
        prim = result["primID"].astype(np.int64)
        dist = np.where(prim >= 0, result["tfar"].astype(np.float64), np.inf)
        return prim, dist


HIT_MARGIN = (1e-4, 1e-5)
"""Metres and share of the distance by which an Embree hit (float32) must come before a body's exact entry to be
in front of it: ties, and what float32 cannot tell from them, are visible."""
MAX_HITS = 256
"""Surfaces a ray is followed through at most when every hit before a distance is wanted."""


def hits_before(
    scene: FirstHit, owner: np.ndarray, origins: np.ndarray, directions: np.ndarray, limit: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Every owner met along each ray before its ``limit`` (by :data:`HIT_MARGIN`), not only the first.

    Each ray is cast again from just beyond each surface it meets, so a mesh behind another, or behind a box, is
    found too.

    Parameters
    ----------
    scene : FirstHit
        Triangles relative to the scene's centre; ``owner[k]`` of triangle ``k``.
    origins, directions : ndarray, shape (m, 3)
        Ray origins (relative to the scene's centre) and unit directions.
    limit : ndarray, shape (m,)
        Metres along each ray: what is met before it (less the margin) is listed.

    Returns
    -------
    (ndarray, ndarray)
        Pairs ``(ray, owner)``, each pair once.

    Examples
    --------
    Two walls across the x axis at 5 m and 8 m (owners 7 and 9), a target at 10 m: both are in front of it.

    >>> wall = lambda x: [[x, -1, -1], [x, 1, -1], [x, 0, 1]]
    >>> scene = FirstHit(np.array([wall(5.0), wall(8.0)]))
    >>> ray, who = hits_before(scene, np.array([7, 9]), np.zeros((1, 3)), np.array([[1.0, 0, 0]]), np.array([10.0]))
    >>> ray.tolist(), who.tolist()
    ([0, 0], [7, 9])
    """
    rays, owners = [], []
    travelled = np.zeros(len(directions))
    active = np.flatnonzero(np.isfinite(limit) & (limit > 0))  # (a ray that misses its target lists nothing)
    for _ in range(MAX_HITS):
        if not len(active):
            break
        start = origins[active] + travelled[active, None] * directions[active]
        prim, dist = scene.cast(start, directions[active])
        at = travelled[active] + dist
        ahead = (prim >= 0) & (at < limit[active] - HIT_MARGIN[0] - HIT_MARGIN[1] * limit[active])
        active, at, prim = active[ahead], at[ahead], prim[ahead]
        rays.append(active)
        owners.append(owner[prim])
        travelled[active] = at + HIT_MARGIN[0] + HIT_MARGIN[1] * at  # on, just beyond the surface met
    if not rays:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    pairs = np.unique(np.column_stack([np.concatenate(rays), np.concatenate(owners)]).astype(np.int64), axis=0)
    return pairs[:, 0], pairs[:, 1]
