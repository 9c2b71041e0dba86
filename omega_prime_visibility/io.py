"""Reading recordings: omega-prime MCAP files and ASAM OSI traces, with errors that name the file."""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import Any


class RecordingReadError(ValueError):
    """A file could not be read as an omega-prime recording."""


def read_recording(path: str | os.PathLike, map_path: str | os.PathLike | None = None) -> Any:
    """An ``omega_prime.Recording`` with object polygons, from an MCAP file (or an OSI trace with its map).

    Raises
    ------
    RecordingReadError
        If the file is missing or cannot be parsed (corrupt or truncated MCAP, wrong format); the message names
        the file and the underlying error.
    """
    import omega_prime

    path = Path(path)
    if not path.exists():
        raise RecordingReadError(f"{path} does not exist")
    kwargs = {"map_path": str(map_path)} if map_path is not None else {}
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="Failed to apply projections")
            return omega_prime.Recording.from_file(str(path), compute_polygons=True, **kwargs)
    except Exception as e:  # omega-prime and its readers raise many kinds; report them as one, naming the file
        raise RecordingReadError(f"cannot read {path} as an omega-prime recording ({type(e).__name__}: {e})") from e
