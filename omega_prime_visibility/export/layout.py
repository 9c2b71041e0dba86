"""A layout for Lichtblick (and Foxglove) that opens on the answer: the 3D panel following the observer with its
scene, a plot of one target's visibility over time, and the rows of the current frame.

The layout is the viewer's JSON (``configById`` of panels, ``layout`` splitting the window); import it with the
layout menu's "Import from file…". :func:`write_layout` writes it for an observer (and sensor) of a file written
by :func:`.mcap.write_mcap`.

>>> panels = lichtblick_layout(0, target=2)["configById"]
>>> panels["Plot!visibility"]["paths"][0]["value"]
'/visibility/ego_0/table.rows[:]{idx==2}.visibility'
"""

from __future__ import annotations

import json
import os
from pathlib import Path


def lichtblick_layout(ego: int, sensor: str | None = None, target: int | None = None) -> dict:
    """The layout (a JSON-able dict) for observer ``ego``'s channels (``sensor``'s, where there are sensors),
    plotting ``target``'s visibility (default: every target's, one line each, as the plot panel draws an
    array)."""
    base = f"/visibility/ego_{ego}" + ("" if sensor is None else f"/{sensor}")
    which = "[:]" if target is None else f"[:]{{idx=={int(target)}}}"
    three_d = {
        "followMode": "follow-pose",
        "followTf": f"ego_{ego}",
        "scene": {"enableStats": False, "transforms": {"showLabel": False}},
        "cameraState": {
            "distance": 60,
            "perspective": True,
            "phi": 55,
            "thetaOffset": 0,
            "targetOffset": [0, 0, 0],
            "fovy": 45,
            "near": 0.5,
            "far": 5000,
        },
        "topics": {f"{base}/scene": {"visible": True}, "/visibility/static_occluders": {"visible": True}},
    }
    plot = {
        "title": f"visibility of {'every target' if target is None else f'target {target}'} from ego {ego}"
        + ("" if sensor is None else f" ({sensor})"),
        "paths": [{"value": f"{base}/table.rows{which}.visibility", "enabled": True, "timestampMethod": "receiveTime"}],
        "minYValue": 0,
        "maxYValue": 1,
        "showLegend": True,
        "xAxisVal": "timestamp",
    }
    rows = {"topicPath": f"{base}/table.rows"}
    return {
        "configById": {"3D!answer": three_d, "Plot!visibility": plot, "RawMessages!rows": rows},
        "globalVariables": {},
        "userNodes": {},
        "layout": {
            "direction": "row",
            "first": "3D!answer",
            "second": {
                "direction": "column",
                "first": "Plot!visibility",
                "second": "RawMessages!rows",
                "splitPercentage": 45,
            },
            "splitPercentage": 62,
        },
    }


def write_layout(path: str | os.PathLike, ego: int, sensor: str | None = None, target: int | None = None) -> Path:
    """Write :func:`lichtblick_layout` to ``path`` (``.json``); return the path."""
    path = Path(path)
    if path.suffix != ".json":
        raise ValueError(f"a layout is a .json file, not {path.name}")
    path.write_text(json.dumps(lichtblick_layout(ego, sensor, target), indent=2) + "\n")
    return path
