"""The ``presliding`` command line: the top layer.

Files
-----
commands.py     the argument parser and `main` (also ``python -m presliding``)
common.py       user errors, input and output paths, CSV tables, figures
demo.py, demo_sections.py, _demo_common.py   ``presliding demo``: the built-in main job
demo_hunting.py ``presliding demo``'s hunting part: predicted against simulated cycle
simulate.py     ``presliding simulate``
analyze.py      ``presliding analyze``
fit.py          ``presliding fit``: one-file kinds, the model file, column roles as notes
fit_options.py  the options of ``presliding fit``, and which kinds use each
command_line.py the command line that reruns a run as given (a model's "identified by")
inputs/         reading records: column roles, files, --segments, virgin runs
example_data.py ``presliding example-data``: small records to try the commands on
_parsers.py     the options of ``demo``, ``simulate``, ``analyze``, ``sweep``, ``precompile``
fit_pooled.py   ``presliding fit FILE ...`` for response, quasi-static and virgin fits
fit_figure.py   the figure of a fit
records.py      records from files or --join groups; --header, --decimal, --axis, --join
predict.py      ``presliding predict MODEL FILE ...`` and ``fit --hold-out``: held-out records
sweep.py, sweep_spec.py     ``presliding sweep`` and its specification files
loop.py         ``presliding loop``: a PID loop, its exact response and limit cycles
network.py      ``presliding network``: a structure with friction contacts, report, figures
ring_down.py    ``presliding ring-down FILE``: a free decay's ω(A), ζ(A) and a fitted joint
report.py       Markdown and HTML reports
precompile.py   `presliding precompile`: every compiled route into numba's cache, no files

May import every layer below it.
"""

from presliding.cli.commands import main
from presliding.cli.common import UserError

__all__ = ["UserError", "main"]
