"""Column roles: which column of a file each signal is taken from, and why the others are not.

A file's columns are matched to the signals a kind of fit needs (`NEEDS`) or
uses when present (`OPTIONAL`), in this order:

1. ``--columns SIGNAL=COLUMN``: the user's word (a signal the kind does not use
   is refused, never ignored);
2. the model file's ``[data] columns`` (``presliding predict``: new records
   are read as the fitted ones were), where the file has that column;
3. a column named as the signal (`ALIASES`: ``Position [mm]`` is position);
4. a column whose unit or name says what it is: a force or torque unit (N,
   N m, lbf) or a name such as ``force``, ``torque``, ``tau``, ``u`` is taken
   for the force the kind uses (the applied force of a motion, the friction
   force of a loop) when it is the only such column and its name does not say
   it is the other force (``friction``, ``applied``) or a normal load; a length
   or angle unit likewise for the position, a speed for the velocity.

Every column that is not taken is reported with the reason (`ColumnRoles`):
the report, the printed output and the fit result's notes say which column
each signal came from and why a candidate was not used; two candidates for
one force are an error asking for ``--columns``.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from presliding.cli.common import UserError, column_key

__all__ = [
    "ALIASES",
    "NEEDS",
    "OPTIONAL",
    "SIGNALS",
    "ColumnRoles",
    "assign_columns",
    "kind_signals",
    "locate",
]

SIGNALS = ("time", "position", "velocity", "acceleration", "applied_force", "friction_force")
#: Column names tried for each signal (after `column_key` normalisation).
ALIASES = {
    "time": ("time", "t"),
    "position": ("position", "displacement", "y", "x"),
    "velocity": ("velocity", "v", "speed"),
    "acceleration": ("acceleration", "a"),
    "applied_force": ("applied_force", "u", "force_applied", "input"),
    "friction_force": ("friction_force", "friction", "force", "f"),
}
#: Signals each kind needs (one of a tuple), and those it uses when present.
NEEDS = {
    "predict": (("time",), ("velocity", "position")),  # presliding predict: a motion
    "presliding": (("position",), ("friction_force",)),
    "motion": (("time",), ("position",), ("applied_force",)),
    "response": (("time",), ("velocity", "position")),
    "quasi-static": (("position",), ("applied_force",)),
    "virgin": (("position",), ("friction_force", "applied_force")),
    "ring-down": (("time",), ("position", "velocity", "acceleration")),  # `presliding ring-down`
}
OPTIONAL = {
    "predict": ("applied_force",),
    "presliding": ("time",),
    "motion": ("velocity", "acceleration"),
    "response": ("applied_force",),
    "quasi-static": ("time",),
    "virgin": ("time",),
    "ring-down": (),
}
#: What each force signal is, in the words of a reason.
_FORCE_WORDS = {"applied_force": "the applied force u (eq. 17)",
                "friction_force": "the friction force F"}  # fmt: skip
# names that say which force a column is, or that it is a force at all
_APPLIED = re.compile(r"appl|input|drive|motor|actuat|command|excit|^u(_|$)|^tau")
_FRICTION = re.compile(r"friction|tangential|^f_?f$|^ff")
_NORMAL = re.compile(r"normal|^f_?n$|^fn|clamp|preload|bolt")
_FORCEISH = re.compile(r"force|torque|^tau|^u(_|$)|^f(_|$)|load|moment|thrust|friction")
#: The quantity a unit says (by its dimension), for the roles by unit.
_BY_UNIT = {"position": "position", "velocity": "velocity", "force": "applied_force"}


def who(kind: str) -> str:
    """The command that reads the signals of `kind`, in messages."""
    return "presliding predict" if kind == "predict" else f"--kind {kind}"


def kind_signals(kind: str) -> tuple[str, ...]:
    """Every signal `kind` reads: those it needs, then those it uses when present."""
    out = [s for group in NEEDS[kind] for s in group] + list(OPTIONAL[kind])
    return tuple(dict.fromkeys(out))


def locate(signal: str, columns: dict[str, str], names: Sequence[str] | None) -> str | int | None:
    """The column (name or index) of `signal`: from `columns` (--columns), else by alias;
    None if absent."""
    if signal in columns:
        spec = columns[signal]
        if names is not None and spec in names:
            return spec
        return int(spec) if spec.lstrip("-").isdigit() else spec
    if names is None:
        return None
    keys = [column_key(n) for n in names]
    for alias in ALIASES[signal]:
        for name, key in zip(names, keys, strict=True):
            if alias in (name, key):
                return name
    return None


def _quantity(name: str) -> str | None:
    """ "position", "velocity" or "force" when the header's unit says so (None otherwise)."""
    from presliding.measurement._units import parse_header, si_factor

    unit = parse_header(name)[1]
    if unit is None:
        return None
    for quantity, signal in (("position", "position"), ("velocity", "velocity"),
                             ("force", "friction_force")):  # fmt: skip
        try:
            si_factor(signal, unit, name)
        except ValueError:
            continue
        return quantity
    return None


