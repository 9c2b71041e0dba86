"""A spinning lidar's beam pattern: its elevation table and azimuth step, and the named patterns of common sensors.

One turn fires, at each azimuth ``k * azimuth_step`` (k = 0, 1, ..., counter-clockwise from the sensor's heading,
the first along it), one beam at every elevation of the table (radians above the sensor's horizontal plane). Real
sensors spin clockwise and fire their channels a few microseconds apart; the pattern is the set of directions of
one turn, which is what the counts need.

Named patterns (:data:`PATTERNS`), nominal tables from the makers' manuals (a unit's own calibration differs by
fractions of a degree):

=============  ========  ==========================================  ===============  =========
name           channels  elevations                                  azimuth step     per turn
=============  ========  ==========================================  ===============  =========
``vlp16``      16        -15° to +15° every 2° (VLP-16 manual)       0.2° (10 Hz)     28,800
``hdl32e``     32        -30.67° to +10.67° every 1.33° (HDL-32E)    0.16° (10 Hz)    72,000
``hdl64e``     64        +2° to -8.33° every 1/3°, then -8.83° to    0.1728° (10 Hz)  133,376
                         -24.33° every 0.5° (HDL-64E S2 manual)
``os1-128``    128       -22.5° to +22.5°, uniform (Ouster OS1-128)  360°/2048        262,144
``carla``      32        -30° to +10°, uniform (CARLA's defaults)    360°/1800        57,600
=============  ========  ==========================================  ===============  =========

>>> p = PATTERNS["os1-128"]
>>> p.channels, p.azimuths, p.channels * p.azimuths
(128, 2048, 262144)
>>> [round(math.degrees(e), 2) for e in PATTERNS["vlp16"].elevations[:3]]
[-15.0, -13.0, -11.0]
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

_TURN = 2 * math.pi


@dataclass(frozen=True, slots=True)
class BeamPattern:
    """The beams of one turn of a spinning lidar.

    Attributes
    ----------
    elevations : tuple of float
        Radians above the sensor's horizontal plane, each in (-π/2, π/2), ascending, no two equal.
    azimuth_step : float
        Radians between consecutive azimuths, in (0, 2π]; the turn has ``ceil(2π / step)`` azimuths (the last
        one short of 2π).
    """

    elevations: tuple[float, ...]
    azimuth_step: float

    def __post_init__(self) -> None:
        try:
            values = [float(e) for e in self.elevations]
        except (TypeError, ValueError):
            raise ValueError(f"lidar elevations must be a list of numbers (radians), not {self.elevations!r}") from None
        if not values:
            raise ValueError("a lidar needs at least one elevation")
        if not all(math.isfinite(e) and abs(e) < math.pi / 2 for e in values):
            bad = next(e for e in values if not (math.isfinite(e) and abs(e) < math.pi / 2))
            hint = f"; {bad:g} looks like degrees" if math.isfinite(bad) and abs(bad) < 90 else ""
            raise ValueError(f"lidar elevations must be radians in (-π/2, π/2), not {bad!r}{hint}")
        values.sort()
        if any(b <= a for a, b in itertools.pairwise(values)):
            raise ValueError("lidar elevations must differ from each other")
        object.__setattr__(self, "elevations", tuple(values))
        step = self.azimuth_step
        if isinstance(step, bool) or not isinstance(step, int | float | np.floating) or not 0 < step <= _TURN:
            hint = f"; {step:g} looks like degrees" if isinstance(step, int | float) and _TURN < step <= 360 else ""
            raise ValueError(f"lidar azimuth_step must be in (0, 2π] radians, not {step!r}{hint}")
        object.__setattr__(self, "azimuth_step", float(step))

    @property
    def channels(self) -> int:
        """The number of elevations."""
        return len(self.elevations)

    @property
    def azimuths(self) -> int:
        """Azimuths in one turn: ``k * azimuth_step`` for ``k = 0 .. azimuths - 1``, all below 2π."""
        return max(1, math.ceil(_TURN / self.azimuth_step - 1e-9))

    def to_dict(self) -> dict:
        """The pattern as plain JSON-able values (radians)."""
        return {"elevations": list(self.elevations), "azimuth_step": self.azimuth_step}


def uniform(channels: int, lowest: float, highest: float, azimuths: int) -> BeamPattern:
    """``channels`` elevations evenly from ``lowest`` to ``highest`` (degrees) and ``azimuths`` columns a turn.

    >>> uniform(3, -10, 10, 4).elevations == (math.radians(-10), 0.0, math.radians(10))
    True
    """
    if channels == 1:
        table = [math.radians(lowest)]
    else:
        table = [math.radians(lowest + (highest - lowest) * k / (channels - 1)) for k in range(channels)]
    return BeamPattern(tuple(table), _TURN / azimuths)


def _degrees(table: Sequence[float], step_degrees: float) -> BeamPattern:
    return BeamPattern(tuple(math.radians(e) for e in table), math.radians(step_degrees))


PATTERNS: dict[str, BeamPattern] = {
    "vlp16": _degrees([-15 + 2 * k for k in range(16)], 0.2),
    "hdl32e": _degrees([-30.67 + 1.33 * k for k in range(32)], 0.16),
    "hdl64e": _degrees([2.0 - k / 3 for k in range(32)] + [-8.83 - 0.5 * k for k in range(32)], 0.1728),
    "os1-128": uniform(128, -22.5, 22.5, 2048),
    "carla": uniform(32, -30.0, 10.0, 1800),
}
"""Named beam patterns (see the module docstring for their sources)."""


def pattern_from(spec: str | BeamPattern | dict) -> BeamPattern:
    """A :class:`BeamPattern` from a name in :data:`PATTERNS`, a pattern, or a JSON object with ``elevations``
    (radians) and ``azimuth_step`` (radians) or ``azimuths`` (a count per turn), or ``pattern`` (a name).

    >>> pattern_from({"elevations": [0.0], "azimuths": 360}).azimuths
    360
    """
    if isinstance(spec, BeamPattern):
        return spec
    if isinstance(spec, str):
        if spec not in PATTERNS:
            raise ValueError(f"unknown lidar pattern {spec!r}; give one of {sorted(PATTERNS)} or its elevations")
        return PATTERNS[spec]
    if not isinstance(spec, dict):
        raise ValueError(f"a lidar is a pattern name ({sorted(PATTERNS)}) or an object with elevations, not {spec!r}")
    known = {"pattern", "elevations", "azimuth_step", "azimuths"}
    unknown = sorted(set(spec) - known)
    if unknown:
        raise ValueError(f"lidar has unknown field(s) {unknown}; known: {sorted(known)}")
    if "pattern" in spec:
        if len(spec) > 1:
            raise ValueError("a lidar gives either a pattern name or its elevations and azimuth step, not both")
        return pattern_from(spec["pattern"])
    if "elevations" not in spec or ("azimuth_step" in spec) == ("azimuths" in spec):
        raise ValueError("a lidar needs elevations (radians) and one of azimuth_step (radians) or azimuths (a count)")
    if "azimuths" in spec:
        count = spec["azimuths"]
        if isinstance(count, bool) or not isinstance(count, int) or count <= 0:
            raise ValueError(f"lidar azimuths must be a positive whole number, not {count!r}")
        return BeamPattern(tuple(spec["elevations"]), _TURN / count)
    return BeamPattern(tuple(spec["elevations"]), spec["azimuth_step"])
