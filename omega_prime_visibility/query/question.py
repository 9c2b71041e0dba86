"""The question: every option that shapes the visibility table, as one frozen value checked once.

A :class:`Query` says *what* to compute (who observes, in which mode, with which engine and measure, through which
sensors, who may block, whom to look for, the static occluders with their heights and meshes, the map's road
objects, what to do with unusable rows). *How* to run it (workers, chunks, progress, an output path) stays with the
call, as polars keeps a query apart from ``collect(engine=...)``. Every front end (``get_visibility_df``, the
Metric, the pictures, the command line, batch) builds one value and hands it on; the old keywords fold into it in
one function, :func:`fold_keywords`.

>>> q = Query(observers=0, engine="sweep", targets="pedestrians")
>>> q.engine, q.mode, q.measure
('sweep', '2d', 'angle')
>>> Query(observers=0).engine  # resolved: never None
'visilibity'
>>> Query(observers=0, mode="3d", measure="area")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
omega_prime_visibility.inputs.errors.OptionError: measure='area' measures footprints in 2D; ...
"""

from __future__ import annotations

import hashlib
import json
import numbers
import os
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np
import polars as pl
import shapely

from ..engines.registry import check_mode, resolve_measure
from ..inputs.errors import OptionError, Setting
from ..inputs.roles import RoleSpec, canonical_name, check_names
from ..inputs.sensor_files import resolve_sensors
from ..inputs.sensors import Sensor, is_layout
from ..inputs.statics import load_static_occluders
from ..threed.statics import check_heights


@contextmanager
def _option(name: str) -> Iterator[None]:
    """Within the block, a ValueError becomes an :class:`OptionError` naming the option ``name``."""
    try:
        yield
    except OptionError:
        raise
    except ValueError as e:
        raise OptionError.plain(name, str(e)) from None


