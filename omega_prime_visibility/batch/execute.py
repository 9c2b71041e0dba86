"""Where a batch's files are computed: in this process, in a local process pool, or on a dask cluster. Each backend
calls ``report`` with one :class:`FileResult` per task, in completion order; an interruption (KeyboardInterrupt)
stops the workers, whose unfinished results are removed, and propagates."""

from __future__ import annotations

import gc
import importlib
import os
import signal
import threading
import time
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from pathlib import Path

from tqdm.std import tqdm

from . import task as file_task
from .files import remove_leftovers
from .forkserver import PRELOAD, context
from .task import FileResult, FileTask, process_file

Report = Callable[[FileResult], None]
MAX_ATTEMPTS = 2  # a file whose worker process dies this often is reported failed (the others go on)
POLL = 0.25  # seconds between looks at the workers: how soon Ctrl-C is heard while every worker is busy
STOP_SECONDS = 2.0  # how long stopped workers get to remove their unfinished results before they are killed


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells, else all)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else max(1, os.cpu_count() or 1)


def settle() -> None:
    """Import what every file needs, then move everything the imports made out of the garbage collector's sight
    (``gc.freeze``): otherwise every few files a full collection walks all of the libraries' objects (0.18 s here
    with omega-prime's, more than a small recording's whole computation)."""
    for name in PRELOAD:
        importlib.import_module(name)
    gc.freeze()


def run_here(tasks: Sequence[FileTask], report: Report) -> None:
    """Compute the tasks one after the other in this process."""
    settle()
    for task in tasks:
        report(process_file(task))


def run_local(tasks: Sequence[FileTask], n_workers: int, report: Report) -> None:
    """Compute the tasks over ``n_workers`` local processes (forkserver where available, else spawn: workers use
    polars, whose thread pool does not survive a plain fork of a process that used it). A task whose worker dies
    (killed, out of memory) is tried again in a fresh pool; one that dies ``MAX_ATTEMPTS`` times is reported
    failed."""
    start_method = context()  # (the fork server imports what every file needs once: halves a batch of small files)
    attempts: Counter[str] = Counter()
    pending = list(tasks)
    while pending:
        broken: list[FileTask] = []
        pool = ProcessPoolExecutor(
            min(n_workers, len(pending)), mp_context=start_method, initializer=_init_worker, initargs=(os.getpid(),)
        )
        futures = {pool.submit(process_file, task): task for task in pending}
        reported: set[Future] = set()
        try:
            waiting = set(futures)
            while waiting:
                # a wait without a timeout is deaf to Ctrl-C until some file finishes (minutes in 3D): poll
                done, waiting = wait(waiting, timeout=POLL, return_when=FIRST_COMPLETED)
                broken += _report_done(done, futures, reported, report)
        except BaseException:
            # what finished before the stop is on disk: report it as done, then stop the others
            finished = [f for f in futures if f.done() and not f.cancelled() and f.exception() is None]
            _report_done(finished, futures, reported, report)
            _stop(pool, [futures[f] for f in futures if f not in reported])
            raise
        pool.shutdown()
        pending = []
        for task in broken:
            remove_leftovers(Path(task.result))  # a worker killed while writing could not clean up
            attempts[task.result] += 1
            if attempts[task.result] < MAX_ATTEMPTS:
                pending.append(task)
            else:
                message = f"the worker process died {MAX_ATTEMPTS} times while computing or holding this file"
                report(FileResult(task.recording, task.result, "failed", error=f"{message} (killed, out of memory?)"))


def _report_done(done, futures: dict[Future, FileTask], reported: set[Future], report: Report) -> list[FileTask]:
    """Report the results of the finished futures ``done`` not reported yet; return the tasks whose worker died."""
    broken = []
    for future in done:
        if future in reported:
            continue
        reported.add(future)
        try:
            report(future.result())
        except BrokenProcessPool:
            broken.append(futures[future])
    return broken


