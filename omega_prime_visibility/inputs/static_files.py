"""Static occluders from files, with their heights where the file carries them: GeoJSON (a ``height`` property),
WKT (a height after the geometry on its line) and JSON lists of ``{"wkt": ..., "height": ...}`` as city models are
often exported.

Coordinates are metres in the recording's frame; a height is the z of the occluder's top in metres (a footprint
without one blocks at every height). An occluder's position in the file is its number in ``static_occluder_idxs``.
"""

from __future__ import annotations

import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .errors import RecordingReadError

HEIGHT_KEYS = ("height",)
"""The property (GeoJSON) or key (JSON list) a height is read from."""

SHAPES = (
    "a GeoJSON FeatureCollection, Feature or geometry (.geojson, .json; heights from a 'height' property), a JSON "
    'list of {"wkt": ..., "height": ...} (.json), or WKT, one geometry per line, optionally followed by its height '
    "(any other name)"
)
"""What a static occluders file may hold, as errors say it."""

_WKT_WITH_HEIGHT = re.compile(r"^(?P<wkt>.*?\))\s*[,;\t ]\s*(?P<height>[-+0-9.eE]+|nan|inf)\s*$", re.IGNORECASE)


@dataclass(frozen=True)
class StaticFile:
    """What a static occluders file holds: the geometries in file order, their heights (metres, z of the top) where
    the file gives them (None where it gives none; a file giving some but not all is refused), and a note saying
    where the heights came from (None without heights)."""

    geometries: list[Any]
    heights: tuple[float, ...] | None
    note: str | None


def read_static_occluders(path: str | os.PathLike) -> list[Any]:
    """Static occluders from a GeoJSON, JSON or WKT file (:func:`read_static_file`), as shapely geometries in file
    order.

    Raises
    ------
    RecordingReadError
        If the file is missing or cannot be parsed; the message names the file (and the line or feature).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     wkt = Path(folder) / "walls.wkt"
    ...     _ = wkt.write_text("# a wall and a building\\nLINESTRING (0 5, 10 5)\\nPOLYGON ((0 0, 1 0, 1 1, 0 0))\\n")
    ...     [g.geom_type for g in read_static_occluders(wkt)]
    ['LineString', 'Polygon']
    """
    return read_static_file(path).geometries


def read_static_file(path: str | os.PathLike) -> StaticFile:
    """Static occluders and their heights from a file (see the module docstring for the shapes it may have).

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     city = Path(folder) / "buildings.json"
    ...     _ = city.write_text('[{"wkt": "POLYGON ((0 0, 9 0, 9 9, 0 0))", "height": 12.5}]')
    ...     found = read_static_file(city)
    >>> found.heights, found.note
    ((12.5,), "heights of 1 of 1 static occluders from the key 'height' of buildings.json")
    """
    path = Path(path)
    if not path.is_file():
        raise RecordingReadError(f"static occluders {path} {'is not a file' if path.exists() else 'does not exist'}")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise RecordingReadError(f"cannot read static occluders {path} ({e})") from None
    if path.suffix.lower() == ".xodr" or "<OpenDRIVE" in text[:2000]:
        raise RecordingReadError(
            f"static occluders {path} is an OpenDRIVE map, not GeoJSON or WKT: give it with --map, and "
            "--map-occluders to let its road objects block the view"
        )
    if path.suffix.lower() in (".geojson", ".json"):
        try:
            document = json.loads(text)
        except json.JSONDecodeError as e:
            raise RecordingReadError(
                f"cannot read static occluders {path} as JSON ({e}); it may hold {SHAPES}"
            ) from None
        if isinstance(document, list):
            geometries, heights = _wkt_list(path, document)
            return _with_note(path, geometries, heights, "key")
        geometries, heights = _geojson(path, document)
        return _with_note(path, geometries, heights, "property")
    geometries, heights = _wkt_lines(path, text)
    return _with_note(path, geometries, heights, "column")