@dataclass(frozen=True, eq=True)
class Query:
    """Every option that shapes the visibility table (see ``get_visibility_df`` for each one's meaning).

    Attributes
    ----------
    observers : int, tuple of int, "all" or None
        Who observes (``ego_idx``); None: the recording's host vehicle.
    mode : {"2d", "3d"}
    engine : str
        The engine, resolved from ``engine``, ``mode``, ``measure`` and ``static_meshes`` (never None).
    measure : {"angle", "area"}
    sensors : layout name, tuple of Sensor, or None
        A layout name stays a name (fitted to each observer's size when the recording is read); a file or Sensors
        become a tuple of :class:`~omega_prime_visibility.sensors.Sensor`.
    occluders, targets : names, idx, a polars expression or None
        Who may block the view, whom to look for (:mod:`omega_prime_visibility.inputs.roles`); lists become tuples.
    static_occluders : tuple of shapely geometries
    static_heights : float, tuple of float or None
        Tops of ``static_occluders`` (metres).
    static_meshes : tuple of paths or trimesh.Trimesh
        3D only.
    map_occluders : path, True or None
        An OpenDRIVE map (True: the recording's own) whose road objects block.
    on_invalid : {"warn", "raise"}
    """

    observers: int | tuple[int, ...] | str | None = None
    mode: str = "2d"
    engine: str | None = None
    measure: str = "angle"
    sensors: str | tuple[Sensor, ...] | None = None
    occluders: Any = None
    targets: Any = None
    static_occluders: tuple[shapely.Geometry, ...] = ()
    static_heights: float | tuple[float, ...] | None = None
    static_meshes: tuple[Any, ...] = ()
    map_occluders: str | bool | None = None
    on_invalid: str = "warn"

    def __post_init__(self) -> None:
        put = object.__setattr__
        with _option("ego_idx"):
            put(self, "observers", _observers(self.observers))
        with _option("mode"):
            put(self, "mode", check_mode(self.mode))
        meshes = self.static_meshes
        with _option("static_meshes"):
            meshes = () if meshes is None else (meshes,) if isinstance(meshes, str | os.PathLike) else tuple(meshes)
            if meshes and self.mode == "2d":
                raise ValueError("static_meshes are 3D occluders: pass mode='3d'")
        put(self, "static_meshes", meshes)
        with _option("measure" if self.measure != "angle" else "engine"):
            put(self, "engine", resolve_measure(self.measure, self.engine, self.mode, meshes=bool(meshes)))
        with _option("sensors"):
            if not is_layout(self.sensors) and self.sensors is not None:
                put(self, "sensors", resolve_sensors(self.sensors))
                counting = [s.name for s in self.sensors if s.kind != "view"]
                if counting and self.mode != "3d":
                    names = ", ".join(counting).replace("{", "{{").replace("}", "}}")
                    raise OptionError(
                        "sensors",
                        f"cameras and lidars count pixels and beams among 3D boxes ({names}): pass {{fix}}",
                        fix=Setting("mode", "3d"),
                    )
                if counting and meshes:
                    raise ValueError(
                        f"cameras and lidars ({', '.join(counting)}) count among boxes and static footprints with "
                        "heights; static_meshes are not convex bodies: give the buildings as footprints with heights"
                    )
        for name in ("occluders", "targets"):
            with _option(name):
                put(self, name, _choice(getattr(self, name), name))
        with _option("static_occluder_polys"):
            statics = self.static_occluders
            statics = () if statics is None else (statics,) if isinstance(statics, shapely.Geometry) else tuple(statics)
            load_static_occluders(list(statics))  # every geometry checked once, here
        put(self, "static_occluders", statics)
        with _option("static_occluder_heights"):
            heights = self.static_heights
            if heights is not None:
                check_heights(heights, len(statics))
                put(self, "static_heights", float(heights) if np.ndim(heights) == 0 else tuple(map(float, heights)))
        with _option("map_occluders"):
            if self.map_occluders is False:
                raise ValueError("map_occluders must be a path, True (the recording's map) or None")
            if self.map_occluders not in (None, True):
                put(self, "map_occluders", os.fspath(self.map_occluders))
        with _option("on_invalid"):
            if self.on_invalid not in ("warn", "raise"):
                raise ValueError(
                    f"on_invalid takes 'warn' (skip bad rows with a warning) or 'raise', not {self.on_invalid!r}"
                )

    def replace(self, **changes: Any) -> Query:
        """A copy with ``changes`` (checked again)."""
        return replace(self, **changes)

    @property
    def three_d(self) -> bool:
        return self.mode == "3d"

    def text(self) -> str:
        """A stable JSON text of the question: equal questions give equal texts, whatever the spelling (names of
        groups and types in one case, lists sorted); files and geometries by the SHA-256 of their content.

        Examples
        --------
        >>> Query(observers=[1, 0], targets=["CAR", "pedestrians"]).text() == Query(observers=(0, 1),
        ...     targets=["Pedestrians", "car"]).text()
        True
        """
        values: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "sensors" and isinstance(value, tuple):
                value = [s.to_dict() if hasattr(s, "to_dict") else _sensor_dict(s) for s in value]
            elif f.name == "static_occluders":
                value = [hashlib.sha256(shapely.to_wkb(g, hex=False)).hexdigest() for g in value]
            elif f.name == "static_meshes":
                value = [_content_hash(m) for m in value]
            elif f.name == "map_occluders" and isinstance(value, str):
                value = {"path": value, "sha256": _content_hash(value)}
            elif isinstance(value, pl.Expr):  # exactly, as polars serialises it (its text may be shortened)
                value = {"expression": value.meta.serialize(format="json")}
            values[f.name] = value
        return json.dumps(values, sort_keys=True, default=str)


def _observers(value: Any) -> int | tuple[int, ...] | str | None:
    """``ego_idx`` as stored: an int, a sorted tuple of distinct ints, ``"all"`` or None."""
    if value is None or value == "all":
        return value
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return int(value)
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, Sequence) and not isinstance(value, str) and value:
        if all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in value):
            return tuple(sorted({int(v) for v in value}))
    raise ValueError(f"ego_idx must be an int, a list of ints or 'all', not {value!r}")


def _choice(value: RoleSpec, option: str) -> Any:
    """``occluders``/``targets`` as stored: None, a name, an expression, or a tuple of names or idx (checked)."""
    if value is None or isinstance(value, pl.Expr):
        return value
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, str):
        value = [value]
    if isinstance(value, Sequence) and not isinstance(value, bytes) and len(value):
        if all(isinstance(v, str) for v in value):  # one spelling, once each, in order: the same choice
            check_names(list(value), option)
            return tuple(sorted({canonical_name(v) for v in value}))
        if all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in value):
            return tuple(sorted({int(v) for v in value}))
        return tuple(value)  # a mix: refused with the roles' own words when the table is read
    raise ValueError(
        f"{option} takes a group or type name, a list of names, a list of idx or a polars expression, not {value!r}"
    )


