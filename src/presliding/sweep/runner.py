"""Parameter sweeps in chunks: local worker processes by default, a Dask cluster on request.

``sweep(fn, grid)`` evaluates a vectorised function on every point of a
parameter grid. The points are cut into chunks and ``fn`` is called once per
chunk with keyword arrays, ``fn(name_1=array, name_2=array, ...)``, each of the
chunk's length, and returns one value (or one row of values) per point. That
keeps the per-call overhead away from batch kernels that run a whole chunk in
compiled code.

Where it runs: ``scheduler=None`` uses a local pool of worker processes
(``n_workers``, default: all cores; 1 runs in this process; started with
"forkserver" where available, so ``fn`` must be importable, as for Dask); a
scheduler address string (``"tcp://host:8786"``) or a ``distributed.Client``
runs the chunks on a Dask cluster (optional dependency: ``pip install presliding[dask]``). Every
backend calls ``fn`` on the same kind of chunks, so an elementwise ``fn`` gives
the same values everywhere.
"""

from __future__ import annotations

import math
import os
import pickle
import time
from collections.abc import Callable, Mapping
from concurrent.futures import Executor, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any

import numpy as np
from numpy.typing import NDArray

from presliding._validation import as_count, as_real_vector, fmt
from presliding.sweep.result import SweepResult, where_run

__all__ = ["SweepResult", "sweep"]

DASK_HINT = "install it with `pip install presliding[dask]`"


def _run_chunk(fn: Callable[..., Any], columns: dict[str, np.ndarray]) -> tuple[bool, Any]:
    """Call fn on one chunk; return (True, values) or (False, error text). Runs in workers."""
    n = next(iter(columns.values())).shape[0]
    try:
        out = np.asarray(fn(**columns))
    except Exception as exc:  # reported on the result, not raised in the worker
        return False, f"{type(exc).__name__}: {exc}"
    if out.ndim == 0 or out.shape[0] != n:
        return False, f"`fn` must return one value per point ({n}); got shape {out.shape}"
    if out.dtype.kind not in "biuf":
        return False, f"`fn` must return real numbers; got dtype {out.dtype}"
    return True, out


def _as_grid(grid: Any) -> tuple[str, dict[str, np.ndarray], dict[str, np.ndarray]]:
    """(kind, grid as stored on the result, columns of all points)."""
    if isinstance(grid, np.ndarray) and grid.dtype.names:
        if grid.ndim != 1 or grid.shape[0] == 0:
            raise ValueError(
                f"`grid` as a table must be a non-empty 1-D structured array; got shape "
                f"{grid.shape}."
            )
        cols = {n: as_real_vector(f"grid[{n!r}]", grid[n]) for n in grid.dtype.names}
        return "table", cols, cols
    if not isinstance(grid, Mapping) or not grid:
        raise TypeError(
            "`grid` must be a non-empty dict of 1-D arrays (Cartesian product) or a "
            f"1-D structured array (table); got {fmt(grid)}."
        )
    axes = {}
    for name, arr in grid.items():
        if not isinstance(name, str) or not name.isidentifier():
            raise ValueError(f"`grid` keys must be parameter names; got {fmt(name)}.")
        if np.ndim(arr) > 1:
            raise ValueError(f"`grid[{name!r}]` must be one-dimensional; got {np.shape(arr)}.")
        axes[name] = as_real_vector(f"grid[{name!r}]", arr)
    mesh = np.meshgrid(*axes.values(), indexing="ij")
    cols = {n: np.ascontiguousarray(m.ravel()) for n, m in zip(axes, mesh, strict=True)}
    return "product", axes, cols


def check_address(address: str) -> None:
    """Reject a malformed scheduler address before any connection is tried.

    (A Client made from a malformed address fails, and distributed's clean-up
    then holds the exiting process for a minute.) Raises ImportError, naming
    the extra to install, when `distributed` is missing.
    """
    distributed = _import_distributed()
    try:
        distributed.comm.get_address_host_port(address)
    except ValueError as exc:
        raise ValueError(
            f"`scheduler` must be a scheduler address such as 'tcp://10.0.0.5:8786'; "
            f"got {address!r} ({exc})."
        ) from None


