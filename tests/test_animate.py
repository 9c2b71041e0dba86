"""Animations: GIF and MP4 read back (frame count, size, content), frame selection, speeds, bad input."""

from __future__ import annotations

import numpy as np
import polars as pl
import pytest
from conftest import interrupted_writer
from PIL import Image

from omega_prime_visibility import Query
from omega_prime_visibility.plot import animate
from omega_prime_visibility.plot.data import load_source
from omega_prime_visibility.plot.style import EGO_FACE


def moving_table(n_frames: int = 4, drop_ego_at: int | None = None) -> pl.DataFrame:
    """The ego drives at 20 m/s (2 m per 0.1 s frame) past a parked car; frames 10, 11, ..."""
    rows = []
    for k in range(n_frames):
        if k != drop_ego_at:
            rows.append((10 + k, k * 100_000_000, 0, 2.0 * k, 0.0))
        rows.append((10 + k, k * 100_000_000, 1, 15.0, 3.5))
    frame, nanos, idx, x, y = map(list, zip(*rows, strict=True))
    n = len(rows)
    return pl.DataFrame(
        {"frame": frame, "total_nanos": nanos, "idx": idx, "x": x, "y": y, "length": [4.0] * n,
         "width": [2.0] * n, "yaw": [0.0] * n}
    )  # fmt: skip


def frames_of(path) -> list[np.ndarray]:
    with Image.open(path) as im:
        out = []
        for k in range(im.n_frames):
            im.seek(k)
            out.append(np.asarray(im.convert("RGB")))
        return out


def test_gif_has_one_picture_per_frame_of_the_asked_size(tmp_path) -> None:
    out = animate(moving_table(), 0, tmp_path / "a.gif", size=(4, 2.5), dpi=50, view_range=20, progress=False)
    pictures = frames_of(out)
    assert len(pictures) == 4
    assert pictures[0].shape == (125, 200, 3)  # 4 x 2.5 inches at 50 dpi
    # the scene moves (the parked car slides left as the ego passes), so the pictures differ
    assert np.abs(pictures[0].astype(int) - pictures[-1].astype(int)).sum() > 0
    with Image.open(out) as im:
        assert im.info["duration"] == 100 and im.info["loop"] == 0  # 10 frames per second, looping


def test_frame_selection_by_slice_and_list(tmp_path) -> None:
    out = animate(moving_table(6), 0, tmp_path / "b.gif", frames=slice(11, 15, 2), dpi=30, progress=False)
    assert len(frames_of(out)) == 2  # frames 11 and 13
    out = animate(moving_table(6), 0, tmp_path / "c.gif", frames=[10, 15], dpi=30, follow=False, progress=False)
    assert len(frames_of(out)) == 2


def test_mp4_reads_back(tmp_path) -> None:
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    out = animate(moving_table(5), 0, tmp_path / "a.mp4", size=(4, 2.5), dpi=50, fps=5, progress=False)
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    assert meta["size"] == (200, 124)  # even height for yuv420p
    assert meta["fps"] == 5
    assert sum(1 for _ in reader) == 5


def test_ego_speed_from_positions_or_velocity_columns() -> None:
    table = moving_table()
    assert load_source(table, Query(observers=0)).ego_speed(0, 11) == pytest.approx(20.0)
    with_velocity = table.with_columns(vel_x=pl.lit(3.0), vel_y=pl.lit(4.0))
    assert load_source(with_velocity, Query(observers=0)).ego_speed(0, 11) == pytest.approx(5.0)


@pytest.mark.parametrize(
    ("frames", "problem"),
    [
        (slice(100, 200), "frame range 100 to 200 (stop excluded) is empty"),
        ([], "frame range is empty"),
        ([10, 99], "frame 99 does not occur in the table (frames 10 to 13)"),
    ],
)
def test_bad_frame_selection_is_a_clear_error(tmp_path, frames, problem: str) -> None:
    with pytest.raises(ValueError, match=problem.replace("(", r"\(").replace(")", r"\)")):
        animate(moving_table(), 0, tmp_path / "a.gif", frames=frames)
    assert list(tmp_path.iterdir()) == []


def test_unsupported_suffix_and_missing_ego_leave_no_file(tmp_path) -> None:
    with pytest.raises(ValueError, match=r"must end in \.gif or \.mp4"):
        animate(moving_table(), 0, tmp_path / "a.avi")
    with pytest.raises(ValueError, match="ego idx 0 is not present in frame 12"):
        animate(moving_table(drop_ego_at=2), 0, tmp_path / "a.gif", dpi=30, progress=False)
    assert list(tmp_path.iterdir()) == []  # neither the file nor a temporary one


def test_an_interrupted_gif_keeps_the_previous_one(tmp_path, monkeypatch) -> None:
    # the GIF writer writes half a file and fails: the earlier GIF stays whole under its name (also while the new
    # one is being written) and nothing else is left in the folder
    import importlib

    target = animate(moving_table(2), 0, tmp_path / "a.gif", dpi=20, progress=False)
    old = target.read_bytes()
    module = importlib.import_module("omega_prime_visibility.plot.animate")
    interrupted_writer(monkeypatch, module, "write_gif", target, old, lambda path: path.write_bytes(old[:100]))
    with pytest.raises(OSError, match="disk full"):
        animate(moving_table(3), 0, target, dpi=20, progress=False)
    assert [p.name for p in tmp_path.iterdir()] == ["a.gif"] and target.read_bytes() == old


def test_a_target_absent_from_the_frames_drawn_is_an_error(tmp_path) -> None:
    table = moving_table(4, drop_ego_at=None).filter(~((pl.col("idx") == 1) & (pl.col("frame") < 12)))
    with pytest.raises(ValueError, match=r"target idx 1 never occurs in the frames drawn"):
        animate(table, 0, tmp_path / "t.gif", frames=[10, 11], target=1, progress=False)
    with pytest.raises(ValueError, match=r"target idx 7 never occurs"):
        animate(table, 0, tmp_path / "t.gif", target=7, progress=False)
    assert list(tmp_path.iterdir()) == []
    assert animate(table, 0, tmp_path / "t.gif", frames=[11, 12], target=1, dpi=30, progress=False).exists()


def test_the_colour_bar_of_a_gif_does_not_band(tmp_path) -> None:
    # one palette for the animation, from its first picture (whose bar holds every visibility's colour): the bar
    # keeps its gradient (a palette of 64 colours per frame left about 20 steps in its 430 pixels)
    out = animate(moving_table(3), 0, tmp_path / "bar.gif", progress=False)
    with Image.open(out) as gif:
        gif.seek(2)
        rgb = np.asarray(gif.convert("RGB")).astype(int)
    right = rgb[:, int(rgb.shape[1] * 0.8) :]
    steps = [len({tuple(c) for c in right[:, x]}) for x in range(right.shape[1])]
    assert max(steps) > 60  # the bar's column: dozens of distinct colours top to bottom
    ego = [int(EGO_FACE[i : i + 2], 16) for i in (1, 3, 5)]
    assert (rgb.reshape(-1, 3) == ego).all(axis=1).sum() > 20  # the key colours exact: the ego's vermillion