def _force_kind(name: str) -> str | None:
    """What a column's name says about the force it holds: "applied_force",
    "friction_force", "normal", "force" (a force, which one not said) or None."""
    key = column_key(name)
    if _NORMAL.search(key):
        return "normal"
    if _FRICTION.search(key):
        return "friction_force"
    if _APPLIED.search(key):
        return "applied_force"
    if _FORCEISH.search(key) or _quantity(name) == "force":
        return "force"
    return None


@dataclass(frozen=True)
class ColumnRoles:
    """The columns taken for each signal and why, and why the others were not.

    Attributes
    ----------
    taken : dict signal -> (column, reason)
    unused : dict column -> reason
    missing : dict signal -> reason
        Signals the kind would use that no column holds (with what was looked for).
    """

    taken: dict[str, tuple[Any, str]] = field(default_factory=dict)
    unused: dict[str, str] = field(default_factory=dict)
    missing: dict[str, str] = field(default_factory=dict)

    def columns(self) -> dict[str, Any]:
        """The column of each signal taken (for `Measurement.from_csv` and ``[data]``)."""
        return {signal: col for signal, (col, _) in self.taken.items()}

    def notes(self) -> tuple[str, ...]:
        """One line on the columns taken, one per column not used, one per signal missing."""
        lines = []
        groups: dict[str, list[str]] = {}  # signals taken for one reason, said together
        for s, (c, why) in self.taken.items():
            groups.setdefault(why, []).append(f"{s} = {c if isinstance(c, int) else repr(c)}")
        if groups:
            lines.append("columns: " + "; ".join(f"{', '.join(items)} ({why})"
                                                 for why, items in groups.items()))  # fmt: skip
        lines += [f"column {c!r} not used: {why}" for c, why in self.unused.items()]
        lines += [f"no {s.replace('_', ' ')}: {why}" for s, why in self.missing.items()]
        return tuple(lines)


