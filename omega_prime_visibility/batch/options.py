"""The options every recording of a batch is computed with, stored as JSON in each result."""

from __future__ import annotations

import hashlib
import json
import numbers
import os
from dataclasses import asdict, dataclass, field, fields
from functools import lru_cache
from pathlib import Path
from typing import Any

from ..inputs.sensors import LAYOUTS
from ..query import Query


@dataclass(frozen=True)
class FileOptions:
    """What every recording of a batch is computed with; stored in each result, so other options recompute it.

    Adding an option: a field here (``metadata={"file": True}`` for a path whose content matters), its place in
    :meth:`question`, and the matching ``batch`` command-line option.

    Attributes
    ----------
    ego : int, tuple of int, "all" or None
        Observer idx; None takes each recording's host vehicle (a file without one fails, asking for an ego).
    engine : str, optional
        Engine name (``omega_prime_visibility.ENGINES``, or ``ENGINES_3D`` in 3D); by default the mode's default.
    static : str, optional
        GeoJSON or WKT file of static occluders (metres, recording frame), see :func:`io.read_static_occluders`.
    map : str, optional
        OpenDRIVE map for OSI traces (MCAP files carry their own), or a JSON list of ``[trace name, map]`` pairs
        (map paths relative to the JSON file) when traces use different maps.
    sensors : str, optional
        A sensor layout name (``"roof"``, ``"typical"``) or a sensors JSON file (see :mod:`sensors`).
    mode : {"2d", "3d"}
        Bird's-eye view (exact) or boxes with heights (see ``get_visibility_df``).
    map_occluders : bool
        The map's road objects as static occluders (the ``map`` file for OSI traces, else the recording's own).
    occluders, targets : str, tuple of str or tuple of int, optional
        Who may block the view and who gets rows (names or idx, as for ``get_visibility_df``; a polars expression
        cannot be stored with the results, so batch takes names and idx only). None: everyone.
    measure : {"angle", "area"}
        What ``visibility`` is a share of (see ``get_visibility_df``).
    conflicts : bool
        Also write each recording's occluded conflicts (``occluded_conflicts`` with its defaults: a PET of 3 s, a
        5 s look-back, the notice model ``(1.0, 1.5)``) beside its result, as ``<result>.conflicts.parquet``.

    Examples
    --------
    >>> FileOptions(ego=[1, 0], engine="sweep").ego
    (0, 1)
    >>> FileOptions(ego="ALL")
    Traceback (most recent call last):
    ...
    ValueError: ego must be an idx, a list of idx, 'all' or None (the host vehicle), not 'ALL'
    """

    ego: int | tuple[int, ...] | str | None = None
    engine: str | None = None
    static: str | None = field(default=None, metadata={"file": True})
    map: str | None = field(default=None, metadata={"file": True})
    sensors: str | None = field(default=None, metadata={"file": True, "names": tuple(LAYOUTS)})
    mode: str = "2d"
    map_occluders: bool = False
    conflicts: bool = False
    occluders: str | tuple[str, ...] | tuple[int, ...] | None = None
    targets: str | tuple[str, ...] | tuple[int, ...] | None = None
    measure: str = "angle"

    def __post_init__(self) -> None:
        from ..engines.registry import check_mode, resolve_engine, resolve_measure
        from ..inputs.sensors import resolve_sensors

        ego = self.ego
        if isinstance(ego, list | tuple) and ego and all(is_int(v) for v in ego):
            object.__setattr__(self, "ego", tuple(sorted({int(v) for v in ego})))
        elif is_int(ego):
            object.__setattr__(self, "ego", int(ego))
        elif ego is not None and ego != "all":
            raise ValueError(f"ego must be an idx, a list of idx, 'all' or None (the host vehicle), not {ego!r}")
        object.__setattr__(self, "mode", check_mode(self.mode))
        resolve_measure(self.measure, self.engine, self.mode)
        if self.measure == "angle":
            object.__setattr__(self, "engine", resolve_engine(self.engine, self.mode))
        for name in ("occluders", "targets"):
            object.__setattr__(self, name, _choice(getattr(self, name), name))
        resolve_sensors(self.sensors)  # an unknown layout or a bad sensors file: ValueError naming it
        for f in fields(self):
            value = getattr(self, f.name)
            if f.metadata.get("file") and value is not None and value not in f.metadata.get("names", ()):
                path = Path(value)
                if not path.is_file():
                    what = "is not a file" if path.exists() else "does not exist"
                    raise ValueError(f"the {f.name} file {path} {what}")
                object.__setattr__(self, f.name, os.path.abspath(path))  # as given: a link stays the link

    def question(self, ego: Any, statics: Any, map_path: str | None = None) -> Query:
        """The question of one recording read with ``map_path``: these options with its observer(s) and static
        occluders (:class:`~omega_prime_visibility.Query`)."""
        map_occluders = (map_path or True) if self.map_occluders else None
        return Query(
            observers=ego,
            engine=self.engine,
            mode=self.mode,
            measure=self.measure,
            sensors=self.sensors,
            occluders=self.occluders,
            targets=self.targets,
            static_occluders=statics or (),
            map_occluders=map_occluders,
        )

    def fingerprint(self) -> str:
        """JSON of the options, with the SHA-256 of every file option's content (an edited file recomputes)."""
        values = asdict(self)
        for f in fields(self):
            if f.metadata.get("file") and values[f.name] not in (None, *f.metadata.get("names", ())):
                values[f.name] = {"path": values[f.name], "sha256": _sha256(values[f.name])}
        return json.dumps(values, sort_keys=True)

    def check(self) -> None:
        """Read the option files once before any work, so a bad file fails the run instead of every recording."""
        from ..inputs.io import RecordingReadError, read_static_occluders
        from ..inputs.statics import load_static_occluders

        try:
            if self.static is not None:
                load_static_occluders(read_static_occluders(self.static))
            if self.map is not None and Path(self.map).suffix == ".json":
                _map_table(self.map, Path(self.map).stat().st_mtime_ns)
        except RecordingReadError as e:
            raise ValueError(str(e)) from None

    def map_for(self, recording: Path) -> str | None:
        """The map to read ``recording`` with: None for MCAP files (their map is inside); ``ValueError`` for a trace
        a map list does not name (as ``run --map LIST.json`` refuses it: a forgotten line would silently lose the
        map's road objects)."""
        if self.map is None or recording.suffix == ".mcap":
            return None
        if Path(self.map).suffix == ".json":
            table = _map_table(self.map, Path(self.map).stat().st_mtime_ns)
            if recording.name not in table and recording.resolve().name in table:  # a link to a listed trace
                recording = recording.resolve()
            if recording.name not in table:
                raise ValueError(
                    f"the map list {self.map} has no map for {recording.name} (it lists {', '.join(sorted(table))})"
                )
            return table[recording.name]
        return self.map


