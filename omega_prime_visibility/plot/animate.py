"""An animation over a range of frames, seen from the ego: GIF (pillow) or MP4 (ffmpeg from ``imageio-ffmpeg``)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from tqdm.auto import tqdm

from ..query import Query
from ..table.output import atomic_write, check_output_path
from ._optional import require
from .data import FrameSpec, describe_question, load_source, picture_question
from .frame import check_target, picture_viewer
from .painter import FramePainter
from .style import KEY_COLOURS, OKABE_ITO, VISIBILITY_CMAP
from .window import AUTO, path_limits, scene_window

SUFFIXES = (".gif", ".mp4")
PROGRESS_MIN_FRAMES = 200


def animate(
    df: Any,
    ego_idx: int | None,
    output: str | os.PathLike,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    frames: FrameSpec = None,
    fps: float = 10.0,
    follow: bool = True,
    view_range: float | str = AUTO,
    target: int | None = None,
    sensors: Any = None,
    lanes: Any = True,
    size: tuple[float, float] = (9.6, 5.4),
    dpi: int = 100,
    colours: int = 256,
    engine: str | None = None,
    mode: str | None = None,
    progress: bool | None = None,
    occluders: Any = None,
    query: Query | None = None,
    **question: Any,
) -> Path:
    """Render frames seen from ``ego_idx`` to an animated GIF or an MP4 video; return the path written.

    Each picture is :func:`~.frame.plot_frame`'s, with the frame, the time and the ego's speed in its title and a
    thin progress line along the bottom edge of the picture.

    Parameters
    ----------
    df : omega_prime.Recording, polars DataFrame/LazyFrame or MCAP path
        The moving objects.
    ego_idx : int
        The observer.
    output : path
        Ends in ``.gif`` (written with pillow) or ``.mp4`` (H.264, needs the ffmpeg that ``imageio-ffmpeg``
        brings). Checked before anything is drawn; written under a temporary name and renamed when complete.
    static_occluder_polys : sequence of shapely geometries, optional
        As for ``get_visibility_df``.
    frames : slice, range or sequence of frame numbers, optional
        Which frames (frame numbers, not positions), by default all; ``slice(30, 90)`` takes those from 30 up to
        (not including) 90 that occur, ``slice(None, None, 2)`` every second one. An empty range or a frame that
        does not occur raises ``ValueError``.
    fps : float
        Frames per second of the animation.
    view_range : float or "auto"
        The scene shows every object within this many metres of the ego, as :func:`~.frame.plot_frame` does
        ("auto", the default: 50 m, or through sensors the reach of those that look around).
    follow : bool
        Follow the ego with a window that shows every object within ``view_range`` metres of it in any of the
        frames (:mod:`.window`, the same rule as :func:`~.frame.plot_frame`'s); False shows one fixed view
        covering the ego's whole path with that window around it.
    target, sensors, lanes : optional
        As for :func:`~.frame.plot_frame`.
    size, dpi : (float, float), int
        Picture size in inches and dots per inch (9.6 x 5.4 at 100 dpi: 960 x 540 pixels).
    colours : int
        GIF palette size (2 to 256): one palette for the whole animation, from its first frame and the visibility
        colour map (so the colour bar and the fills do not band).
    engine, mode : str
        As for ``get_visibility_df``: ``mode="3d"`` colours the objects by their 3D visibility (the region shaded
        is still the bird's-eye one).
    occluders : str, sequence or polars expression, optional
        Who may block the view, as for ``get_visibility_df``: the numbers computed here and the region shaded as
        seen honour it (give the choice a ``table=`` was computed with). Default: everything blocks.
    progress : bool, optional
        Show a progress bar while rendering; by default for ``PROGRESS_MIN_FRAMES`` frames or more.
    query : Query, optional
        The whole question as one value, and the other table keywords of ``get_visibility_df``, as for
        :func:`~.frame.plot_frame`.

    Examples
    --------
    >>> import polars as pl, tempfile, pathlib
    >>> cars = pl.DataFrame({"frame": [0, 0, 1, 1], "total_nanos": [0, 0, 10**8, 10**8], "idx": [0, 1, 0, 1],
    ...                      "x": [0.0, 20.0, 2.0, 21.0], "y": [0.0, 0.0, 0.0, 0.0], "length": [4.0] * 4,
    ...                      "width": [2.0] * 4, "yaw": [0.0] * 4})
    >>> out = animate(cars, 0, pathlib.Path(tempfile.mkdtemp()) / "two.gif", view_range=30, dpi=40)
    >>> out.stat().st_size > 0
    True
    """
    output = check_output_path(output, SUFFIXES)
    if not (isinstance(fps, int | float) and 0 < fps <= 100):
        raise ValueError(f"fps must be a number of frames per second in (0, 100], not {fps!r}")
    if not (isinstance(colours, int) and 2 <= colours <= 256):
        raise ValueError(f"colours must be an integer from 2 to 256, not {colours!r}")
    if output.suffix == ".mp4":
        require("imageio_ffmpeg", "writing MP4")
    else:
        require("PIL", "writing GIF")
    asked = picture_question(query, ego_idx, static_occluder_polys, engine=engine, mode=mode, sensors=sensors,
                             occluders=occluders, **question)  # fmt: skip
    source = load_source(df, asked, lanes)
    positions = source.positions(frames)
    check_target(source, target, positions)
    viewer = picture_viewer(df, source, asked, positions, view_range)
    pictures = render(
        source, viewer, positions, follow=follow, view_range=view_range, target=target, size=size, dpi=dpi,
        progress=len(positions) >= PROGRESS_MIN_FRAMES if progress is None else progress,
        choices=describe_question(asked),
    )  # fmt: skip
    with atomic_write(output) as temp:
        if output.suffix == ".gif":
            write_gif(pictures, temp, fps, colours)
        else:
            write_mp4(pictures, temp, fps)
    return output


def render(source, viewer, positions, *, follow, view_range, target, size, dpi, progress, choices=""):
    """Yield one RGB picture (uint8 array, shape (h, w, 3)) per frame position; ``choices``: the question's
    choices in words, under each title."""
    require("matplotlib")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    fig = Figure(figsize=size, dpi=dpi, layout="constrained")
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    window = scene_window(source.objects, viewer.ego_idx, positions, viewer.reach, source.lanes.points)
    painter = FramePainter(ax, source, viewer.ego_idx, target=target, sensors=viewer.sensors, window=window,
                           legend_columns=5, region=viewer.region, choices=choices)  # fmt: skip
    # no tick labels: a scene that follows the ego has the scale bar for metres, and each frame draws far less text
    ax.set(xticks=[], yticks=[], xlabel="", ylabel="")
    window = painter.fit()
    if painter.show_only(path_limits(source.objects, viewer.ego_idx, positions, window)):  # what any frame shows
        window = painter.fit()
    limits = None if follow else path_limits(source.objects, viewer.ego_idx, positions, window)
    # progress: a thin line along the bottom edge of the picture, outside the scene, drawn over each frame
    bar = Rectangle((0, 0), 0, 0.006, transform=fig.transFigure, facecolor=OKABE_ITO["blue"], lw=0, zorder=10)
    fig.add_artist(bar)
    n = len(positions)
    for j, k in enumerate(tqdm(positions.tolist(), desc="frames", unit="frame", disable=not progress)):
        view = viewer.view(k)
        speed = source.ego_speed(viewer.ego_idx, view.frame)
        clock = f"frame {view.frame}, t = {view.total_nanos / 1e9:.2f} s, ego {viewer.ego_idx} at "
        clock += f"{speed:.1f} m/s ({speed * 3.6:.0f} km/h)" if np.isfinite(speed) else "unknown speed"
        painter.draw(view, limits, title=clock)
        bar.set_width((j + 1) / n)
        if j == 0:
            # lay out once and keep every frame's axes where the first frame's are; what lies outside the scene's
            # axes (colour bar, legend) is the same in every frame: keep its pixels and redraw only the axes
            canvas.draw()
            fig.set_layout_engine("none")
            ax.set_visible(False)
            bar.set_visible(False)
            canvas.draw()
            background = canvas.copy_from_bbox(fig.bbox)
            ax.set_visible(True)
            bar.set_visible(True)
        canvas.restore_region(background)
        ax.draw(canvas.get_renderer())
        bar.draw(canvas.get_renderer())
        yield np.asarray(canvas.buffer_rgba())[:, :, :3].copy()


def write_gif(pictures, path: Path, fps: float, colours: int) -> None:
    """Write RGB pictures as a looping GIF with one palette of ``colours`` colours (:func:`gif_palette`: the
    pictures' key colours exactly, the rest cut from the first picture and the visibility colour map; a palette of
    64 colours per frame banded the colour bar, and took 2.5 times as long). The pictures are quantized as they
    come: one byte a pixel is kept, not three."""
    image = require("PIL.Image", "writing GIF")
    palette = None
    frames = []
    for picture in pictures:
        if palette is None:
            palette = gif_palette(picture, colours)
        frames.append(image.fromarray(picture).quantize(palette=palette, dither=image.Dither.NONE))
    frames[0].save(
        path, format="GIF", save_all=True, append_images=frames[1:], duration=round(1000 / fps), loop=0, optimize=False
    )


def gif_palette(picture: np.ndarray, colours: int) -> Any:
    """A GIF's one palette of ``colours`` colours, as a pillow ``P`` image: each of :data:`~.style.KEY_COLOURS`
    exactly (a small ego or a sensor's outline keeps its colour), then a median cut of the first picture's pixels
    and of the visibility colour map's 256 colours on as many pixels in all as the picture has (so that the colour
    bar and the fills keep their gradient)."""
    image = require("PIL.Image", "writing GIF")
    keys = np.array([[int(c[i : i + 2], 16) for i in (1, 3, 5)] for c in KEY_COLOURS], dtype=np.uint8)
    keys = keys[: colours // 2]  # (a small palette keeps half of it for the cut)
    n = picture.shape[0] * picture.shape[1]
    scale = require("matplotlib").colormaps[VISIBILITY_CMAP](np.linspace(0.0, 1.0, 256))[:, :3]
    gradient = np.tile(np.rint(scale * 255).astype(np.uint8), (max(n // 256, 1), 1))
    sample = np.concatenate([picture.reshape(-1, 3), gradient]).reshape(-1, 1, 3)
    cut = image.fromarray(sample).quantize(colors=colours - len(keys), method=image.Quantize.MEDIANCUT)
    entries = keys.ravel().tolist() + cut.getpalette()[: 3 * (colours - len(keys))]
    palette = image.new("P", (1, 1))
    palette.putpalette(entries + [0] * (768 - len(entries)))
    return palette


def write_mp4(pictures, path: Path, fps: float) -> None:
    """Write RGB pictures as an H.264 MP4 (yuv420p, so sizes are cut to even numbers of pixels)."""
    ffmpeg = require("imageio_ffmpeg", "writing MP4")
    writer = None
    try:
        for p in pictures:
            h, w = p.shape[0] // 2 * 2, p.shape[1] // 2 * 2
            if writer is None:
                writer = ffmpeg.write_frames(
                    str(path), (w, h), fps=fps, codec="libx264", pix_fmt_out="yuv420p", macro_block_size=2,
                    output_params=["-f", "mp4"], quality=7,
                )  # fmt: skip
                writer.send(None)
            writer.send(np.ascontiguousarray(p[:h, :w]))
    finally:
        if writer is not None:
            writer.close()
