"""Batch over many recordings: files, folders and globs -> one parquet result each, locally or on a dask cluster.

- :mod:`.options`: :class:`FileOptions`, what every file of a batch is computed with, stored in each result;
- :mod:`.files`: inputs -> (recording, result) pairs, current results, leftovers of interrupted runs;
- :mod:`.run`: :func:`run_batch`, :func:`process_file` (one file, atomic), the summary;
- :mod:`.execute`: where the files are computed: here, a local process pool, or a dask cluster.
"""

from .options import FileOptions
from .run import SUMMARY_NAME, BatchInterrupted, run_batch
from .task import FileResult, FileTask, process_file

__all__ = ["SUMMARY_NAME", "BatchInterrupted", "FileOptions", "FileResult", "FileTask", "process_file", "run_batch"]
