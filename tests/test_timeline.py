"""The timeline: runs of frames merged as drawn, colours by visibility or status, tooltips, exports."""

from __future__ import annotations

import json

import polars as pl
import pytest
from conftest import interrupted_writer
from PIL import Image

from omega_prime_visibility.plot import save_timeline, timeline_chart
from omega_prime_visibility.plot.timeline import STATUS_COLOURS, VEGAFUSION_MIN_ROWS, chart_spec, timeline_intervals


def table(visibility: list[float], occluders: list[list[int]], idx: int = 2) -> pl.DataFrame:
    n = len(visibility)
    return pl.DataFrame(
        {
            "frame": list(range(n)),
            "total_nanos": [k * 100_000_000 for k in range(n)],
            "idx": [idx] * n,
            "occluder_idxs": occluders,
            "static_occluder_idxs": [[] for _ in range(n)],
            "visibility": visibility,
        },
        schema_overrides={"occluder_idxs": pl.List(pl.Int64), "static_occluder_idxs": pl.List(pl.Int64)},
    )


def test_consecutive_frames_that_look_the_same_are_one_stretch() -> None:
    t = table([1.0, 1.0, 0.5, 0.5, 0.5, 0.0, 1.0], [[], [], [1], [1], [1, 4], [1, 4], []])
    runs = timeline_intervals(t)
    assert runs.select("first_frame", "last_frame", "occluders").rows() == [
        (0, 1, "none"),
        (2, 3, "1"),
        (4, 4, "1, 4"),  # same visibility, another occluder: a stretch of its own
        (5, 5, "1, 4"),
        (6, 6, "none"),
    ]
    # a frame lasts until the next one (0.1 s)
    assert runs["start"].to_list() == pytest.approx([0.0, 0.2, 0.4, 0.5, 0.6])
    assert runs["end"].to_list() == pytest.approx([0.2, 0.4, 0.5, 0.6, 0.7])


def test_a_gap_in_the_frames_starts_a_new_stretch() -> None:
    t = table([1.0] * 4, [[]] * 4).filter(pl.col("frame") != 2)
    assert timeline_intervals(t).select("first_frame", "last_frame").rows() == [(0, 1), (3, 3)]


def test_chart_colours_by_visibility_with_occluders_in_the_tooltip() -> None:
    spec = timeline_chart(table([1.0, 0.0], [[], [3]])).to_dict()
    colour = spec["encoding"]["color"]
    assert colour["field"] == "visibility" and colour["scale"]["domain"] == [0, 1]
    assert colour["scale"]["scheme"] == "cividis"
    assert "occluders" in [t["field"] for t in spec["encoding"]["tooltip"]]
    rows = next(iter(spec["datasets"].values()))
    assert [r["occluders"] for r in rows] == ["none", "3"]


def test_chart_colours_by_status_when_the_table_has_it() -> None:
    t = table([1.0, 0.4, 0.0, 0.0], [[], [1], [1], []]).with_columns(
        status=pl.Series(["visible", "partly_visible", "occluded", "out_of_fov"])
    )
    colour = timeline_chart(t).to_dict()["encoding"]["color"]
    assert colour["field"] == "status"
    assert colour["scale"]["domain"] == ["visible", "partly_visible", "occluded", "out_of_fov"]
    assert colour["scale"]["range"] == [STATUS_COLOURS[s] for s in colour["scale"]["domain"]]
    assert timeline_chart(t, by="visibility").to_dict()["encoding"]["color"]["field"] == "visibility"


def test_bands_are_ordered_by_observer_and_target() -> None:
    t = pl.concat([table([1.0], [[]], idx=10), table([1.0], [[]], idx=2)])
    assert timeline_chart(t).to_dict()["encoding"]["y"]["sort"] == ["idx 2", "idx 10"]


