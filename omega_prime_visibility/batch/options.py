"""The options every recording of a batch is computed with, stored as JSON in each result."""

from __future__ import annotations

import hashlib
import json
import numbers
import os
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

from ..inputs.errors import OptionError
from ..query import Query, fold_keywords

BATCH_KEYWORDS = {
    "ego": "ego_idx",
    "engine": "engine",
    "mode": "mode",
    "measure": "measure",
    "sensors": "sensors",
    "occluders": "occluders",
    "targets": "targets",
    "static": "static_occluder_polys",
    "map_occluders": "map_occluders",
}
"""``run_batch``'s keywords that shape the table, by the keyword of ``get_visibility_df`` they stand for (``static``
is a file read once, ``map_occluders`` a flag: the map each recording is read with)."""


@dataclass(frozen=True)
class FileOptions:
    """What every recording of a batch is computed with; stored in each result, so other options recompute it.

    Attributes
    ----------
    query : Query
        The question (:class:`~omega_prime_visibility.Query`); its observers None take each recording's host
        vehicle (a file without one fails, asking for an ego), its ``map_occluders=True`` the map each recording
        is read with.
    map : str, optional
        OpenDRIVE map for OSI traces (MCAP files carry their own), or a JSON list of ``[trace name, map]`` pairs
        (map paths relative to the JSON file) when traces use different maps.
    conflicts : bool
        Also write each recording's occluded conflicts (``occluded_conflicts`` with its defaults: a PET of 3 s, a
        5 s look-back, the notice model ``(1.0, 1.5)``) beside its result, as ``<result>.conflicts.parquet``.
    fallback_ego : int, optional
        With the observers None: the observer of a recording that names no host vehicle (esmini's OSI traces name
        none; its first entity, idx 0, is usually the ego); without it such a recording fails, saying so.
    mcap : bool
        Also write each recording with the answer drawn in (:func:`~omega_prime_visibility.write_mcap`: its own
        channels, the scene and rows per observer and sensor, OSI SensorData) beside its result, as
        ``<result>.mcap``.

    Examples
    --------
    >>> FileOptions.of(None, ego=[1, 0], engine="sweep").query.observers
    (0, 1)
    >>> FileOptions.of(Query(observers=0, targets="Pedestrians"), conflicts=True).query.targets
    ('pedestrians',)
    """

    query: Query = field(default_factory=Query)
    map: str | None = None
    conflicts: bool = False
    fallback_ego: int | None = None
    mcap: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.query, Query):
            raise TypeError(f"query must be an omega_prime_visibility.Query, not {type(self.query).__name__}")
        fallback = self.fallback_ego
        if fallback is not None:
            if isinstance(fallback, bool) or not isinstance(fallback, numbers.Integral):
                raise OptionError.plain("fallback_ego", f"fallback_ego takes one idx, not {fallback!r}")
            if self.query.observers is not None:
                raise OptionError.plain(
                    "fallback_ego",
                    f"fallback_ego applies where the observer is each recording's host vehicle; the observers are "
                    f"given ({self.query.observers!r}), so it would never be used",
                )
            object.__setattr__(self, "fallback_ego", int(fallback))
        if self.map is not None:
            path = Path(self.map)
            if not path.is_file():
                raise ValueError(f"the map file {path} {'is not a file' if path.exists() else 'does not exist'}")
            object.__setattr__(self, "map", os.path.abspath(path))  # as given: a link stays the link

    @classmethod
    def of(
        cls,
        query: Query | None = None,
        *,
        map: Any = None,
        conflicts: bool = False,
        fallback_ego: int | None = None,
        mcap: bool = False,
        **keywords: Any,
    ) -> FileOptions:
        """The options of ``run_batch(query, ..., **keywords)``: the keywords of :data:`BATCH_KEYWORDS` folded into
        ``query`` (a keyword that contradicts it is an error naming both), the static file read once."""
        from ..inputs.io import RecordingReadError, read_static_file

        unknown = sorted(set(keywords) - set(BATCH_KEYWORDS))
        if unknown:
            known = ["query", "map", "conflicts", "fallback_ego", "mcap", *BATCH_KEYWORDS]
            raise ValueError(f"unknown option(s) {unknown}; options are {known}")
        table = {BATCH_KEYWORDS[k]: v for k, v in keywords.items()}
        if table.get("map_occluders") is False:
            table["map_occluders"] = None
        static = table.get("static_occluder_polys")
        if isinstance(static, str | os.PathLike):
            try:
                found = read_static_file(static)
            except RecordingReadError as e:
                raise OptionError.plain("static", str(e)) from None
            table["static_occluder_polys"] = found.geometries
            if found.heights is not None and table.get("static_occluder_heights") is None:
                table["static_occluder_heights"] = found.heights  # (the file's own heights)
        return cls(fold_keywords(query, **table), map, conflicts, fallback_ego, bool(mcap))

    def question(self, recording: Any, name: str, map_path: str | None) -> Query:
        """The question of one recording (read from the file ``name`` with ``map_path``): the observers settled
        (:meth:`observer`) and ``map_occluders=True`` made the map it was read with."""
        query = self.query
        if query.observers is None:
            query = query.replace(observers=self.observer(recording, name)[0])
        if query.map_occluders is True and map_path is not None:
            query = query.replace(map_occluders=map_path)
        return query

    def observer(self, recording: Any, name: str) -> tuple[Any, str]:
        """Whom the recording read from the file ``name`` is seen from, and how that was chosen, in a reader's
        words: the observers given, else its host vehicle, else :attr:`fallback_ego`; ``ValueError`` for a
        recording that names no host vehicle when there is no fallback.

        >>> class Trace:
        ...     host_vehicle_idx = None
        >>> FileOptions.of(fallback_ego=0).observer(Trace(), "cut-in.osi")
        (0, 'idx 0 (fallback: names no host vehicle)')
        >>> FileOptions.of(ego="all").observer(Trace(), "cut-in.osi")
        ('all', 'every road user')
        """
        from ..inputs.observers import observer_words

        given = self.query.observers
        if given is not None:
            return given, observer_words(given, recording)
        host = recording.host_vehicle_idx
        if host is not None:
            return int(host), f"host vehicle idx {int(host)}"
        if self.fallback_ego is not None:
            return self.fallback_ego, f"idx {self.fallback_ego} (fallback: names no host vehicle)"
        from ..inputs.roles import kinds_present
        from ..inputs.scene import as_polars

        raise ValueError(
            f"{name} names no host vehicle: give an observer for such recordings (--fallback-ego IDX keeps each "
            f"recording's host vehicle where it names one), or one for all (--ego IDX, --ego all); "
            f"present: {kinds_present(as_polars(recording))}"
        )

    def fingerprint(self) -> str:
        """JSON of the options: the question's text (files and geometries by their content, see
        :meth:`Query.text`) and the map with the SHA-256 of its content (an edited file recomputes)."""
        values = {"query": json.loads(self.query.text()), "conflicts": self.conflicts, "map": self.map}
        if self.fallback_ego is not None:  # (only when given: results made before it stay current)
            values["fallback_ego"] = self.fallback_ego
        if self.mcap:  # (likewise)
            values["mcap"] = True
        if self.map is not None:
            values["map"] = {"path": self.map, "sha256": _sha256(self.map)}
        return json.dumps(values, sort_keys=True)

    @staticmethod
    def stored(text: str) -> dict[str, Any]:
        """The options a result was computed with, from its stored :meth:`fingerprint`, as one flat dict named as
        ``run_batch``'s keywords (``ego``: the observers, None for each recording's host vehicle).

        >>> FileOptions.stored(FileOptions.of(ego=3, engine="sweep").fingerprint())["ego"]
        3
        """
        values = json.loads(text)
        question = values.pop("query", {})
        question["ego"] = question.pop("observers", None)
        return question | values

    def check(self) -> None:
        """Read the map list once before any work, so a bad list fails the run instead of every recording."""
        if self.map is not None and Path(self.map).suffix == ".json":
            _map_table(self.map, Path(self.map).stat().st_mtime_ns)

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
