"""Sensors from files and names: a JSON list of sensors, or a ready-made layout (:data:`.sensors.LAYOUTS`).

A JSON sensor has :class:`~.sensors.Sensor`'s fields (angles in radians, ``range`` null or absent for no limit);
a camera adds ``"camera": {"width": ..., "height": ..., "fov": ...}`` (or ``focal``, ``matrix``, ``fx, fy, cx,
cy``), a lidar ``"lidar": "os1-128"`` (a pattern's name) or ``{"elevations": [...], "azimuths": 2048}``.

>>> import json, tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "rig.json"
>>> _ = path.write_text(json.dumps([{"name": "cam", "x": 1.5, "camera": {"width": 640, "height": 480, "fov": 1.2}},
...                                 {"name": "top", "z": 1.9, "lidar": "vlp16"}]))
>>> [s.kind for s in read_sensors(path)]
['camera', 'lidar']
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from dataclasses import fields
from pathlib import Path

from .cameras import pinhole_from_dict
from .lidars import pattern_from
from .sensors import LAYOUTS, Sensor, check_sensors


def read_sensors(path: str | os.PathLike) -> tuple[Sensor, ...]:
    """Sensors from a JSON file: a list of objects with :class:`Sensor`'s fields (angles in radians; ``range``
    null or absent for no limit), or ``{"sensors": [...]}``. Any problem raises ``ValueError`` naming the file.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except OSError as e:
        raise ValueError(f"cannot read sensors file {path}: {e.strerror or e}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ValueError(f"sensors file {path} is not valid JSON: {e}") from None
    if isinstance(data, dict) and "sensors" in data:
        data = data["sensors"]
    if not isinstance(data, list):
        raise ValueError(f"sensors file {path} must hold a list of sensors (or {{'sensors': [...]}})")
    known = {f.name for f in fields(Sensor)}
    out = []
    for k, item in enumerate(data):
        if not isinstance(item, dict):
            raise ValueError(f"sensors file {path}: entry {k} is not an object")
        unknown = sorted(set(item) - known)
        if unknown:
            raise ValueError(f"sensors file {path}: entry {k} has unknown field(s) {unknown}; known: {sorted(known)}")
        if "name" not in item:
            raise ValueError(f"sensors file {path}: entry {k} has no name")
        item = dict(item)
        if item.get("range", 0) is None:
            item["range"] = math.inf
        try:
            if "camera" in item:
                item["camera"] = pinhole_from_dict(item["camera"])
            if "lidar" in item:
                item["lidar"] = pattern_from(item["lidar"])
            out.append(Sensor(**item))
        except ValueError as e:
            raise ValueError(f"sensors file {path}: {e}") from None
    try:
        return check_sensors(out)
    except ValueError as e:
        raise ValueError(f"sensors file {path}: {e}") from None


def resolve_sensors(
    spec: str | os.PathLike | Sensor | Sequence[Sensor] | None, length: float = 4.6, width: float = 1.85
) -> tuple[Sensor, ...] | None:
    """Sensors from a layout name (:data:`LAYOUTS`), a JSON file path, one :class:`Sensor` or a sequence of them.

    >>> [s.name for s in resolve_sensors("roof")]
    ['roof']
    >>> resolve_sensors(None) is None
    True
    """
    if spec is None:
        return None
    if isinstance(spec, Sensor):
        return (spec,)
    if isinstance(spec, str) and spec in LAYOUTS:
        return check_sensors(LAYOUTS[spec](length, width))
    if isinstance(spec, str | os.PathLike):
        path = Path(spec)
        if path.suffix.lower() != ".json" and not path.exists():
            raise ValueError(f"unknown sensor layout {str(spec)!r}; give one of {sorted(LAYOUTS)} or a .json file")
        return read_sensors(path)
    return check_sensors(spec)
