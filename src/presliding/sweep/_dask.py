"""Sweeps on a Dask cluster: a small graph, data sent once, chunks built on the workers.

`run_on_dask` scatters the function (with the base model it carries) to every
worker once. A product grid's description (its axes, `_grid.Points`) is
broadcast the same way, and each task carries those two futures and an index
range ``(i, n_chunks)``: a few hundred bytes whatever the size of the grid, and
a worker builds its chunk's columns itself. A table's rows cannot be described
more briefly than they are: each chunk's rows are scattered once, to one
worker, and its task runs there, so every row crosses the network once.

A worker that dies takes no broadcast data with it: the scheduler re-runs its
chunks elsewhere (a killed worker is not a failed task). Table rows that were
only on that worker are scattered again and their chunks re-run.
``retries`` re-runs chunks whose function raised.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import CancelledError
from typing import Any

from presliding._interop import install_hint, require
from presliding._validation import check_type, fmt
from presliding.sweep._grid import Points, describe_error, run_chunk

DASK_HINT = f"install it with `{install_hint('dask')}`"
#: How long a sweep waits for a first worker to join a scheduler that has none [s].
WORKER_WAIT = 60.0
#: How many times a table's chunks are scattered again after their worker died.
LOST_DATA_ROUNDS = 3


def import_distributed() -> Any:
    distributed = require("distributed", "running a sweep on a Dask cluster")
    require("distributed.comm", "running a sweep on a Dask cluster")
    return distributed


def check_address(address: str) -> None:
    """Reject a malformed scheduler address before any connection is tried.

    (A Client made from a malformed address fails, and distributed's clean-up
    then holds the exiting process for a minute.) Raises ImportError, naming
    the extra to install, when `distributed` is missing.
    """
    check_type("scheduler", address, str)
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
    """Every chunk on the cluster; (ok, values or error text) per chunk, in chunk order.

    A product grid's axes are broadcast to every worker, and each task is an index
    range. A table's rows are scattered chunk by chunk (each row sent once, to
    one worker, where its task then runs); when a worker dies with rows that
    were only there, those chunks are scattered and run again, up to
    `LOST_DATA_ROUNDS` times.
    """
    distributed = import_distributed()
    fn_future = client.scatter(fn, broadcast=True, hash=False)
    shared = None
    if points.kind == "product":
        shared = client.scatter(points, broadcast=True, hash=False)
    outcomes: list[tuple[bool, Any]] = [(False, "not run")] * n_chunks
    pending = list(range(n_chunks))
    held: list[Any] = [fn_future, shared]
    try:
        for _ in range(LOST_DATA_ROUNDS):
            if shared is not None:
                args = [(shared, i, n_chunks) for i in pending]
            else:
                rows = client.scatter([points.rows(i, n_chunks) for i in pending], hash=False)
                held += rows
                args = [(r, 0, 1) for r in rows]
            tag = time.time_ns()
            futures = client.map(
                run_chunk,
                [fn_future] * len(pending),
                *(list(column) for column in zip(*args, strict=True)),
                key=[f"presliding-sweep-{tag}-{i}" for i in pending],
                retries=retries,
                pure=False,
            )
            held += futures
            index = {f.key: i for f, i in zip(futures, pending, strict=True)}
            lost = []
            for future in distributed.as_completed(futures, loop=client.loop):
                i = index[future.key]
                try:
                    outcomes[i] = future.result()
                except CancelledError as exc:  # a chunk's rows died with their worker
                    outcomes[i] = (False, describe_error(exc))
                    lost.append(i)
                    continue
                except Exception as exc:  # fn raised (after the retries), or the cluster gave up
                    outcomes[i] = (False, describe_error(exc))
                bar.update()
            if not lost or shared is not None:
                break
            pending = sorted(lost)
    finally:
        client.cancel([f for f in held if f is not None])
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
