"""Writing results safely: output paths checked before any work, files written under a temporary name and renamed
when complete, so nothing half-written is ever left under the final name."""

from __future__ import annotations

import os
import secrets
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path


def check_output_path(path: str | os.PathLike, suffixes: Sequence[str] = (".parquet",)) -> Path:
    """``path`` as a Path, after checking that a file ending in one of ``suffixes`` can be written there.

    Raises
    ------
    ValueError
        If the suffix is not one of ``suffixes``, the folder is missing or not a folder, the path is a directory
        or a read-only file, or the folder is not writable; the message names the path and the problem.
    """
    path = Path(path)
    if path.suffix not in suffixes:
        hint = ""
        if path.suffix == ".csv":
            hint = "; output= streams parquet: to write CSV, call write_csv on the returned table"
        raise ValueError(f"cannot write {path}: the name must end in {' or '.join(suffixes)}{hint}")
    folder = path.parent
    if not folder.exists():
        raise ValueError(f"cannot write {path}: the folder {folder} does not exist")
    if not folder.is_dir():
        raise ValueError(f"cannot write {path}: {folder} is not a folder")
    if path.is_dir():
        raise ValueError(f"cannot write {path}: it is a directory")
    if path.exists() and not os.access(path, os.W_OK):
        raise ValueError(f"cannot write {path}: the file exists and is read-only")
    # permissions alone do not tell (read-only mounts, /proc, ACLs): create and remove a file to be sure
    probe = _temp_name(path)
    try:
        os.close(os.open(probe, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        os.remove(probe)
    except OSError as e:
        raise ValueError(f"cannot write {path}: cannot create files in {folder} ({e.strerror or e})") from None
    return path


def _temp_name(path: Path) -> Path:
    """A hidden, unused name next to ``path`` (same folder, so the final rename is atomic)."""
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")


@contextmanager
def atomic_write(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; rename it to ``path`` on success, remove it on any error.

    So an interrupted or failed run never leaves a half-written file under the final name.
    """
    path = Path(path)
    temp = _temp_name(path)
    try:
        yield temp
        os.replace(temp, path)
    except BaseException:
        temp.unlink(missing_ok=True)
        raise
