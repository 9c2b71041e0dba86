"""Batch over many recordings: files, folders and globs -> one parquet result each, locally or on a dask cluster.

- :mod:`.options`: :class:`FileOptions`, what every file of a batch is computed with, stored in each result;
- :mod:`.files`: inputs -> (recording, result) pairs, current results, leftovers of interrupted runs;
- :mod:`.task`: :func:`process_file`, one file computed and written atomically (and its conflicts, when asked);
- :mod:`.run`: :func:`run_batch` and the summary;
- :mod:`.execute`: where the files are computed: here, a local process pool, or a dask cluster;
- :mod:`.forkserver`: what the local workers' fork server imports, started early by the command line;
- :mod:`.campaign`: :func:`~.campaign.campaign_statistics` over a batch output folder.
"""

from .. import _lazy_names

_WHERE = {
    "FileOptions": "options",
    "SUMMARY_NAME": "run",
    "BatchInterrupted": "run",
    "run_batch": "run",
    "FileResult": "task",
    "FileTask": "task",
    "process_file": "task",
}
"""Where each name lives, loaded on first use (PEP 562): the command line imports :mod:`.forkserver` first, alone."""

__all__ = sorted(_WHERE)


__getattr__, __dir__ = _lazy_names(__name__, _WHERE)
