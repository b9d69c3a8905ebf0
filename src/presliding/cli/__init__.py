"""The ``presliding`` command line: the top layer.

Files
-----
commands.py     the argument parser and `main` (also ``python -m presliding``)
common.py       user errors, input and output paths, CSV tables, figures
_parsers.py     the options of ``demo``, ``simulate``, ``analyze``, ``sweep``, ``precompile``
command_line.py the command line that reruns a run as given (a model's "identified by")
report.py       Markdown and HTML reports
example_data.py ``presliding example-data``: small records to try the commands on
precompile.py   `presliding precompile`: every compiled route into numba's cache, no files
example_files/  the records ``presliding example-data`` writes (shipped with the package)

Rooms (each command in the room of what it does; each room's ``__init__`` is its map):

demo/           ``presliding demo``: the built-in main job, its parts, figures and report
inputs/         reading records: column roles, files, --segments, virgin runs
fitting/        ``fit``, ``predict``, ``ring-down``: models fitted to measured records
simulation/     ``simulate``, ``analyze``, ``loop``, ``network``: a model file run
sweeping/       ``sweep``: a quantity of the free motion over a grid of parameters

The top holds the shared ground of the commands (the parser, errors, paths, reports) and
the commands that need no room. A room may import `inputs` and the shared modules at the
top, never another command's room; the top's `commands`, `_parsers` and `precompile` import
the rooms to dispatch, to read a schema and to run the demo.

May import every layer below it.
"""

from presliding.cli.commands import main
from presliding.cli.common import UserError

__all__ = ["UserError", "main"]
