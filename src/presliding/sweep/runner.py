"""Parameter sweeps in chunks: local worker processes by default, a Dask cluster on request.

``sweep(fn, grid)`` evaluates a vectorised function on every point of a
parameter grid. The points are cut into chunks and ``fn`` is called once per
chunk with keyword arrays, ``fn(name_1=array, name_2=array, ...)``, each of the
chunk's length, and returns one value (or one row of values) per point. That
keeps the per-call overhead away from batch kernels that run a whole chunk in
compiled code.

Where it runs: ``scheduler=None`` uses a local pool of worker processes
(``n_workers``, default: all cores; 1 runs in this process; loky's pool, which
starts clean interpreters and never re-runs the calling script, and ``fn`` sent
by value with cloudpickle, so a function defined in a notebook or a script
works: `presliding.sweep._local`); a scheduler
address string (``"tcp://host:8786"``) or a ``distributed.Client`` runs the
chunks on a Dask cluster (optional dependency: ``pip install "presliding[dask]"``),
where the grid's description is sent once and each task carries an index range
(`presliding.sweep._dask`). Every backend calls ``fn`` on the same chunks, so an
elementwise ``fn`` gives the same values everywhere.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Mapping
from concurrent.futures import Executor
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._progress import Progress
from presliding._validation import as_count, fmt
from presliding.sweep._dask import (
    DASK_HINT,
    check_address,
    check_cloudpickle,
    cluster_threads,
    dask_client,
    run_on_dask,
)
from presliding.sweep._grid import Points, as_points, describe_error, run_chunk
from presliding.sweep._local import by_value, on_executor, on_local_pool
from presliding.sweep.result import SweepResult, where_run

__all__ = ["DASK_HINT", "SweepResult", "check_address", "sweep"]

#: Default chunks per worker (per thread on Dask): enough to balance uneven chunks.
CHUNKS_PER_WORKER = 4
#: Most local worker processes (each starts an interpreter and the compiled kernels).
MAX_WORKERS = 1024
#: Without a scheduler or `n_workers`, a sweep whose chunks would take less than this many
#: seconds in all runs in this process [s]: starting worker processes (an interpreter,
#: numpy and presliding each) costs seconds, 27 s of wall time for a trivial function on a
#: loaded 2-core machine. The first chunk, run here, times one chunk.
IN_PROCESS_SECONDS = 2.0


def sweep(
    fn: Callable[..., Any],
    grid: Mapping[str, Any] | np.ndarray,
    scheduler: Any = None,
    *,
    chunk_size: int | None = None,
    n_workers: int | None = None,
    progress: bool = False,
    retries: int = 0,
) -> SweepResult:
    """Evaluate a vectorised function on every point of a parameter grid, in chunks.

    Parameters
    ----------
    fn : callable
        ``fn(**columns) -> array`` with one keyword per parameter, each a 1-D
        float64 array of a chunk's length; returns one value (or one row) per
        point. It is sent to worker processes by value (cloudpickle): a function
        defined in a notebook or in a script's ``__main__``, a lambda or a
        closure works, as long as what it holds can be pickled.
    grid : dict of str to 1-D array, or 1-D structured array
        A dict gives the Cartesian product of its axes (``values`` gets their
        shape); a structured array gives a table, one point per row.
    scheduler : None, str, distributed.Client or concurrent.futures.Executor
        None: a new pool of local worker processes. An address string or a
        Client: Dask (``pip install "presliding[dask]"``); a Client made from an
        address is closed afterwards, a given Client is left open. An Executor
        (e.g. a ProcessPoolExecutor kept for many sweeps, which saves the worker
        start-up) is used as given and left open.
    chunk_size : int, optional
        Points per call of `fn`. Default: about four chunks per local worker,
        or per worker thread of the Dask cluster.
    n_workers : int, optional
        Local worker processes (1 runs serially in this process). Default: the
        first chunk runs in this process and is timed; when all the chunks would
        take less than `IN_PROCESS_SECONDS` (2 s) here, or there is one chunk, the
        rest run here too (``backend`` "serial": a pool's start-up would cost
        more), else on the machine's cores. With an Executor, only reported;
        ignored with Dask, where the cluster's workers are counted.
    progress : bool
        Show progress on stderr once the sweep has run for a second: a bar on a
        terminal, else a line per tenth of the chunks
        (`presliding._progress.Progress`).
    retries : int
        Dask only: how many times the scheduler re-runs a chunk whose `fn`
        raised before it is reported as failed. A chunk whose worker died is
        re-run on another worker in any case (Dask's own rule). Local backends
        run each chunk once.

    Returns
    -------
    SweepResult
        ``status`` is "failed" when any chunk raised or any point got only NaN
        or infinite values from `fn`; those points are NaN and flagged in
        ``failed``, and ``message`` says how many failed and names the first
        failing chunk and the first non-finite point (a worker process that
        died is named with its signal or exit code and the likely cause).
        Ctrl-C (KeyboardInterrupt) cancels the queued chunks, ends the local
        workers without waiting for them and propagates.

    Notes
    -----
    On Dask, the function and the grid's description (the axes of a product, or
    the columns of a table) are scattered to every worker once, and each task
    carries only an index range: the task graph stays a few hundred bytes per
    chunk, and each worker builds its chunks itself. Chunk ``i`` of ``n``
    holds the points ``i, i + n, i + 2n, ...``, on every backend, so an
    elementwise `fn` gives the same values everywhere.
    """
    if not callable(fn):
        raise TypeError(f"`fn` must be callable; got {fmt(fn)}.")
    points = as_points(grid)
    retries = as_count("retries", retries)
    n = points.n_points
    client: Any = None
    owned = False
    threads = None
    if isinstance(scheduler, Executor):
        client = scheduler
        given = getattr(scheduler, "_max_workers", None) or 1
        workers = (
            given
            if n_workers is None
            else as_count("n_workers", n_workers, minimum=1, maximum=MAX_WORKERS)
        )
        backend = "executor"
    elif scheduler is not None:
        check_cloudpickle(fn)
        client, owned = dask_client(scheduler)
        backend = "dask"
    else:
        default = os.cpu_count() or 1
        workers = (
            default
            if n_workers is None
            else as_count("n_workers", n_workers, minimum=1, maximum=MAX_WORKERS)
        )
        backend = "serial" if workers == 1 else ("auto" if n_workers is None else "processes")
    if chunk_size is not None:
        chunk_size = as_count("chunk_size", chunk_size, minimum=1)
    if backend in ("processes", "executor", "auto"):
        by_value(fn)  # a TypeError now if it cannot be sent (whatever the timing decides)
    t0 = time.perf_counter()
    try:
        if backend == "dask":
            workers, threads = cluster_threads(client)
        size = chunk_size or max(1, math.ceil(n / (CHUNKS_PER_WORKER * (threads or workers))))
        n_chunks = math.ceil(n / size)
        with Progress(
            "presliding sweep", total=n_chunks, unit="chunk", quiet=not progress, delay=1.0
        ) as bar:
            if backend == "auto":
                outcomes, backend, workers = _timed(fn, points, n_chunks, workers, bar)
            else:
                outcomes = _execute(fn, points, n_chunks, backend, workers, client, bar, retries)
    finally:
        if owned:
            client.close()
    elapsed = time.perf_counter() - t0
    return _assemble(outcomes, points, elapsed, workers, backend)


def _timed(fn, points, n_chunks, workers, bar):
    """The first chunk here, timed; the rest here too when all would take less than
    `IN_PROCESS_SECONDS` (or there is no rest), else on a pool. Returns (outcomes, backend,
    workers)."""
    start = time.perf_counter()
    first = _execute(fn, points, n_chunks, "serial", 1, None, bar, 0, stop=1)
    took = time.perf_counter() - start
    if n_chunks == 1 or took * n_chunks < IN_PROCESS_SECONDS:
        rest = _execute(fn, points, n_chunks, "serial", 1, None, bar, 0, start=1)
        return first + rest, "serial", 1
    workers = min(workers, n_chunks - 1)
    rest = on_local_pool(by_value(fn), points, n_chunks, workers, bar, first=1)
    return first + rest, "processes", workers


def _execute(fn, points, n_chunks, backend, workers, client, bar, retries, start=0, stop=None):
    """(ok, values or error text) per chunk, in chunk order (serially: chunks start..stop)."""
    if backend == "serial":
        outcomes = []
        for i in range(start, n_chunks if stop is None else stop):
            try:
                outcomes.append(run_chunk(fn, points, i, n_chunks))
            except Exception as exc:  # reported on the result, not raised
                outcomes.append((False, describe_error(exc)))
            bar.update()
        return outcomes
    if backend == "dask":
        return run_on_dask(client, fn, points, n_chunks, retries=retries, bar=bar)
    if backend == "executor":
        return on_executor(client, by_value(fn), points, n_chunks, bar)
    return on_local_pool(by_value(fn), points, n_chunks, min(workers, n_chunks), bar)


def _nonfinite_points(values: np.ndarray, failed: NDArray[np.bool_]) -> NDArray[np.intp]:
    """Flat indices of the points not yet failed whose value (every entry of a row) is NaN
    or infinite: `fn` gave nothing usable there."""
    if values.dtype.kind not in "fc" or values.size == 0:
        return np.empty(0, dtype=np.intp)
    finite = np.isfinite(values.reshape(values.shape[0], -1))
    return np.flatnonzero(~finite.any(axis=1) & ~failed)


def _assemble(
    outcomes: list[tuple[bool, Any]],
    points: Points,
    elapsed: float,
    workers: int,
    backend: str,
) -> SweepResult:
    outcomes = list(outcomes)
    n_chunks, n, shape = len(outcomes), points.n_points, points.shape
    row = next((out.shape[1:] for ok, out in outcomes if ok), ())
    for i, (ok, out) in enumerate(outcomes):
        if ok and out.shape[1:] != row:
            outcomes[i] = (False, f"`fn` must return rows of one shape {row}; got {out.shape[1:]}")
    errors = [(i, out) for i, (ok, out) in enumerate(outcomes) if not ok]
    good = [out for ok, out in outcomes if ok]
    dtype = np.result_type(*good) if good and not errors else np.float64
    values = np.empty((n, *row), dtype=dtype)
    failed = np.zeros(n, dtype=bool)
    for i, (ok, out) in enumerate(outcomes):
        if ok:
            values[i::n_chunks] = out
        else:
            values[i::n_chunks] = np.nan
            failed[i::n_chunks] = True
    parts = []
    if errors:
        i, text = errors[0]
        first = ", ".join(f"{k}={v!r}" for k, v in points.point(i).items())
        parts.append(
            f"{len(errors)} of {n_chunks} chunks failed; chunk {i} (first point {first}) "
            f"raised {text}"
        )
    nonfinite = _nonfinite_points(values, failed)
    if nonfinite.size:
        j = int(nonfinite[0])
        where = ", ".join(f"{k}={v!r}" for k, v in points.point(j).items())
        index = tuple(int(q) for q in np.unravel_index(j, shape))
        parts.append(
            f"{nonfinite.size} of {n} points got no finite value from `fn`; the first at "
            f"{where} (index {index[0] if len(index) == 1 else index})"
        )
        values[nonfinite] = np.nan
        failed[nonfinite] = True
    if parts:
        status, message = "failed", "; ".join(parts)
    else:
        status = "ok"
        message = f"{n} points in {n_chunks} chunks {where_run(backend, workers)}"
    return SweepResult(
        grid=dict(zip(points.names, points.arrays, strict=True)),
        values=values.reshape(*shape, *row),
        elapsed=elapsed,
        n_workers=workers,
        status=status,
        message=message,
        kind=points.kind,
        backend=backend,
        n_chunks=n_chunks,
        failed=failed.reshape(shape),
    )