def _import_distributed() -> Any:
    try:
        import distributed
        import distributed.comm
    except ImportError as exc:
        raise ImportError(
            f"running a sweep on a Dask cluster needs the optional `distributed` package; "
            f"{DASK_HINT}."
        ) from exc
    return distributed


def _dask_client(scheduler: Any) -> tuple[Any, bool]:
    """(client, whether this call owns and must close it)."""
    distributed = _import_distributed()
    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    if isinstance(scheduler, str):
        check_address(scheduler)
        return distributed.Client(scheduler, set_as_default=False), True
    raise TypeError(
        "`scheduler` must be None, a scheduler address string, a distributed.Client or an "
        "Executor; "
        f"got {type(scheduler).__name__}."
    )


def sweep(
    fn: Callable[..., Any],
    grid: Mapping[str, Any] | np.ndarray,
    scheduler: Any = None,
    *,
    chunk_size: int | None = None,
    n_workers: int | None = None,
    progress: bool = False,
) -> SweepResult:
    """Evaluate a vectorised function on every point of a parameter grid, in chunks.

    Parameters
    ----------
    fn : callable
        ``fn(**columns) -> array`` with one keyword per parameter, each a 1-D
        float64 array of a chunk's length; returns one value (or one row) per
        point. It must be picklable (a module-level function) for worker
        processes and Dask.
    grid : dict of str to 1-D array, or 1-D structured array
        A dict gives the Cartesian product of its axes (``values`` gets their
        shape); a structured array gives a table, one point per row.
    scheduler : None, str, distributed.Client or concurrent.futures.Executor
        None: a new pool of local worker processes. An address string or a
        Client: Dask (``pip install presliding[dask]``); a Client made from an
        address is closed afterwards, a given Client is left open. An Executor
        (e.g. a ProcessPoolExecutor kept for many sweeps, which saves the worker
        start-up) is used as given and left open.
    chunk_size : int, optional
        Points per call of `fn`; default about four chunks per worker.
    n_workers : int, optional
        Local worker processes (default: the machine's cores; 1 runs serially
        in this process). With an Executor, only reported; ignored with Dask.
    progress : bool
        Show a progress bar over the chunks.

    Returns
    -------
    SweepResult
        ``status`` is "failed" when any chunk raised or any point got only NaN
        or infinite values from `fn`; those points are NaN and flagged in
        ``failed``, and ``message`` says how many failed and names the first
        failing chunk and the first non-finite point.
    """
    if not callable(fn):
        raise TypeError(f"`fn` must be callable; got {fmt(fn)}.")
    kind, stored, cols = _as_grid(grid)
    if kind == "product":
        shape = tuple(a.size for a in stored.values())
    else:
        shape = (next(iter(cols.values())).shape[0],)
    n = int(np.prod(shape))
    client = owned = None
    if isinstance(scheduler, Executor):
        client = scheduler
        given = getattr(scheduler, "_max_workers", None) or 1
        workers = given if n_workers is None else as_count("n_workers", n_workers, minimum=1)
        backend = "executor"
    elif scheduler is not None:
        client, owned = _dask_client(scheduler)
        workers = max(1, len(client.nthreads()))
        backend = "dask"
    else:
        default = os.cpu_count() or 1
        workers = default if n_workers is None else as_count("n_workers", n_workers, minimum=1)
        backend = "serial" if workers == 1 else "processes"
    if chunk_size is None:
        size = max(1, math.ceil(n / (4 * workers)))
    else:
        size = as_count("chunk_size", chunk_size, minimum=1)
    # Chunk i holds points i, i + n_chunks, i + 2·n_chunks, ...: interleaving spreads
    # expensive regions of the grid over all chunks, so workers finish together.
    n_chunks = math.ceil(n / size)
    chunks = [{k: np.ascontiguousarray(v[i::n_chunks]) for k, v in cols.items()}
              for i in range(n_chunks)]  # fmt: skip
    if backend != "serial":
        try:
            pickle.dumps(fn)
        except Exception as exc:
            raise TypeError(
                f"`fn` must be picklable (a module-level function) to run in worker processes; "
                f"got {fmt(fn)} ({exc})."
            ) from exc
    t0 = time.perf_counter()
    try:
        outcomes = _execute(fn, chunks, backend, workers, client, progress)
    finally:
        if owned:
            client.close()
    elapsed = time.perf_counter() - t0
    return _assemble(outcomes, chunks, n, shape, kind, stored, elapsed, workers, backend)


