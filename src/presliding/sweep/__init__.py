"""Parameter sweeps: a quantity over a grid, in local processes or on Dask.

Files
-----
runner.py    `sweep`: chunks of the grid on workers, then one `SweepResult`
result.py    `SweepResult`: values, status, plot, report, pandas and xarray
_grid.py     the points as product axes or table columns; chunks as index ranges
_dask.py     Dask: scatter once, tasks of index ranges, retries, cluster size
_local.py    local processes (loky): the function by value, dead workers named, Ctrl-C
_tasks.py    the per-chunk work of ``presliding sweep`` (reversal counts, rest positions, …)

May import: `presliding.identification` and everything below it, and the root's
shared modules. Dask, pandas and xarray are imported only when used (the
``dask``, ``pandas`` and ``xarray`` extras).
"""

from presliding.sweep.result import SweepResult
from presliding.sweep.runner import check_address, sweep

__all__ = ["SweepResult", "check_address", "sweep"]
