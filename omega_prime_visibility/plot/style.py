"""Colours every picture shares, all readable with the common colour-vision deficiencies: visibility on cividis
(a sequential map that reads the same to red-green colour-blind readers), statuses and sensors in the
Okabe–Ito qualitative palette (Okabe & Ito 2008, "Color Universal Design").

No plotting library is imported here.
"""

from __future__ import annotations

import math

import numpy as np

OKABE_ITO = {
    "orange": "#E69F00",
    "sky blue": "#56B4E9",
    "bluish green": "#009E73",
    "yellow": "#F0E442",
    "blue": "#0072B2",
    "vermillion": "#D55E00",
    "reddish purple": "#CC79A7",
    "black": "#000000",
}
"""The eight colours of the Okabe–Ito palette."""

VISIBILITY_CMAP = "cividis"
"""Default matplotlib colour map of visibility (0 dark blue, 1 yellow)."""

CIVIDIS = (
    "#00224e #083370 #35456c #4f576c #666970 #7d7c78 #948e77 #aea371 #c8b866 #e5cf52 #fee838".split()
)  # fmt: skip
"""matplotlib's cividis at 0, 0.1, ..., 1: the same scale in the HTML report (linear between these)."""

WINE = "#882255"
"""Paul Tol's wine (his colour-blind-safe "muted" scheme): a sixth line colour beside Okabe-Ito's."""
SENSOR_COLOURS = (*(OKABE_ITO[c] for c in ("orange", "blue", "bluish green", "reddish purple")), WINE,
                  OKABE_ITO["sky blue"])  # fmt: skip
"""Outline colour of the k-th sensor's field of view (cycled beyond six): Okabe-Ito's colours but vermillion (the
ego's), black (the outlines of a target and what hides it) and yellow (a fully visible road user's fill, pale on
the seen region), which Tol's wine replaces."""

STATUS_COLOURS = {
    "visible": CIVIDIS[-1],
    "partly_visible": CIVIDIS[5],
    "occluded": CIVIDIS[0],
    "out_of_fov": "#bdbdbd",
    "out_of_range": "#e3e3e3",
}
"""Colour of each ``status`` value (the sensors' verdict per target), in the legend's order: the ends and the middle
of the visibility scale, so that dark means hidden in every chart and page (timelines by visibility or by status,
the campaign page), and light greys for a target out of view (nothing hides it)."""

CLASS_COLOURS = {
    "visible": STATUS_COLOURS["visible"],
    "partly": STATUS_COLOURS["partly_visible"],
    "hidden": STATUS_COLOURS["occluded"],
    "out_of_view": STATUS_COLOURS["out_of_fov"],
}
"""Colour of each class of :mod:`~omega_prime_visibility.analysis.classes` on the campaign page (as the statuses)."""

EGO_FACE, EGO_EDGE = OKABE_ITO["vermillion"], "#5a2800"
REGION_FACE = "#cfe8f7"  # the region the ego sees: a pale sky blue under everything but the road surface
REGION_ALPHA = 0.85  # ... drawn over the road surface, which shows through faintly where seen
TARGET_EDGE = "black"  # dashed; the target's occluders are outlined solid
OCCLUDER_EDGE = "black"
STATIC_FACE, STATIC_EDGE = "#bbbbbb", "#555555"
LANE_FACE, LANE_COLOUR = "#a8a8a8", "#7a7a7a"  # the road surface (opaque, under the seen region), its lines
KEY_COLOURS = (
    EGO_FACE, EGO_EDGE, REGION_FACE, STATIC_FACE, STATIC_EDGE, LANE_FACE, LANE_COLOUR, *OKABE_ITO.values(),
    *SENSOR_COLOURS, "#000000", "#333333", "#ffffff", "#cccccc",
)  # fmt: skip
"""The colours the pictures draw things with (ego, region, statics, lanes, sensors, outlines): a GIF's one palette
keeps each of them exact, however small the thing drawn in it."""


def percent(value: float) -> str:
    """A share as a picture's label says it: rounded to whole percent, but "<1%" and ">99%" where rounding would
    call a partly hidden road user hidden (0%) or fully visible (100%).

    >>> percent(0.0), percent(0.004), percent(0.125), percent(0.58), percent(0.996), percent(1.0)
    ('0%', '<1%', '13%', '58%', '>99%', '100%')
    """
    if 0.0 < value < 0.005:
        return "<1%"
    if 0.995 <= value < 1.0:
        return ">99%"
    return f"{math.floor(100 * value + 0.5)}%"  # halves up, as the report's Math.round: 0.125 is 13% in both


def visibility_colour(v: float) -> str:
    """Hex colour of visibility ``v`` in 0..1 on the cividis scale (linear between its 11 colours); grey for NaN.

    >>> visibility_colour(0.0), visibility_colour(1.0), visibility_colour(float("nan"))
    ('#00224e', '#fee838', '#cccccc')
    """
    if not np.isfinite(v):
        return "#cccccc"
    x = min(max(float(v), 0.0), 1.0) * (len(CIVIDIS) - 1)
    k = min(int(x), len(CIVIDIS) - 2)
    a = np.array([int(CIVIDIS[k][i : i + 2], 16) for i in (1, 3, 5)])
    b = np.array([int(CIVIDIS[k + 1][i : i + 2], 16) for i in (1, 3, 5)])
    r, g, bl = np.rint(a + (b - a) * (x - k)).astype(int)
    return f"#{r:02x}{g:02x}{bl:02x}"


def visibility_rgb(values: np.ndarray) -> np.ndarray:
    """:func:`visibility_colour` of many visibilities at once, as integers 0-255, shape (n, 3); NaN grey.

    >>> visibility_rgb(np.array([0.0, 0.5, np.nan])).tolist()
    [[0, 34, 78], [125, 124, 120], [204, 204, 204]]
    """
    values = np.asarray(values, dtype=np.float64)
    stops = np.array([[int(c[i : i + 2], 16) for i in (1, 3, 5)] for c in CIVIDIS], dtype=np.float64)
    x = np.clip(np.nan_to_num(values, nan=0.0), 0.0, 1.0) * (len(CIVIDIS) - 1)
    k = np.minimum(x.astype(np.int64), len(CIVIDIS) - 2)
    out = np.rint(stops[k] + (stops[k + 1] - stops[k]) * (x - k)[:, None]).astype(np.int64)
    out[np.isnan(values)] = 204
    return out


def sensor_colour(k: int) -> str:
    """Outline colour of the ``k``-th sensor (0-based).

    >>> sensor_colour(0), sensor_colour(6)
    ('#E69F00', '#E69F00')
    """
    return SENSOR_COLOURS[k % len(SENSOR_COLOURS)]