def _stop(pool: ProcessPoolExecutor, unfinished: Sequence[FileTask] = ()) -> None:
    """Stop the workers now: SIGTERM makes each remove the result it is writing and exit; one that has not within
    :data:`STOP_SECONDS` (inside a long compiled call) is killed, and its unfinished result removed here."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    for process in processes:
        process.terminate()
    deadline = time.monotonic() + STOP_SECONDS
    for process in processes:
        process.join(timeout=max(0.0, deadline - time.monotonic()))
    stubborn = [process for process in processes if process.is_alive()]
    for process in stubborn:
        process.kill()
        process.join(timeout=1.0)
    if stubborn:
        for task in unfinished:
            remove_leftovers(Path(task.result))
    pool.shutdown(wait=False, cancel_futures=True)


def _init_worker(parent_pid: int) -> None:
    # one file per worker and as many workers as cores: library thread pools of their own would only fight over
    # the cores (polars' and arrow's pools start at first use, after this; a user's own setting is kept)
    os.environ.setdefault("POLARS_MAX_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    import pyarrow

    pyarrow.set_cpu_count(int(os.environ["OMP_NUM_THREADS"]))
    # progress bars (disabled here) share a lock; tqdm's default one holds a named semaphore that a worker stopped
    # by SIGTERM cannot release ("leaked semaphore objects" at the end of an interrupted batch): one process, a
    # thread lock is enough
    tqdm.set_lock(threading.RLock())
    settle()
    # Ctrl-C reaches the whole process group: the parent decides and stops the workers with SIGTERM
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _terminate)
    threading.Thread(target=_watch_parent, args=(parent_pid,), daemon=True).start()


def _terminate(signum, frame) -> None:
    """Stopped by the batch: remove what this worker was writing (its temporary files; a result already renamed
    into place is complete and stays) and exit at once. No exception is raised to unwind: one raised inside a
    finaliser that runs at that moment would be printed and swallowed, and the worker would go on."""
    if file_task.CURRENT is not None:
        remove_leftovers(Path(file_task.CURRENT))
    os._exit(143)


def _watch_parent(parent_pid: int) -> None:
    """End this worker when the batch process is gone (killed with SIGKILL, it cannot stop its workers)."""
    while True:
        time.sleep(1.0)
        try:
            os.kill(parent_pid, 0)
        except ProcessLookupError:
            os._exit(1)
        except PermissionError:
            pass


@contextmanager
def sigterm_as_interrupt() -> Iterator[None]:
    """Within the block, SIGTERM to this process stops the batch like Ctrl-C (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum, frame):
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def connect(scheduler: str | None, scheduler_file: str | os.PathLike | None):
    """A ``dask.distributed.Client`` for an existing cluster, by address or scheduler file.

    Raises
    ------
    ValueError
        If the scheduler cannot be reached or the file cannot be read.
    """
    from distributed import Client

    where = scheduler if scheduler is not None else f"the scheduler file {scheduler_file}"
    if scheduler_file is not None and not os.path.isfile(scheduler_file):
        raise ValueError(f"the scheduler file {scheduler_file} does not exist")
    try:
        if scheduler is not None:
            return Client(scheduler, timeout="15s")
        return Client(scheduler_file=str(scheduler_file), timeout="15s")
    except (OSError, TimeoutError, ValueError) as e:
        raise ValueError(f"cannot reach the dask scheduler at {where} ({type(e).__name__}: {e})") from None


def run_dask(tasks: Sequence[FileTask], client, report: Report) -> None:
    """Compute the tasks on the workers of a dask cluster (which must see the input and output paths); a task
    dask gives up on (its workers died) is reported failed. Interrupted, the tasks not started are cancelled."""
    from distributed import as_completed as dask_completed

    try:
        client.run(settle)  # each worker once (a worker without the package fails here and in its tasks alike)
    except Exception:
        pass
    futures = [client.submit(process_file, task, pure=False) for task in tasks]
    by_key = {future.key: task for future, task in zip(futures, tasks, strict=True)}
    try:
        for future in dask_completed(futures):
            task = by_key[future.key]
            try:
                report(future.result())
            except Exception as e:  # KilledWorker, lost connection, the package missing on a worker, ...
                message = " ".join(f"dask: {type(e).__name__}: {e}".split())
                report(FileResult(task.recording, task.result, "failed", error=message))
    except BaseException:
        client.cancel(futures)
        raise
