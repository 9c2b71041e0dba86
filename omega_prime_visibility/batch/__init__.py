"""Batch over many recordings: files, folders and globs -> one parquet result each, locally or on a dask cluster.

- :mod:`.options`: :class:`FileOptions`, what every file of a batch is computed with, stored in each result;
- :mod:`.files`: inputs -> (recording, result) pairs, current results, leftovers of interrupted runs;
- :mod:`.task`: :func:`process_file`, one file computed and written atomically (and its conflicts, when asked);
- :mod:`.run`: :func:`run_batch` and the summary;
- :mod:`.execute`: where the files are computed: here, a local process pool, or a dask cluster;
- :mod:`.campaign`: :func:`~.campaign.campaign_statistics` over a batch output folder.
"""

from .options import FileOptions
from .run import SUMMARY_NAME, BatchInterrupted, run_batch
from .task import FileResult, FileTask, process_file

__all__ = ["SUMMARY_NAME", "BatchInterrupted", "FileOptions", "FileResult", "FileTask", "process_file", "run_batch"]