def _choice(value: Any, option: str) -> str | tuple | None:
    """``occluders``/``targets`` as stored: a name, or a sorted tuple of names or idx (checked); names in one
    spelling (groups in lower case, omega-prime types and subtypes in upper case), so that ``CAR`` and ``car``
    are one choice and a rerun with either skips the files already done."""
    from ..inputs.roles import canonical_name, check_names

    if value is None:
        return None
    if isinstance(value, str):
        check_names([value], option)
        return canonical_name(value)
    if isinstance(value, list | tuple) and value and all(is_int(v) for v in value):
        return tuple(sorted({int(v) for v in value}))
    if isinstance(value, list | tuple) and value and all(isinstance(v, str) for v in value):
        check_names(value, option)
        return tuple(sorted({canonical_name(v) for v in value}))
    raise ValueError(
        f"{option} in a batch takes a name, a list of names or a list of idx (a polars expression cannot be stored "
        f"with the results), not {value!r}"
    )


def is_int(value: object) -> bool:
    """Whether ``value`` is a whole number (Python or numpy integer, not a bool)."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _sha256(path: str) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


@lru_cache
def _map_table(path: str, mtime_ns: int) -> dict[str, str]:
    """``{trace file name: absolute map path}`` from a JSON list of pairs or object (paths relative to the JSON);
    cached per file version."""
    expected = f"cannot read the map list {path}: expected a JSON list of [trace, map] pairs of file names"
    try:
        pairs = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as e:
        raise ValueError(f"cannot read the map list {path} ({e.strerror or e})") from None
    except ValueError as e:
        raise ValueError(f"{expected} (not JSON: {e})") from None
    pairs = list(pairs.items()) if isinstance(pairs, dict) else pairs
    if not isinstance(pairs, list) or not all(
        isinstance(pair, list | tuple) and len(pair) == 2 and all(isinstance(v, str) and v for v in pair)
        for pair in pairs
    ):
        raise ValueError(f'{expected}, such as [["trace.osi", "map.xodr"]]; it holds {json.dumps(pairs)[:80]}')
    table = {trace: os.path.abspath(Path(path).parent / m) for trace, m in pairs}
    missing = sorted({m for m in table.values() if not Path(m).is_file()})
    if missing:
        raise ValueError(f"the map list {path} names maps that do not exist: {', '.join(missing[:5])}")
    return table