def _sensor_dict(sensor: Sensor) -> dict[str, Any]:
    return {f.name: getattr(sensor, f.name) for f in fields(sensor)}


def _content_hash(item: Any) -> str:
    """SHA-256 of a file's bytes, or of a mesh's vertices and faces."""
    if isinstance(item, str | os.PathLike):
        path = Path(item)
        return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else f"missing: {path}"
    digest = hashlib.sha256()
    for name in ("vertices", "faces"):
        digest.update(np.ascontiguousarray(getattr(item, name, np.zeros(0))).tobytes())
    return digest.hexdigest()


TABLE_KEYWORDS = {
    "ego_idx": "observers",
    "engine": "engine",
    "mode": "mode",
    "measure": "measure",
    "sensors": "sensors",
    "occluders": "occluders",
    "targets": "targets",
    "static_occluder_polys": "static_occluders",
    "static_occluder_heights": "static_heights",
    "static_meshes": "static_meshes",
    "map_occluders": "map_occluders",
    "on_invalid": "on_invalid",
}
"""The keywords of ``get_visibility_df`` (and the Metric, the pictures) that shape the table, by the field of
:class:`Query` they fill."""


def fold_keywords(query: Query | None, **keywords: Any) -> Query:
    """The question of a call: ``query`` with the table-shaping keywords of :data:`TABLE_KEYWORDS` folded in (a
    keyword left at None is not given). Without ``query``, the keywords make one; with it, a keyword that
    contradicts it is an error naming both.

    >>> fold_keywords(None, ego_idx=3, engine="sweep").engine
    'sweep'
    >>> fold_keywords(Query(observers=3, engine="sweep"), engine="visilibity")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    omega_prime_visibility.inputs.errors.OptionError: engine='visilibity' contradicts the query's ...
    """
    unknown = sorted(set(keywords) - set(TABLE_KEYWORDS))
    if unknown:
        raise TypeError(f"unexpected keyword argument {unknown[0]!r}")
    given = {TABLE_KEYWORDS[k]: v for k, v in keywords.items() if v is not None and not _empty(v)}
    if query is None:
        return Query(**given)
    if not isinstance(query, Query):
        raise TypeError(f"query must be an omega_prime_visibility.Query, not {type(query).__name__}")
    values = {f.name: getattr(query, f.name) for f in fields(query)}
    for field_name, value in given.items():
        try:  # each keyword alone against the query: one that cannot stand with it contradicts it too
            agrees = _same(Query(**values | {field_name: value}), query, field_name)
        except OptionError:
            agrees = False
        if not agrees:
            keyword = next(k for k, v in TABLE_KEYWORDS.items() if v == field_name)
            given_text, query_text = _shown(keywords[keyword]), _shown(getattr(query, field_name))
            raise OptionError.plain(
                keyword, f"{keyword}={given_text} contradicts the query's {field_name}={query_text}; give one of them"
            )
    return query


def _shown(value: Any) -> str:
    """A value as a message shows it (an expression by its text)."""
    return f"<expression {value}>" if isinstance(value, pl.Expr) else repr(value)


def _empty(value: Any) -> bool:
    """An empty sequence of static meshes or occluders is as good as none."""
    return isinstance(value, tuple | list) and not value


def _same(a: Query, b: Query, name: str) -> bool:
    """Whether two values of one field say the same (expressions by their text, geometries exactly; an expression
    is never compared with ``==``, which builds another expression)."""
    x, y = getattr(a, name), getattr(b, name)
    if isinstance(x, pl.Expr) or isinstance(y, pl.Expr):
        return isinstance(x, pl.Expr) and isinstance(y, pl.Expr) and str(x) == str(y)
    if name == "static_occluders":
        return len(x) == len(y) and all(g.equals_exact(h, 0.0) for g, h in zip(x, y, strict=True))
    return bool(x == y)
