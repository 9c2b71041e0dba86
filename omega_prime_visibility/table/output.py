"""Writing results safely: output paths checked before any work, files (or a directory of parquet parts) written
under a temporary name and renamed when complete, so nothing half-written is ever left under the final name.

A streamed table is a *dataset*: a directory named like a file (``vis.parquet``) holding one parquet part per
chunk of frames (``part-000000.parquet``, ...), each written by the worker that computed it, all with one schema.
``polars.scan_parquet``, ``polars.read_parquet``, ``pandas.read_parquet`` and ``pyarrow.parquet.read_table`` read
it as one table, in part order.
"""

from __future__ import annotations

import os
import re
import secrets
import shutil
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import polars as pl
import pyarrow as pa
import pyarrow.parquet as pq

from .schema import COUNT_SCHEMA, count_present

PART = re.compile(r"part-\d{6,}\.parquet")
"""Names of the parts of a dataset written here."""


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
            hint = "; output= streams parquet: to write CSV, call omega_prime_visibility.write_csv(table, path)"
        raise ValueError(f"cannot write {path}: the name must end in {' or '.join(suffixes)}{hint}")
    folder = path.parent
    if not folder.exists():
        raise ValueError(f"cannot write {path}: the folder {folder} does not exist")
    if not folder.is_dir():
        raise ValueError(f"cannot write {path}: {folder} is not a folder")
    if path.is_dir() and not (path.suffix == ".parquet" and is_dataset(path)):
        raise ValueError(f"cannot write {path}: it is a directory (and not a parquet dataset written here)")
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


def check_dataset_path(path: str | os.PathLike) -> Path:
    """:func:`check_output_path` for a folder of parquet parts (``output=``, ``run -o x.parquet``): an existing single
    file there is refused, never silently turned into a folder (one written by ``batch`` or another tool would be
    lost, and the name would then hold a folder)."""
    path = check_output_path(path)
    if path.is_file() or (path.is_symlink() and not path.is_dir()):
        raise ValueError(
            f"cannot write {path}: it is a single file, and the output is a folder of parquet parts under that name; "
            "remove it or choose another name"
        )
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


def write_csv(table: pl.DataFrame | pl.LazyFrame, path: str | os.PathLike) -> Path:
    """Write a visibility table as one CSV file, under a temporary name renamed when complete; the list columns
    (``occluder_idxs``, ``static_occluder_idxs``) become their idx joined by spaces (``"1 4"``), as CSV has no lists.

    Raises
    ------
    ValueError
        If ``path`` does not end in ``.csv`` or cannot be written (see :func:`check_output_path`).

    Examples
    --------
    >>> import tempfile
    >>> table = pl.DataFrame({"idx": [2, 3], "occluder_idxs": [[1, 4], []], "visibility": [0.5, 1.0]})
    >>> path = write_csv(table, Path(tempfile.mkdtemp()) / "vis.csv")
    >>> print(path.read_text().strip())
    idx,occluder_idxs,visibility
    2,1 4,0.5
    3,"",1.0
    """
    path = check_output_path(path, (".csv",))
    frame = table.collect() if isinstance(table, pl.LazyFrame) else table
    lists = [name for name, dtype in frame.schema.items() if isinstance(dtype, pl.List)]
    if lists:
        frame = frame.with_columns(pl.col(lists).list.eval(pl.element().cast(pl.String)).list.join(" "))
    with atomic_write(path) as temp:
        frame.write_csv(temp)
    return path