def _execute(fn, chunks, backend, workers, client, progress):
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(chunks), unit="chunk", desc="sweep")
    try:
        if backend == "serial":
            outcomes = []
            for c in chunks:
                outcomes.append(_run_chunk(fn, c))
                if bar is not None:
                    bar.update()
            return outcomes
        if backend == "executor":
            return _on_executor(client, fn, chunks, bar)
        if backend == "processes":
            n_proc = min(workers, len(chunks))
            with ProcessPoolExecutor(max_workers=n_proc, mp_context=_mp_context()) as pool:
                return _on_executor(pool, fn, chunks, bar)
        futures = client.map(_run_chunk, [fn] * len(chunks), chunks, pure=False)
        if bar is not None:
            for f in futures:
                f.add_done_callback(lambda _: bar.update())
        return client.gather(futures)
    finally:
        if bar is not None:
            bar.close()


def _on_executor(pool: Executor, fn, chunks, bar) -> list[tuple[bool, Any]]:
    futures = [pool.submit(_run_chunk, fn, c) for c in chunks]
    if bar is not None:
        for f in futures:
            f.add_done_callback(lambda _: bar.update())
    return [_result(f) for f in futures]


def _mp_context() -> Any:
    """'forkserver' where available: workers start from a clean, single-threaded
    process, so a parent that already runs threads (numba's parallel layer, a
    Dask client) cannot leave them with a broken copy, as plain fork can."""
    import multiprocessing

    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("forkserver" if "forkserver" in methods else None)


def _result(future: Any) -> tuple[bool, Any]:
    try:
        return future.result()
    except BrokenProcessPool as exc:
        return False, f"a worker process died ({type(exc).__name__}: {exc})"


def _nonfinite_points(values: np.ndarray, failed: NDArray[np.bool_]) -> NDArray[np.intp]:
    """Flat indices of the points not yet failed whose value (every entry of a row) is NaN
    or infinite: `fn` gave nothing usable there."""
    if values.dtype.kind not in "fc" or values.size == 0:
        return np.empty(0, dtype=np.intp)
    finite = np.isfinite(values.reshape(values.shape[0], -1))
    return np.flatnonzero(~finite.any(axis=1) & ~failed)


def _assemble(outcomes, chunks, n, shape, kind, stored, elapsed, workers, backend):
    outcomes = list(outcomes)
    n_chunks = len(outcomes)
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
        first = ", ".join(f"{k}={float(v[0])!r}" for k, v in chunks[i].items())
        parts.append(
            f"{len(errors)} of {n_chunks} chunks failed; chunk {i} (first point {first}) "
            f"raised {text}"
        )
    nonfinite = _nonfinite_points(values, failed)
    if nonfinite.size:
        j = int(nonfinite[0])
        chunk, pos = chunks[j % n_chunks], j // n_chunks
        where = ", ".join(f"{k}={float(v[pos])!r}" for k, v in chunk.items())
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
        grid=dict(stored),
        values=values.reshape(*shape, *row),
        elapsed=elapsed,
        n_workers=workers,
        status=status,
        message=message,
        kind=kind,
        backend=backend,
        n_chunks=len(outcomes),
        failed=failed.reshape(shape),
    )