def test_png_export_has_the_chart_size(tmp_path) -> None:
    t = pl.concat([table([1.0, 0.5, 0.0], [[], [1], [1]], idx=i) for i in (1, 2, 3)])
    out = save_timeline(timeline_chart(t, width=300, band=20), tmp_path / "t.png", scale=2)
    with Image.open(out) as im:
        width, height = im.size
    # 300 px of plot plus axis labels, three 20 px bands plus title, axis and legend, all doubled
    assert 600 < width < 900
    assert 120 < height < 500
    svg = save_timeline(t, tmp_path / "t.svg").read_text()
    assert svg.startswith("<svg") and "idx 3" in svg


def test_html_export_is_self_contained(tmp_path) -> None:
    page = save_timeline(table([1.0, 0.0], [[], [1]]), tmp_path / "t.html").read_text()
    assert "<script src=" not in page and "cdn." not in page


def test_long_tables_go_through_vegafusion() -> None:
    n = VEGAFUSION_MIN_ROWS + 10
    t = table([float(k % 2) for k in range(n)], [[] for _ in range(n)])  # alternating: every frame a stretch
    spec, mode = chart_spec(timeline_chart(t))
    assert mode == "vega" and "$schema" in spec and "vega/" in spec["$schema"]
    json.dumps(spec)  # plain data, embeddable as it is


def test_bad_input_is_a_clear_error(tmp_path) -> None:
    with pytest.raises(ValueError, match="is empty"):
        timeline_chart(table([], []))
    with pytest.raises(ValueError, match=r"lacks column\(s\) \['visibility'\]"):
        timeline_chart(table([1.0], [[]]).drop("visibility"))
    with pytest.raises(ValueError, match="no such column"):
        timeline_chart(table([1.0], [[]]), by="status")
    with pytest.raises(ValueError, match=r"must end in \.png or \.svg or \.html or \.json"):
        save_timeline(table([1.0], [[]]), tmp_path / "t.jpg")


def test_an_interrupted_export_keeps_the_previous_file(tmp_path, monkeypatch) -> None:
    # the SVG text is written half and the write fails: the earlier file stays whole under its name (also while
    # the new one is being written) and nothing else is left in the folder
    from pathlib import Path

    target = save_timeline(table([1.0, 0.0], [[], [1]]), tmp_path / "t.svg")
    old = target.read_bytes()
    interrupted_writer(monkeypatch, Path, "write_text", target, old, lambda path: path.write_bytes(b"<svg"))
    with pytest.raises(OSError, match="disk full"):
        save_timeline(table([0.5, 1.0], [[1], []]), target)
    assert [p.name for p in tmp_path.iterdir()] == ["t.svg"] and target.read_bytes() == old


def test_status_colours_tell_every_status_apart_and_dark_means_hidden() -> None:
    from matplotlib.colors import to_rgb

    from omega_prime_visibility.plot.style import CIVIDIS, CLASS_COLOURS

    colours = list(STATUS_COLOURS.values())
    assert len(set(colours)) == len(colours) == 5

    def lightness(colour: str) -> float:
        r, g, b = to_rgb(colour)
        return 0.2126 * r + 0.7152 * g + 0.0722 * b

    # one colour meaning everywhere: the visibility scale's ends and middle (dark = hidden), as the timelines by
    # visibility colour them; the two "not in view" statuses light greys
    assert (STATUS_COLOURS["occluded"], STATUS_COLOURS["visible"]) == (CIVIDIS[0], CIVIDIS[-1])
    assert lightness(STATUS_COLOURS["occluded"]) < lightness(STATUS_COLOURS["partly_visible"]) < 0.6
    assert all(c[1:3] == c[3:5] == c[5:7] for c in (STATUS_COLOURS["out_of_fov"], STATUS_COLOURS["out_of_range"]))
    assert lightness(STATUS_COLOURS["out_of_fov"]) > 0.6 and lightness(STATUS_COLOURS["out_of_range"]) > 0.6
    # the campaign page's classes take the same colours
    assert (CLASS_COLOURS["hidden"], CLASS_COLOURS["visible"]) == (CIVIDIS[0], CIVIDIS[-1])