def assign_columns(
    kind: str, names: Sequence[str] | None, given: dict[str, str],
    mapping: dict[str, Any] | None = None, where: str = "",
) -> ColumnRoles:  # fmt: skip
    """The `ColumnRoles` of a file with columns `names` (None: no header) for `kind`.

    `given` holds --columns, `mapping` a model file's ``[data] columns``; `where`
    (the file) prefixes errors. See the module notes for the order of the rules.
    """
    signals = kind_signals(kind)
    for signal, spec in given.items():
        if signal not in signals:
            raise UserError(
                f"--columns {signal}={spec}: {who(kind)} does not use `{signal}` (it reads "
                f"{', '.join(signals)}); drop it"
                + ("." if kind == "predict" else ", or choose the kind that uses it.")
            )
    taken: dict[str, tuple[Any, str]] = {}
    missing: dict[str, str] = {}
    for signal in signals:
        if signal in given:
            taken[signal] = (locate(signal, given, names), "--columns")
    for signal, col in (mapping or {}).items():
        if signal not in signals or signal in taken:
            continue
        if (names is None and isinstance(col, int)) or (names is not None and col in names):
            taken[signal] = (col, "as the model file's [data] table states")
        else:
            lacks = where or "the file"
            missing[signal] = f"the model file reads it from {col!r}, which {lacks} lacks"
    used = {col for col, _ in taken.values()}
    for signal in signals:
        if signal in taken or names is None:
            continue
        col = locate(signal, {}, [n for n in names if n not in used])
        if col is not None:
            taken[signal] = (col, "by its name")
            used.add(col)
    if names is not None:
        _by_unit_and_name(kind, names, taken, used, where)
    for signal, why in missing.items():  # found otherwise: say the model file's is absent
        if signal in taken:
            col, how = taken[signal]
            taken[signal] = (col, f"{how}; {why}")
    unused = {n: _why_not(kind, n, taken) for n in names or () if n not in used}
    return ColumnRoles(taken, unused, {s: w for s, w in missing.items() if s not in taken})


def _force_roles(kind: str) -> tuple[str, ...]:
    return tuple(s for s in kind_signals(kind) if s.endswith("_force"))


def _by_unit_and_name(kind: str, names: Sequence[str], taken: dict, used: set, where: str) -> None:
    """Rule 4: the kind's force (and position, velocity) from a column's unit or name."""
    free = [n for n in names if n not in used]
    roles = _force_roles(kind)
    if roles and not any(r in taken for r in roles):
        for role in roles:
            fits = [n for n in free if _force_kind(n) in ("force", role)]
            if len(fits) > 1:
                raise UserError(
                    f"{where}: the columns {', '.join(repr(n) for n in fits)} all hold a force "
                    f"and {who(kind)} takes one as {role}; name it with --columns "
                    f"{role}=COLUMN."
                )
            if fits:
                how = "unit" if _quantity(fits[0]) == "force" else "name"
                taken[role] = (fits[0], f"its {how} says force, and no other column does: "
                               f"{who(kind)} takes it as {_FORCE_WORDS[role]}")  # fmt: skip
                used.add(fits[0])
                break
    for signal in ("position", "velocity"):
        if signal not in kind_signals(kind) or signal in taken:
            continue
        fits = [n for n in names if n not in used and _quantity(n) == signal]
        if len(fits) == 1:
            taken[signal] = (fits[0], f"its unit says {signal}, the only such column")
            used.add(fits[0])


def _why_not(kind: str, name: str, taken: dict[str, tuple[Any, str]]) -> str:
    """Why column `name` was not taken for any signal of `kind`."""
    force = _force_kind(name)
    signals = kind_signals(kind)
    if force == "normal":
        return f"a normal load, which {who(kind)} does not use"
    if force is not None:
        roles = _force_roles(kind)
        if not roles:
            return f"a force, which {who(kind)} does not use"
        if force in ("applied_force", "friction_force") and force not in roles:
            return (f"its name says {force.replace('_', ' ')}, which {who(kind)} does not use "
                    f"(it takes {' or '.join(roles)}); name it with --columns "
                    f"{roles[0]}='{name}' if it is that")  # fmt: skip
        held = [f"{r} is {taken[r][0]!r}" for r in roles if r in taken]
        if held:
            return f"a force, but {'; '.join(held)} (--columns chooses another)"
    for signal in SIGNALS:
        if locate(signal, {}, [name]) is not None:
            if signal in taken:
                return f"named {signal} too, but {signal} is {taken[signal][0]!r}"
            if signal not in signals:
                return f"{signal}, which {who(kind)} does not use"
    return f"its name says no signal {who(kind)} reads (--columns SIGNAL=COLUMN names one)"
