"""Local worker processes of a sweep: the function sent by value, dead workers named.

A sweep's ``fn`` goes to the workers *by value* (cloudpickle), wrapped in
`ByValue`: a function defined in a notebook, in a script's ``__main__``, a
lambda or a closure runs in the workers, which never import ``__main__``. The
default pool is loky's (the process executor of joblib): its workers start
fresh interpreters without re-running the calling script, so a script without
an ``if __name__ == "__main__"`` guard runs its sweep once, not once per
worker. A worker that dies (killed for memory, a crash in compiled code) is
reported by its exit signal or code, in the result's message; Ctrl-C cancels
the queued chunks and ends the workers without waiting for them.
"""

from __future__ import annotations

import signal
from collections.abc import Callable
from concurrent.futures import Executor, Future
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from presliding._validation import fmt
from presliding.sweep._grid import Points, describe_error, run_chunk

__all__ = ["ByValue", "by_value", "on_executor", "on_local_pool"]


class ByValue:
    """A function carried as cloudpickle bytes: picklable by reference itself, it loads
    the function by value in the worker (once per worker and function)."""

    __slots__ = ("_fn", "payload")

    def __init__(self, payload: bytes) -> None:
        self.payload = payload
        self._fn: Callable[..., Any] | None = None

    def __getstate__(self) -> bytes:
        return self.payload

    def __setstate__(self, payload: bytes) -> None:
        self.payload, self._fn = payload, None

    def __call__(self, **columns: Any) -> Any:
        if self._fn is None:
            import cloudpickle

            self._fn = cloudpickle.loads(self.payload)
        return self._fn(**columns)


def by_value(fn: Callable[..., Any]) -> ByValue:
    """`fn` serialised by value, or a TypeError naming what cannot be sent."""
    import cloudpickle

    try:
        return ByValue(cloudpickle.dumps(fn))
    except Exception as exc:
        raise TypeError(
            f"`fn` must be picklable by cloudpickle to run in worker processes; got {fmt(fn)} "
            f"({type(exc).__name__}: {exc}). Move what it holds that cannot be sent (an open "
            "file, a lock, a client) inside the function."
        ) from exc


def _cause(exc: BaseException) -> str:
    """Why a worker died, in words: the signal or exit code loky names, and its usual cause."""
    text = str(exc)
    hints = {
        "SIGKILL": "killed by the system, most often for lack of memory: use smaller chunks "
        "(`chunk_size`) or fewer workers",
        "SIGSEGV": "a crash in compiled code",
        "SIGABRT": "aborted by the runtime",
        "SIGTERM": "terminated from outside",
    }
    for name, hint in hints.items():
        if name in text or f"({-getattr(signal, name, 0)})" in text:
            return f"a worker process died ({name}: {hint})"
    codes = text.split("exit codes of the workers are", 1)
    if len(codes) == 2:
        return f"a worker process died (exit codes {codes[1].strip().rstrip('.')})"
    return f"a worker process died ({type(exc).__name__}: {text.splitlines()[0] if text else ''})"


def _outcome(future: Future[Any]) -> tuple[bool, Any]:
    try:
        return future.result()
    except BrokenProcessPool as exc:
        return False, _cause(exc)
    except Exception as exc:  # fn raised in the worker
        return False, describe_error(exc)


def on_executor(
    pool: Executor,
    fn: Callable[..., Any],
    points: Points,
    n_chunks: int,
    bar: Any,
    cancel: bool = True,
    first: int = 0,
) -> list[tuple[bool, Any]]:
    """Each chunk from `first` on: its own rows go to a worker (a product grid sends only its
    axes); on any interruption the chunks not yet started are cancelled (with `cancel`; a
    pool that is shut down drops them itself) before it propagates."""
    chunks = range(first, n_chunks)
    if points.kind == "product" and points.nbytes < 1 << 20:
        futures = [pool.submit(run_chunk, fn, points, i, n_chunks) for i in chunks]
    else:
        futures = [pool.submit(run_chunk, fn, points.rows(i, n_chunks), 0, 1)
                   for i in chunks]  # fmt: skip
    for f in futures:
        f.add_done_callback(lambda _: bar.update())
    try:
        return [_outcome(f) for f in futures]
    except BaseException:  # Ctrl-C: nothing queued starts any more
        for f in futures if cancel else ():
            f.cancel()
        raise


def on_local_pool(
    fn: Callable[..., Any],
    points: Points,
    n_chunks: int,
    workers: int,
    bar: Any,
    first: int = 0,
) -> list[tuple[bool, Any]]:
    """The chunks from `first` on, on a new loky pool of `workers` processes, shut down
    afterwards: waiting for the workers on success, killing them on Ctrl-C or any other
    interruption."""
    from loky import ProcessPoolExecutor
    from loky.backend.context import get_context

    pool = ProcessPoolExecutor(max_workers=workers, context=get_context("loky"))
    try:
        outcomes = on_executor(pool, fn, points, n_chunks, bar, cancel=False, first=first)
    except BaseException:
        pool.shutdown(wait=False, kill_workers=True)
        raise
    pool.shutdown(wait=True)
    return outcomes