def _with_note(path: Path, geometries: list[Any], heights: list[float | None], kind: str) -> StaticFile:
    given = sum(h is not None for h in heights)
    if not given:
        return StaticFile(geometries, None, None)
    where = "the column after each WKT geometry" if kind == "column" else f"the {kind} 'height'"
    if given < len(heights):
        first = heights.index(None)
        raise RecordingReadError(
            f"static occluders {path}: {given} of {len(heights)} occluders have a height ({where}) but occluder "
            f"{first} has none: give every occluder a height, or none (then each blocks at every height)"
        )
    note = f"heights of {given} of {len(heights)} static occluders from {where} of {path.name}"
    return StaticFile(geometries, tuple(heights), note)


def _height(path: Path, name: str, value: Any) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise RecordingReadError(f"static occluders {path}: {name} has a height that is no number ({value!r})")
    try:
        height = float(value)
    except ValueError:
        raise RecordingReadError(
            f"static occluders {path}: {name} has a height that is no number ({value!r})"
        ) from None
    if not math.isfinite(height) or height <= 0:
        raise RecordingReadError(
            f"static occluders {path}: {name} has the height {value!r}; a height is the z of the top in metres, above 0"
        )
    return height


def _geojson(path: Path, document: Any) -> tuple[list[Any], list[float | None]]:
    """The geometries and heights of a GeoJSON FeatureCollection, Feature or geometry, in order."""
    import shapely.geometry

    kind = document.get("type") if isinstance(document, dict) else None
    if kind == "FeatureCollection":
        features = document.get("features") or []
        items = [(f"feature {k}", f if isinstance(f, dict) else {}) for k, f in enumerate(features)]
    elif kind == "Feature":
        items = [("the feature", document)]
    elif (isinstance(document, dict) and "coordinates" in document) or kind == "GeometryCollection":
        items = [("the geometry", {"geometry": document})]
    else:
        raise RecordingReadError(f"static occluders {path} is JSON of no shape it may have: it may hold {SHAPES}")
    if not items:
        raise RecordingReadError(f"static occluders {path} holds no feature")
    geometries, heights = [], []
    for name, feature in items:
        geometry = feature.get("geometry")
        try:
            if not isinstance(geometry, dict):
                raise ValueError("it has no geometry")
            geometries.append(shapely.geometry.shape(geometry))
        except Exception as e:  # shapely raises several kinds for malformed GeoJSON
            raise RecordingReadError(
                f"cannot read static occluders {path}: {name} is no GeoJSON geometry ({e})"
            ) from None
        properties = feature.get("properties") or {}
        value = next((properties[k] for k in HEIGHT_KEYS if isinstance(properties, dict) and k in properties), None)
        heights.append(_height(path, name, value))
    return geometries, heights


def _wkt_list(path: Path, items: list[Any]) -> tuple[list[Any], list[float | None]]:
    """A JSON list of ``{"wkt": ..., "height": ...}`` (height optional)."""
    import shapely

    if not items:
        raise RecordingReadError(f"static occluders {path} holds no item")
    geometries, heights = [], []
    for k, item in enumerate(items):
        if not isinstance(item, dict) or not isinstance(item.get("wkt"), str):
            raise RecordingReadError(
                f'static occluders {path}: item {k} is no {{"wkt": ..., "height": ...}} object; it may hold {SHAPES}'
            )
        try:
            geometries.append(shapely.from_wkt(item["wkt"]))
        except shapely.errors.ShapelyError as e:
            raise RecordingReadError(f"cannot read static occluders {path}: item {k}'s wkt ({e})") from None
        heights.append(_height(path, f"item {k}", item.get("height")))
    return geometries, heights


def _wkt_lines(path: Path, text: str) -> tuple[list[Any], list[float | None]]:
    """One geometry per line, optionally followed by its height; blank lines and ``#`` comments left out."""
    import shapely

    geometries, heights = [], []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        match = _WKT_WITH_HEIGHT.match(line.strip())
        wkt, height = (match["wkt"], match["height"]) if match else (line, None)
        try:
            geometries.append(shapely.from_wkt(wkt))
        except shapely.errors.ShapelyError as e:
            raise RecordingReadError(f"cannot read static occluders {path}, line {number}, as WKT ({e})") from None
        heights.append(_height(path, f"line {number}", height))
    if not geometries:
        raise RecordingReadError(f"static occluders {path} holds no geometry")
    return geometries, heights
