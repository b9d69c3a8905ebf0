"""What a fit shows while it runs: stages, solver evaluations, search generations.

Every ``fit_*`` function takes ``progress=``: False (the default: nothing, no
cost), True (its own `presliding._progress.Progress` on stderr: a tqdm bar when
stderr is a terminal, tqdm's notebook bar in Jupyter, nothing otherwise, so logs and
pipes stay clean), or a
`Progress` that the caller owns and configured (the command line's, shared with
reading the data and writing the outputs).
`reporting` turns that argument into a `FitProgress`, which the fit and its
solver call:

- `stage` names a step (the linear start, a start of a multistart, a check,
  a bootstrap resample, a left-out record): always shown;
- `counting` wraps a residual function: each call counts one evaluation, and
  the count with the current cost ‖r‖² is shown at most once per `interval`
  seconds (plain lines: every two seconds; a bar: five times a second);
- `generation` reports a generation of the global search, throttled the same way.

Reporting only reads what the solver computes, so a fit gives the same
result with progress on or off. Notes go through `Progress.note`, never
`update`: the command line counts its own parts (read, fit, write).
"""

from __future__ import annotations

import contextlib
import functools
import time
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

import numpy as np

from presliding._progress import Progress, progress_enabled

__all__ = ["FitProgress", "as_reporter", "reporting", "shows_progress"]

F = TypeVar("F", bound=Callable[..., Any])

#: seconds between two evaluation notes: plain lines, and a bar on a terminal
PLAIN_INTERVAL = 2.0
BAR_INTERVAL = 0.2


class FitProgress:
    """Notes of one fit on a `Progress` (or none: every method is then a no-op)."""

    def __init__(self, bar: Progress | None, *, interval: float | None = None) -> None:
        self.bar = bar
        self.active = bar is not None and not bar.quiet
        if interval is None:
            interactive = bar is not None and bar.interactive
            interval = BAR_INTERVAL if interactive else PLAIN_INTERVAL
        self.interval = float(interval)
        self.runs = 0
        self._last = -np.inf

    def stage(self, text: str) -> None:
        """A named step of the fit begins."""
        if self.active:
            self.bar.note(text)  # type: ignore[union-attr]
            self._last = time.perf_counter()

    def counting(
        self, fun: Callable[[Any], Any], what: str = "least squares"
    ) -> Callable[[Any], Any]:
        """`fun` that also counts its calls and shows the count and cost now and then."""
        if not self.active:
            return fun
        self.runs += 1
        label = what if self.runs == 1 else f"{what} (run {self.runs})"
        count = [0]

        def counted(x: Any) -> Any:
            r = fun(x)
            count[0] += 1
            if self._due():
                with np.errstate(all="ignore"):
                    cost = float(np.dot(r, r)) if np.ndim(r) == 1 else float("nan")
                n = count[0]
                self._say(f"{label}: {n} evaluation{'' if n == 1 else 's'}, cost {cost:.4g}")
            return r

        return counted

    def generation(self, done: int, total: int, best: float) -> None:
        """Generation `done` of at most `total` of a global search; `best` the lowest loss."""
        if self.active and (self._due() or done == total):
            self._say(f"global search: generation {done} of at most {total}, best loss {best:.4g}")

    def _due(self) -> bool:
        return time.perf_counter() - self._last >= self.interval

    def _say(self, text: str) -> None:
        self.bar.note(text)  # type: ignore[union-attr]
        self._last = time.perf_counter()


#: The reporter of a fit without progress.
SILENT = FitProgress(None)


@contextlib.contextmanager
def reporting(progress: Any, name: str) -> Iterator[FitProgress]:
    """The `FitProgress` of a fit's ``progress=`` argument (see the module notes).

    `name` is the fit's function name, the prefix of the plain lines of its own
    `Progress` (``progress=True``). A `FitProgress` (a fit called by another,
    as in `cross_validate` or a pruning refit) is used as it is.
    """
    if isinstance(progress, FitProgress):
        yield progress
    elif isinstance(progress, Progress):
        yield FitProgress(progress)
    elif progress is None or isinstance(progress, (bool, np.bool_)):
        if not progress:
            yield SILENT
            return
        quiet = not progress_enabled()  # a bar on a terminal or in a notebook, else silent
        with Progress(f"presliding {name}", unit="evaluation", quiet=quiet) as bar:
            yield FitProgress(bar)
    else:
        raise TypeError(
            "`progress` must be True, False or a presliding._progress.Progress; got "
            f"{type(progress).__name__}."
        )


def as_reporter(progress: Any) -> FitProgress:
    """The `FitProgress` a fit wrapped by `shows_progress` receives (silent otherwise)."""
    return progress if isinstance(progress, FitProgress) else SILENT


def shows_progress(name: str) -> Callable[[F], F]:
    """Decorate a fit: its ``progress=`` argument is opened by `reporting` around the call.

    The fit itself receives a `FitProgress` (`as_reporter`), and a `Progress`
    the fit opened itself is closed when it returns or raises.
    """

    def wrap(fit: F) -> F:
        @functools.wraps(fit)
        def run(*args: Any, progress: Any = False, **kwargs: Any) -> Any:
            with reporting(progress, name) as shown:
                return fit(*args, progress=shown, **kwargs)

        return run  # type: ignore[return-value]

    return wrap