def is_dataset(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a directory holding parquet parts written here and nothing else (so it may be replaced)."""
    path = Path(path)
    if not path.is_dir() or path.is_symlink():
        return False
    names = [p.name for p in path.iterdir()]
    return bool(names) and all(PART.fullmatch(name) for name in names)


@contextmanager
def atomic_directory(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a new, empty temporary directory next to ``path``; on success it replaces ``path`` (a file or a
    dataset, see :func:`is_dataset`), on any error it is removed.

    The old content is first renamed away, then the new directory renamed in, then the old removed: at no moment
    does ``path`` hold a half-written result (a run killed between the two renames leaves ``path`` absent and the
    previous result under a hidden name beside it).

    Examples
    --------
    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> with atomic_directory(folder / "t.parquet") as temp:
    ...     (temp / "part-000000.parquet").write_bytes(b"")
    0
    >>> sorted(p.name for p in folder.iterdir()), is_dataset(folder / "t.parquet")
    (['t.parquet'], True)
    """
    path = Path(path)
    temp = _temp_name(path)
    temp.mkdir()
    try:
        yield temp
        old = None
        if path.exists() or path.is_symlink():
            old = _temp_name(path)
            os.replace(path, old)
        os.replace(temp, path)
    except BaseException:
        shutil.rmtree(temp, ignore_errors=True)
        raise
    if old is not None and old.is_dir() and not old.is_symlink():
        shutil.rmtree(old)
    elif old is not None:
        old.unlink()


def parquet_options(schema: pa.Schema) -> dict:
    """How results are written to parquet (pyarrow's ``write_table`` and ``ParquetWriter`` keywords): zstd at its
    fastest level, and dictionaries for every column but the floating-point ones.

    The integer columns repeat (a frame's rows, an observer's targets, the few blockers) and shrink to almost nothing
    in dictionaries; a float column (``visibility``) has as many values as partly hidden targets, and a dictionary of
    them costs time to write and to read for no gain. Against pyarrow's defaults (snappy, dictionaries everywhere) a
    result is a third smaller, written a tenth and read three times faster (every object as observer on the
    synthetic highway: 2.7 bytes a row instead of 4.0).

    >>> schema = pa.schema(
    ...     [("idx", pa.int64()), ("occluder_idxs", pa.large_list(pa.int64())), ("visibility", pa.float64())]
    ... )
    >>> parquet_options(schema)["use_dictionary"]  # (by the paths of the stored values: a list's are its elements)
    ['idx', 'occluder_idxs.list.element']
    """
    leaves = [leaf for f in schema for leaf in _leaves(f.name, f.type)]
    return {
        "compression": "zstd",
        "compression_level": 1,
        "use_dictionary": [path for path, type_ in leaves if not pa.types.is_floating(type_)],
    }


def _leaves(path: str, type_: pa.DataType) -> list[tuple[str, pa.DataType]]:
    """The stored columns under a field: (parquet's path of each, its Arrow type)."""
    if pa.types.is_list(type_) or pa.types.is_large_list(type_) or pa.types.is_fixed_size_list(type_):
        return _leaves(f"{path}.list.element", type_.value_type)
    if pa.types.is_dictionary(type_):
        return [(path, type_.value_type)]
    return [(path, type_)]


def chunk_table(schema: pa.Schema, labels: Mapping[str, Sequence[str]], columns: Mapping) -> pa.Table:
    """A chunk's columns as an Arrow table of ``schema`` (see :class:`PartWriter` for what the columns hold)."""
    return pa.Table.from_arrays([_array(f, columns[f.name], labels) for f in schema], schema=schema)


@dataclass(frozen=True)
class PartWriter:
    """Writes the ``k``-th chunk's columns as ``part-{k:06d}.parquet`` in ``directory`` (called in the worker
    that computed them; pyarrow only, no polars, which does not survive a fork).

    Parameters
    ----------
    directory : Path
        The dataset's (temporary) directory.
    schema : pyarrow.Schema
        The table's schema (e.g. ``empty_table(...).to_arrow().schema``): column order and types. Large-list
        columns come as ``(lengths, values)`` pairs of arrays, the others as arrays.
    labels : mapping of str to sequence of str
        For string or dictionary columns: the strings that the column's integer codes stand for.
    """

    directory: Path
    schema: pa.Schema
    labels: Mapping[str, Sequence[str]] = field(default_factory=dict)

    def __call__(self, k: int, columns: Mapping | None) -> int:
        """Write chunk ``k`` (nothing when ``columns`` is None); the number of rows written."""
        if columns is None:
            return 0
        table = chunk_table(self.schema, self.labels, columns)
        pq.write_table(table, self.directory / f"part-{k:06d}.parquet", **parquet_options(self.schema))
        return table.num_rows

    def write_empty(self) -> None:
        """Write a part with no rows, so that an empty result still reads as a table with the schema."""
        pq.write_table(self.schema.empty_table(), self.directory / "part-000000.parquet")


class FileWriter:
    """Writes chunks, in the order they come, as the row groups of one parquet file (where the chunks are computed
    one after another in this process): what :class:`PartWriter` and :func:`join_parts` give, without writing the
    rows twice. A context manager: the file is complete when it closes.

    Parameters
    ----------
    path : Path
        The (temporary) file.
    schema, labels
        As for :class:`PartWriter`.
    metadata : mapping of bytes to bytes, optional
        Key-value metadata added to the file's schema's.
    """

    def __init__(self, path: Path, schema: pa.Schema, labels: Mapping[str, Sequence[str]], metadata=None) -> None:
        self.schema, self.labels = schema, labels
        self._file = schema.with_metadata({**(schema.metadata or {}), **(metadata or {})})
        self._writer = pq.ParquetWriter(path, self._file, **parquet_options(schema))

    def __call__(self, k: int, columns: Mapping | None) -> int:
        """Write the next chunk (``k`` counts them; nothing when ``columns`` is None); the number of rows written."""
        return 0 if columns is None else self.write(chunk_table(self.schema, self.labels, columns))

    def write(self, table: pa.Table) -> int:
        """Append an Arrow table of the file's schema (its own metadata aside); the number of rows written."""
        self._writer.write_table(table.replace_schema_metadata(self._file.metadata))
        return table.num_rows

    def write_empty(self) -> None:
        """Nothing to do: the file has its schema already."""

    def __enter__(self) -> FileWriter:
        return self

    def __exit__(self, *exc) -> None:
        self._writer.close()


def join_parts(dataset: Path, path: Path, metadata=None) -> int:
    """The parts of a dataset written as the one file ``path`` with ``metadata`` added to its schema's, one part at
    a time (memory stays that of a chunk); the rows written."""
    files = sorted(dataset.glob("part-*.parquet"))
    schema = pq.read_schema(files[0])
    with FileWriter(path, schema, {}, metadata) as writer:
        return sum(writer.write(pq.read_table(part, schema=schema)) for part in files)


def _array(f: pa.Field, data, labels: Mapping[str, Sequence[str]]) -> pa.Array:
    if f.name in COUNT_SCHEMA:  # nulls where the sensor does not count (see .schema.missing_counts)
        values = np.asarray(data)
        valid = np.packbits(count_present(f.name, values), bitorder="little")
        if pa.types.is_fixed_size_list(f.type):
            flat = _numbers(values.reshape(-1), f.type.value_type)
            return pa.Array.from_buffers(f.type, len(values), [pa.py_buffer(valid)], children=[flat])
        numbers = _numbers(values, f.type)
        return pa.Array.from_buffers(f.type, len(values), [pa.py_buffer(valid), numbers.buffers()[1]])
    if pa.types.is_large_list(f.type):
        lengths, values = data
        offsets = np.zeros(len(lengths) + 1, dtype=np.int64)
        np.cumsum(lengths, out=offsets[1:])
        return pa.LargeListArray.from_arrays(_numbers(offsets, pa.int64()), _numbers(values, f.type.value_type))
    if pa.types.is_dictionary(f.type):
        dictionary = pa.array(list(labels[f.name]), f.type.value_type)
        return pa.DictionaryArray.from_arrays(_numbers(data, f.type.index_type), dictionary)
    if f.name in labels:
        return pa.array(list(labels[f.name]), f.type).take(_numbers(data, pa.int64()))
    return _numbers(data, f.type)


def _numbers(values, type_: pa.DataType) -> pa.Array:
    """An Arrow array of fixed-width numbers or booleans over the numpy array's memory (``pa.array`` of a numpy
    array imports pandas, a quarter of a second of a short run).

    >>> _numbers(np.array([1, 2]), pa.int32()).to_pylist()
    [1, 2]
    >>> _numbers(np.array([True, False, True]), pa.bool_()).to_pylist()
    [True, False, True]
    >>> _numbers(np.array([1.5]), pa.int64())
    Traceback (most recent call last):
    ...
    TypeError: the values of an Arrow int64 column changed on conversion from float64
    """
    if pa.types.is_boolean(type_):
        flags = np.asarray(values, dtype=bool)
        _same(flags, values, type_)
        bits = np.packbits(flags, bitorder="little")
        return pa.Array.from_buffers(type_, len(flags), [None, pa.py_buffer(bits)])
    data = np.ascontiguousarray(values, dtype=type_.to_pandas_dtype())
    _same(data, values, type_)
    return pa.Array.from_buffers(type_, len(data), [None, pa.py_buffer(data)])


def _same(converted: np.ndarray, values, type_: pa.DataType) -> None:
    """A TypeError where converting ``values`` to ``type_`` changed them (a fraction cut, a negative number made
    unsigned, a missing value made False), as ``pa.array`` refused them."""
    original = np.asarray(values)
    if original.dtype != converted.dtype and not np.array_equal(converted, original):
        raise TypeError(f"the values of an Arrow {type_} column changed on conversion from {original.dtype}")
