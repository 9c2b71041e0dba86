"""Make every picture of the README from the bundled recording with the package's own plotting functions:
``uv run python scripts/make_pictures.py`` (or ``make pictures``) writes docs/frame.png, docs/merge.gif (at most
2 MB), docs/timeline.png, for the sensors docs/sensors.png and docs/sensors_timeline.png, docs/threed.png
(:mod:`threed_picture`, a made-up scene where 2D and 3D disagree) and docs/urban.png (the town junction of
``scenarios/urban.py``: buildings, parked buses, queues and pedestrians), docs/camera.png and docs/camera_merge.png
(what a camera sees, :func:`camera_pictures`).

The scene is the README's example: ``highway_merge.mcap`` seen from idx 0, with the guard rail as a static occluder.
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import polars as pl
import shapely

from omega_prime_visibility import animate, get_visibility_df, plot_camera, plot_frame, save_timeline, timeline_chart
from omega_prime_visibility.inputs.io import read_recording
from omega_prime_visibility.inputs.sensors import camera

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(1, str(Path(__file__).resolve().parent.parent / "scenarios"))
import threed_picture
from urban import building_heights, urban_scene

REPO = Path(__file__).resolve().parent.parent
DOCS = REPO / "docs"
GIF_LIMIT = 2_000_000  # bytes


URBAN_FRAME, URBAN_TARGET = 60, 163  # the ego queued at the junction; a pedestrian hidden by parked cars


def urban_picture() -> None:
    """docs/urban.png: the town junction from the queued ego, the buildings as static occluders, a pedestrian on
    the far sidewalk as the target."""
    table, buildings = urban_scene(frames=URBAN_FRAME + 1)
    fig, ax = plt.subplots(figsize=(9, 7.2), layout="constrained")
    plot_frame(table, 0, URBAN_FRAME, buildings, target=URBAN_TARGET, ax=ax)
    fig.savefig(DOCS / "urban.png", dpi=110)
    plt.close(fig)


CAMERA = camera("front", 1920, 1080, math.radians(90), x=1.5, z=1.4)


def camera_pictures() -> None:
    """docs/camera.png: what a 1920 x 1080 front camera of the queued ego sees at the town junction (buildings with
    their heights); docs/camera_merge.png: the bundled recording's ego at frame 30, through a 70° camera."""
    table, buildings = urban_scene(frames=URBAN_FRAME + 1)
    fig, ax = plt.subplots(figsize=(11, 6.6), layout="constrained")
    plot_camera(table, 0, URBAN_FRAME, buildings, sensors=[CAMERA], ax=ax,
                static_occluder_heights=building_heights(buildings))  # fmt: skip
    fig.savefig(DOCS / "camera.png", dpi=110)
    plt.close(fig)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(REPO / "highway_merge.mcap")
    fig, ax = plt.subplots(figsize=(11, 6.6), layout="constrained")
    plot_camera(r, 0, 30, sensors=[camera("front", 1920, 1080, math.radians(70), x=1.0, z=1.4)], ax=ax)
    fig.savefig(DOCS / "camera_merge.png", dpi=110)
    plt.close(fig)


def main() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(REPO / "highway_merge.mcap")
    rail = [shapely.LineString([(60, -5.4), (140, -5.4)])]

    fig, ax = plt.subplots(figsize=(11, 4.6), layout="constrained")
    plot_frame(r, 0, 30, rail, target=2, ax=ax, view_range=70)
    fig.savefig(DOCS / "frame.png", dpi=110)
    plt.close(fig)

    # every second frame at 5 frames per second: real time, and small enough for a README
    gif = animate(
        r,
        0,
        DOCS / "merge.gif",
        rail,
        frames=slice(None, None, 2),
        fps=5,
        target=3,
        view_range=75,
        size=(8.0, 4.5),
        colours=128,
    )
    size = gif.stat().st_size
    if size > GIF_LIMIT:
        raise SystemExit(f"{gif} is {size / 1e6:.2f} MB, more than the README's {GIF_LIMIT / 1e6:.0f} MB")

    table = get_visibility_df(r, 0, rail, progress=False)
    chart = timeline_chart(table, title="visibility from ego 0 in highway_merge.mcap (guard rail included)")
    save_timeline(chart, DOCS / "timeline.png", scale=1.5)

    # the typical sensor set on the ego: fields of view at frame 30, and the status per sensor over time
    fig, ax = plt.subplots(figsize=(11, 4.6), layout="constrained")
    plot_frame(r, 0, 30, rail, target=2, sensors="typical", ax=ax, view_range=70)
    fig.savefig(DOCS / "sensors.png", dpi=110)
    plt.close(fig)
    per_sensor = get_visibility_df(r, 0, rail, sensors="typical", progress=False)
    shown = per_sensor.filter(pl.col("sensor").is_in(["front_camera", "corner_rear_left"]))
    chart = timeline_chart(shown, title="status per sensor from ego 0: front camera and rear-left corner radar")
    save_timeline(chart, DOCS / "sensors_timeline.png", scale=1.5)
    threed_picture.main(DOCS / "threed.png")
    urban_picture()
    camera_pictures()
    print(
        f"wrote {DOCS / 'frame.png'}, {gif} ({size / 1e6:.2f} MB), {DOCS / 'timeline.png'}, sensors, 3D and urban "
        "pictures"
    )


if __name__ == "__main__":
    main()
