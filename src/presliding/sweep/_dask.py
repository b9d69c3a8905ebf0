"""Sweeps on a Dask cluster: a small graph, data sent once, chunks built on the workers.

`run_on_dask` scatters the function (with the base model it carries) and the
description of the points (`_grid.Points`: product axes or table columns) to
every worker once, then submits one task per chunk whose arguments are those two
futures and an index range ``(i, n_chunks)``. Each task is a few hundred bytes
whatever the size of the grid; a worker builds its chunk's columns itself.

Both are broadcast to every worker, so a worker that dies takes no data with it:
the scheduler re-runs its chunks elsewhere (a killed worker is not a failed
task), and ``retries`` re-runs chunks whose function raised.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from presliding._validation import fmt
from presliding.sweep._grid import Points, describe_error, run_chunk

DASK_HINT = "install it with `pip install presliding[dask]`"
#: How long a sweep waits for a first worker to join a scheduler that has none [s].
WORKER_WAIT = 60.0


def import_distributed() -> Any:
    try:
        import distributed
        import distributed.comm
    except ImportError as exc:
        raise ImportError(
            f"running a sweep on a Dask cluster needs the optional `distributed` package; "
            f"{DASK_HINT}."
        ) from exc
    return distributed


def check_address(address: str) -> None:
    """Reject a malformed scheduler address before any connection is tried.

    (A Client made from a malformed address fails, and distributed's clean-up
    then holds the exiting process for a minute.) Raises ImportError, naming
    the extra to install, when `distributed` is missing.
    """
    distributed = import_distributed()
    try:
        distributed.comm.get_address_host_port(address)
    except ValueError as exc:
        raise ValueError(
            f"`scheduler` must be a scheduler address such as 'tcp://10.0.0.5:8786'; "
            f"got {address!r} ({exc})."
        ) from None


def dask_client(scheduler: Any) -> tuple[Any, bool]:
    """(client, whether this call owns and must close it)."""
    distributed = import_distributed()
    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    if isinstance(scheduler, str):
        check_address(scheduler)
        return distributed.Client(scheduler, set_as_default=False), True
    raise TypeError(
        "`scheduler` must be None, a scheduler address string, a distributed.Client or an "
        f"Executor; got {type(scheduler).__name__}."
    )


def cluster_threads(client: Any) -> tuple[int, int]:
    """(workers, threads) of the cluster, waiting up to `WORKER_WAIT` s for a first worker."""
    nthreads = client.nthreads()
    if not nthreads:
        import asyncio

        try:
            client.wait_for_workers(1, timeout=WORKER_WAIT)
        except (TimeoutError, asyncio.TimeoutError):  # distinct types before Python 3.11
            raise RuntimeError(
                f"the Dask scheduler at {client.scheduler.address} has no workers after "
                f"{WORKER_WAIT:g} s; start some with `dask worker {client.scheduler.address}`."
            ) from None
        nthreads = client.nthreads()
    return len(nthreads), max(1, sum(nthreads.values()))


def check_cloudpickle(fn: Callable[..., Any]) -> int:
    """The size of `fn` as Dask sends it (cloudpickle: lambdas and closures are fine)."""
    import cloudpickle

    try:
        return len(cloudpickle.dumps(fn))
    except Exception as exc:
        raise TypeError(
            f"`fn` must be serialisable by cloudpickle to run on Dask workers; got {fmt(fn)} "
            f"({type(exc).__name__}: {exc})."
        ) from exc


def run_on_dask(
    client: Any,
    fn: Callable[..., Any],
    points: Points,
    n_chunks: int,
    *,
    retries: int,
    bar: Any,
) -> list[tuple[bool, Any]]:
    """Every chunk on the cluster; (ok, values or error text) per chunk, in chunk order."""
    distributed = import_distributed()
    fn_future = client.scatter(fn, broadcast=True, hash=False)
    points_future = client.scatter(points, broadcast=True, hash=False)
    futures = client.map(
        run_chunk,
        [fn_future] * n_chunks,
        [points_future] * n_chunks,
        range(n_chunks),
        [n_chunks] * n_chunks,
        key=[f"presliding-sweep-{time.time_ns()}-{i}" for i in range(n_chunks)],
        retries=retries,
        pure=False,
    )
    index = {f.key: i for i, f in enumerate(futures)}
    outcomes: list[tuple[bool, Any]] = [(False, "not run")] * n_chunks
    try:
        for future in distributed.as_completed(futures, loop=client.loop):
            try:
                outcomes[index[future.key]] = future.result()
            except Exception as exc:  # fn raised (after the retries), or the cluster gave up
                outcomes[index[future.key]] = (False, describe_error(exc))
            bar.update()
    finally:
        client.cancel([*futures, fn_future, points_future])
    return outcomes


__all__ = [
    "DASK_HINT",
    "check_address",
    "check_cloudpickle",
    "cluster_threads",
    "dask_client",
    "import_distributed",
    "run_on_dask",
]
