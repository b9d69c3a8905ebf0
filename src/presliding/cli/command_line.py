"""The command line that reruns a run as it was given (a model file's "identified by" line).

`rerun_line` walks the options of the command's parser and writes back every
option the user set (its value differs from the default), quoted for a POSIX
shell, with input files by name (rerun from the folder that holds them). The
output folder, ``--overwrite``, ``--quiet`` and ``--debug`` are left out: they
change where the results go, not what they are. It is taken when the command
starts, before anything is read, so it is the command as given.
"""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path
from typing import Any

__all__ = ["rerun_line"]

#: Options that do not change the results.
_LEFT_OUT = {"help", "output", "overwrite", "quiet", "debug", "version"}


def _word(value: Any) -> str:
    text = Path(value).name if isinstance(value, Path) else str(value)
    return shlex.quote(text)


def rerun_line(args: argparse.Namespace, parser: argparse.ArgumentParser, command: str) -> str:
    """``presliding COMMAND ...``: every option of `args` that differs from `parser`'s default."""
    parts = ["presliding", command]
    options: list[str] = []
    for action in parser._actions:
        dest = action.dest
        if dest in _LEFT_OUT or dest == argparse.SUPPRESS or not hasattr(args, dest):
            continue
        value = getattr(args, dest)
        if not action.option_strings:  # positional: the input files
            items = value if isinstance(value, (list, tuple)) else [value]
            parts += [_word(v) for v in items if v is not None]
            continue
        if value is None or value == action.default or value in ((), []):
            continue
        flag = max(action.option_strings, key=len)
        if isinstance(action, argparse.BooleanOptionalAction):
            options.append(action.option_strings[0] if value else action.option_strings[1])
        elif action.nargs == 0:  # store_true
            options.append(flag)
        elif isinstance(action, argparse._AppendAction):  # --join: one group per use
            for group in value:
                options += [flag, *[_word(v) for v in group]]
        elif isinstance(value, (list, tuple)):
            options += [flag, *[_word(v) for v in value]]
        else:
            options += [flag, _word(value)]
    return " ".join(parts + options)
