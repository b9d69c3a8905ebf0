"""Parameter sweeps: a quantity over a grid, in local processes or on Dask.

Files
-----
runner.py    `sweep`: chunks of the grid on workers, then one `SweepResult`
result.py    `SweepResult`: values, status, plot, report
_tasks.py    the per-chunk work of ``presliding sweep`` (reversal counts, rest positions, …)

May import: `presliding.identification` and everything below it, and the root's
shared modules. Dask is imported only when used (the ``dask`` extra).
"""

from presliding.sweep.result import SweepResult
from presliding.sweep.runner import check_address, sweep

__all__ = ["SweepResult", "check_address", "sweep"]
