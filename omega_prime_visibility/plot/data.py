"""What every picture needs, computed once: the loaded recording, the frames asked for, and per frame what the ego
sees (visibility, occluders, the visible region), on the same per-frame pipeline as ``get_visibility_df``.

No plotting library is imported here.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import polars as pl
import shapely

from ..engines.registry import ENGINE_TITLES, get_engine
from ..engines.visilibity import VisiLibityEngine
from ..inputs.objects import ObjectTable
from ..inputs.scene import as_polars
from ..inputs.sensors import Sensor
from ..inputs.statics import StaticOccluders
from ..query import Query, Resolved, fold_keywords, resolve
from ..table.pipeline import ContainmentLog, observe_frame, observer_rows
from ..table.schema import TableBuilder, to_polars
from .lanes import Lanes, prepared_lanes
from .regions import seen_region

FrameSpec = range | slice | Sequence[int] | None


@dataclass
class Source:
    """A recording loaded for pictures.

    Attributes
    ----------
    objects : ObjectTable
        The validated objects, grouped by frame.
    statics : StaticOccluders
        The static occluders.
    table : polars.DataFrame
        The input's ``frame, total_nanos, idx, x, y`` (and ``vel_x, vel_y`` where present), for speeds.
    lanes : Lanes
        Lane surfaces and centre lines from the recording's map, simplified for drawing (empty without a map).
    """

    objects: ObjectTable
    statics: StaticOccluders
    table: pl.DataFrame
    lanes: Lanes = field(default_factory=Lanes)
    scene: Resolved | None = None
    """The question resolved against the recording (its sensors fitted to the ego, its engine, its statics)."""

    @property
    def frames(self) -> np.ndarray:
        """The frame numbers of the table, ascending."""
        return self.objects.frame[self.objects.frame_starts[:-1]]

    def position_of(self, frame: int) -> int:
        """0-based position of frame number ``frame``; ``ValueError`` if it does not occur."""
        frames = self.frames
        k = int(np.searchsorted(frames, frame))
        if k >= len(frames) or frames[k] != frame:
            raise ValueError(
                f"frame {frame} does not occur in the table (frames {int(frames[0])} to {int(frames[-1])})"
                if len(frames)
                else f"frame {frame} does not occur in the table (it has no frames)"
            )
        return k

    def positions(self, frames: FrameSpec) -> np.ndarray:
        """0-based positions of ``frames``: None (all), a slice of frame numbers (``slice(30, 90)``: the frames
        from 30 up to 90 that occur), a range or a sequence of frame numbers (each must occur).

        Raises ``ValueError`` if the selection is empty or names a frame that does not occur."""
        all_frames = self.frames
        if frames is None:
            wanted = all_frames
        elif isinstance(frames, slice):
            lo = int(all_frames[0]) if frames.start is None else int(frames.start)
            hi = int(all_frames[-1]) + 1 if frames.stop is None else int(frames.stop)
            wanted = all_frames[(all_frames >= lo) & (all_frames < hi)][:: frames.step or 1]
            if len(wanted) == 0:
                raise ValueError(
                    f"the frame range {lo} to {hi} (stop excluded) is empty: the table has frames "
                    f"{int(all_frames[0])} to {int(all_frames[-1])}"
                )
        else:
            wanted = np.asarray(list(frames) if isinstance(frames, range) else frames, dtype=np.int64).reshape(-1)
            if len(wanted) == 0:
                raise ValueError("the frame range is empty: give at least one frame")
        return np.array([self.position_of(int(f)) for f in wanted], dtype=np.int64)

    def ego_speed(self, ego_idx: int, frame: int) -> float:
        """Speed of ``ego_idx`` in ``frame``, m/s: from ``vel_x, vel_y`` if the table has them, else from the
        change of its position between neighbouring frames (NaN when it cannot be told)."""
        rows = self.table.filter((pl.col("idx") == ego_idx) & (pl.col("frame") == frame))
        if rows.height and {"vel_x", "vel_y"} <= set(rows.columns):
            return float(math.hypot(rows["vel_x"][0], rows["vel_y"][0]))
        ego = self.table.filter(pl.col("idx") == ego_idx).sort("frame").select("frame", "total_nanos", "x", "y")
        k = int(np.searchsorted(ego["frame"].to_numpy(), frame))
        a, b = max(k - 1, 0), min(k + 1, ego.height - 1)
        dt = (ego["total_nanos"][b] - ego["total_nanos"][a]) / 1e9
        if b == a or dt <= 0:
            return math.nan
        return float(math.hypot(ego["x"][b] - ego["x"][a], ego["y"][b] - ego["y"][a]) / dt)


def load_source(df: Any, question: Query, lanes: Any = True) -> Source:
    """Load a recording (``omega_prime.Recording``, polars table or MCAP path) for pictures of ``question`` (a
    :class:`~omega_prime_visibility.Query` with one observer): the objects as the question reads them (who may
    block, whom to look for), the static occluders its engines see (the map's road objects, the 2D height rule).

    ``lanes``: True takes the lanes of the recording's map where it has one, False none; a map object (with a
    ``lanes`` dict) or a sequence of shapely geometries gives them explicitly.
    """
    if isinstance(df, str) or hasattr(df, "__fspath__"):
        from ..inputs.io import read_recording

        df = read_recording(df)
    table = as_polars(df)
    scene = resolve(question, df)
    if scene.objects.n_frames == 0:
        raise ValueError("the table has no usable object rows: there is nothing to draw")
    keep = [c for c in ("frame", "total_nanos", "idx", "x", "y", "vel_x", "vel_y") if c in table.columns]
    if lanes is True:  # (a recording of the reader draws its lanes without importing omega-prime)
        lanes = df.picture_lanes() if hasattr(df, "picture_lanes") else getattr(df, "map", None)
    return Source(scene.objects, scene.statics, table.select(keep), prepared_lanes(lanes), scene)


def picture_question(query: Query | None, ego_idx: int | None, static_occluder_polys: Any, **keywords: Any) -> Query:
    """The question of a picture: ``query`` with the picture's table keywords folded in (as
    ``get_visibility_df`` folds them); one observer.

    >>> picture_question(None, 3, None, engine="sweep").observers
    3
    """
    question = fold_keywords(query, ego_idx=ego_idx, static_occluder_polys=static_occluder_polys, **keywords)
    if not isinstance(question.observers, int):
        raise ValueError(f"a picture is seen from one observer: give ego_idx as one idx, not {question.observers!r}")
    return question


def describe_question(question: Query) -> str:
    """The choices of ``question`` in a few words, for a picture's title or a page's subtitle.

    >>> describe_question(Query(observers=0, mode="3d", targets="pedestrians"))
    'engine 3D silhouettes, 3D, whom to look for: pedestrians'
    >>> describe_question(Query(observers=0, measure="area"))
    'engine area, % = share of its area seen'
    """
    words = [f"engine {ENGINE_TITLES.get(question.engine, question.engine)}"]
    if question.three_d:
        words.append("3D")
    else:  # what the numbers on the picture are
        words.append(f"% = share of its {question.measure} seen")
    for name, label in (("occluders", "who may block"), ("targets", "whom to look for")):
        value = getattr(question, name)
        if value is not None:
            text = f"expression {value}" if isinstance(value, pl.Expr) else ", ".join(map(str, value))
            words.append(f"{label}: {text}")
    if question.map_occluders is not None:
        words.append("the map's road objects block")
    return ", ".join(words)


def needs_table(question: Query) -> bool:
    """Whether the views cannot compute the numbers of ``question`` frame by frame themselves (they run a 2D
    angle engine from the ego's centre), so the table of the drawn frames is computed first."""
    return question.three_d or question.measure != "angle"


@dataclass
class FrameView:
    """What the ego sees in one frame.

    Attributes
    ----------
    frame, total_nanos : int
    idx : ndarray, shape (n,), int64
        The objects of the frame, ascending.
    rings : list of ndarray, shape (k, 2)
        Their outlines, metres.
    position : ndarray, shape (n, 2)
        Bounding-box centres, metres.
    yaw : ndarray, shape (n,)
        Headings, radians counter-clockwise from +x.
    ego_row : int
        Row of the ego in these arrays.
    visibility : ndarray, shape (n,)
        Visibility of each object from the ego (NaN for the ego itself).
    occluders, static_occluders : dict[int, list[int]]
        Per target idx, the idx of the objects (positions of the static occluders) hit before it.
    region : shapely.Polygon or MultiPolygon
        The region the ego sees (:func:`.regions.seen_region`: from its centre, or through its sensors), bounded
        ``margin`` metres around the scene.
    """

    frame: int
    total_nanos: int
    idx: np.ndarray
    rings: list[np.ndarray]
    position: np.ndarray
    yaw: np.ndarray
    ego_row: int
    visibility: np.ndarray
    occluders: dict[int, list[int]]
    static_occluders: dict[int, list[int]]
    region: shapely.Polygon

    @property
    def observer(self) -> np.ndarray:
        """The viewpoint: the centre of the ego's bounding box, metres."""
        return self.position[self.ego_row]

    def row_of(self, idx: int | None) -> int | None:
        """The row of object ``idx`` in this frame (None if it is not in it, or ``idx`` is None)."""
        if idx is None:
            return None
        rows = np.flatnonzero(self.idx == idx)
        return int(rows[0]) if len(rows) else None


NONE = shapely.Polygon()
"""The region of a view that carries none (3D)."""


class FrameViewer:
    """Computes :class:`FrameView` of one ego frame after frame, with one engine for all of them.

    Parameters
    ----------
    source : Source
    ego_idx : int
    engine : str
        2D engine of the visibility values (the visible region is always VisiLibity's).
    margin : float
        Metres around the scene up to which the visible region is drawn.
    sensors : sequence of Sensor, optional
        Look through these sensors (as ``get_visibility_df(sensors=...)``); an object's ``visibility`` is then the
        best over the sensors and its occluders those of any sensor, as :func:`~omega_prime_visibility.seen_by_any`
        combines them.
    table : polars.DataFrame, optional
        A visibility table of this ego computed elsewhere (e.g. in 3D, or through sensors): the views take their
        numbers from it (combined over ``sensor`` as above) instead of computing them.
    region : bool
        Whether the views carry the region seen on the ground; False for a 3D table, whose targets are seen from
        the eye over what a bird's-eye region would call blocked (no picture shades "not seen" where the table
        says seen).
    reach : float, optional
        Metres around the ego the pictures of these views show (None: the whole frame).
    """

    def __init__(
        self,
        source: Source,
        ego_idx: int,
        engine: str = "visilibity",
        margin: float = 200.0,
        sensors: Sequence[Sensor] = (),
        table: pl.DataFrame | None = None,
        region: bool = True,
        reach: float | None = None,
    ) -> None:
        self.region = region
        self.reach = reach  # metres around the ego a picture shows (None: the whole frame)
        if ego_idx not in set(np.unique(source.objects.idx).tolist()):
            raise ValueError(f"ego idx {ego_idx} never occurs in the table")
        self.source, self.ego_idx = source, int(ego_idx)
        self.sensors = tuple(sensors)
        self.margin = margin
        if table is not None and "idx_ego" in table.columns:  # a table of several observers: this ego's rows
            table = table.filter(pl.col("idx_ego") == self.ego_idx).drop("idx_ego")
        self.tables = None if table is None else {k[0]: t for k, t in table.partition_by("frame", as_dict=True).items()}
        self.engine = None if table is not None else get_engine(engine)(source.statics)
        self.region_engine = self.engine if isinstance(self.engine, VisiLibityEngine) else None

    def frame_table(self, k: int) -> pl.DataFrame:
        """The visibility table of the ``k``-th frame (0-based position), per sensor where there are sensors."""
        fo = self.source.objects.frame_objects(k)
        if self.tables is not None:
            return self.tables.get(fo.frame, pl.DataFrame(schema={"idx": pl.Int64, "visibility": pl.Float64}))
        builder = TableBuilder()
        with warnings.catch_warnings():  # containment is told by get_visibility_df; a picture need not repeat it
            warnings.simplefilter("ignore")
            sensors = self.sensors or None
            observe_frame(self.engine, self.source.statics, fo, np.array([self.ego_idx]), builder, ContainmentLog(),
                          sensors)  # fmt: skip
        names = [s.name for s in self.sensors] if self.sensors else None
        return to_polars(builder.arrays(), with_ego=False, sensor_names=names)

    def view(self, k: int) -> FrameView:
        """The view of the ``k``-th frame (0-based position)."""
        src = self.source
        fo = src.objects.frame_objects(k)
        rows = observer_rows(fo, np.array([self.ego_idx]))
        if len(rows) == 0:
            raise ValueError(f"ego idx {self.ego_idx} is not present in frame {fo.frame}")
        table = combined(self.frame_table(k))
        ids = table["idx"].to_list()
        vis = dict(zip(ids, table["visibility"].to_list(), strict=True))
        lists = {c: table[c].to_list() if c in table.columns else [[]] * len(ids) for c in OCCLUDER_COLUMNS}
        if self.region_engine is None:
            self.region_engine = VisiLibityEngine(src.statics)
        self.region_engine.box_margin = self.margin
        region = seen_region(self.region_engine, fo, int(rows[0]), src.statics, self.sensors) if self.region else NONE
        return FrameView(
            frame=fo.frame,
            total_nanos=fo.total_nanos,
            idx=fo.idx.copy(),
            rings=[fo.rings.ring(i).copy() for i in range(len(fo))],
            position=fo.position.copy(),
            yaw=fo.yaw.copy(),
            ego_row=int(rows[0]),
            visibility=np.array([vis.get(i, np.nan) for i in fo.idx.tolist()], dtype=float),
            occluders={i: list(v or []) for i, v in zip(ids, lists["occluder_idxs"], strict=True)},
            static_occluders={i: list(v or []) for i, v in zip(ids, lists["static_occluder_idxs"], strict=True)},
            region=region,
        )


OCCLUDER_COLUMNS = ("occluder_idxs", "static_occluder_idxs")


def listed_once(*columns: str) -> pl.Expr:
    """In an aggregation: every value the list columns hold over the group, once each, ascending."""
    return pl.col(*columns).list.explode(keep_nulls=False, empty_as_null=False).drop_nulls().unique().sort()


def combined(table: pl.DataFrame) -> pl.DataFrame:
    """One row per target: ``visibility`` the best over the table's sensors (as ``seen_by_any`` gives it) and the
    occluders *of that best sensor* (ties: the first sensor by name, as ``seen_by_any``'s ``best_sensor``), so that
    a picture outlines what hides the target from the view whose number it shows; a table without ``sensor`` as
    it is.

    >>> t = pl.DataFrame({"idx": [2, 2], "sensor": ["a", "b"], "visibility": [0.25, 0.5],
    ...                   "occluder_idxs": [[1], [3]], "static_occluder_idxs": [[], []]})
    >>> combined(t).rows()
    [(2, 0.5, [3], [])]
    """
    if "sensor" not in table.columns:
        return table
    present = [c for c in OCCLUDER_COLUMNS if c in table.columns]
    return table.group_by("idx").agg(pl.col("visibility").max(), *[of_best_sensor(c) for c in present]).sort("idx")


def of_best_sensor(column: str) -> pl.Expr:
    """In a ``group_by(...).agg`` over a table's sensors: ``column`` of the sensor with the best visibility (ties:
    the first by name, as ``seen_by_any``'s ``best_sensor``)."""
    order = [pl.col("visibility"), pl.col("sensor").cast(pl.String)]
    return pl.col(column).sort_by(order, descending=[True, False]).first()


def frames_table(df: Any, question: Query, frame_numbers: Sequence[int]) -> pl.DataFrame:
    """The visibility table of ``question`` in the frames ``frame_numbers`` only (for what the per-frame views
    do not compute themselves, such as ``mode="3d"`` or the area measure)."""
    from ..api import within_recording
    from ..table.compute import compute

    table = as_polars(df)
    rows = table.filter(pl.col("frame").is_in(list(frame_numbers)))
    part = within_recording(question, table.lazy())  # idx of the whole recording
    with warnings.catch_warnings():  # told for the whole recording, not again for its frames
        warnings.filterwarnings("ignore", r"(targets|occluders)=.* matches (no object|only the observer)")
        return compute(resolve(part, rows if not hasattr(df, "map") else _with_rows(df, rows)), progress=False)


def _with_rows(recording: Any, rows: pl.DataFrame) -> Any:
    """A stand-in for an omega-prime Recording holding only ``rows`` but its map (for the map's road objects, read
    only if they are asked for: a reader's recording reads its map through omega-prime)."""

    class Part:
        host_vehicle_idx = getattr(recording, "host_vehicle_idx", None)
        _df = rows

        @property
        def map(self) -> Any:
            return getattr(recording, "map", None)

    return Part()


def sensor_list(source: Source, ego_idx: int) -> tuple[Sensor, ...]:
    """The ego's sensors of the picture's question (a layout fitted to the ego's own size, as
    :func:`~omega_prime_visibility.get_visibility_df` fits it)."""
    sensors = None if source.scene is None else source.scene.sensors
    if sensors is None:
        return ()
    return tuple(sensors[int(ego_idx)] if isinstance(sensors, dict) else sensors)
