"""Other packages at the boundary: optional dependencies and pint Quantities.

`require` imports an optional module or raises ``ImportError`` whose message says
what needed it and the extra that installs it (``pip install "presliding[dask]"``): the
one wording of a missing extra. `show_versions` prints what is installed.
`missing_extra` turns any ImportError (also a bare ``No module named 'pandas'``
from deeper code) into that one sentence, for the command line's one-line errors.
`si_magnitude` converts a pint Quantity to SI after checking its dimension (pint is not
imported for the test), of the kind `QUANTITY_KINDS` gives the argument by its name;
`presliding._validation` calls it where numbers enter, and words its errors.
"""

from __future__ import annotations

import importlib
import re
from typing import Any

__all__ = [
    "CORE",
    "EXTRA_OF",
    "OPTIONAL",
    "QUANTITY_KINDS",
    "SI_UNITS",
    "install_hint",
    "is_quantity",
    "missing_extra",
    "quantity_kind",
    "require",
    "show_versions",
    "si_magnitude",
]

#: The extra of pyproject.toml that installs each optional top-level module.
EXTRA_OF: dict[str, str] = {
    "dask": "dask",
    "distributed": "dask",
    "cloudpickle": "dask",
    "pandas": "pandas",
    "xarray": "xarray",
    "lmfit": "lmfit",
    "h5py": "h5py",
    # a core dependency; its extra is kept so that old install lines keep working
    "control": "control",
}


#: The core dependencies, by the name they are imported under.
CORE = ("numpy", "scipy", "numba", "matplotlib", "tqdm", "pint", "control", "filelock",
        "threadpoolctl", "cloudpickle", "loky")  # fmt: skip
#: The optional packages, each installed by the extra `EXTRA_OF` names.
OPTIONAL = ("pandas", "xarray", "distributed", "lmfit", "h5py")


def _version(module: str) -> str | None:
    """The version of an installed package (None: not installed), without importing it."""
    from importlib import metadata

    dist = {"control": "control", "distributed": "distributed"}.get(module, module)
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def show_versions() -> None:
    """Print presliding's version, Python's, every dependency's (an optional one that is
    missing with the command that installs it) and where the compiled kernels are cached.

    What a bug report needs, as ``pandas.show_versions()`` gives it.
    """
    import platform

    from presliding import _numba_cache
    from presliding._version import __version__

    lines = [f"presliding {__version__}", f"Python {platform.python_version()} "
             f"({platform.system()} {platform.machine()})", "", "core:"]  # fmt: skip
    lines += [f"  {m:<14} {_version(m) or 'not installed'}" for m in CORE]
    lines += ["optional:"]
    for m in OPTIONAL:
        found = _version(m)
        lines.append(f"  {m:<14} {found or 'not installed: ' + install_hint(EXTRA_OF[m])}")
    folder = f" {_numba_cache.FOLDER}" if _numba_cache.FOLDER is not None else ""
    lines += ["", f"compiled kernels cached: {_numba_cache.LOCATION}{folder}"]
    print("\n".join(lines))


def install_hint(extra: str) -> str:
    """The install command of an extra, quoted so that every shell takes the brackets."""
    return f'pip install "presliding[{extra}]"'


def require(module: str, what: str, extra: str | None = None) -> Any:
    """Import `module`, or raise ImportError naming `what` needs it and the extra to install.

    >>> require("numpy", "this").__name__
    'numpy'
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".", 1)[0]
        name = extra or EXTRA_OF.get(top, top)
        raise ImportError(
            f"{what} needs the optional package `{top}`; install it with `{install_hint(name)}`."
        ) from exc


def missing_extra(exc: ImportError) -> str:
    """One sentence for an ImportError: the message of `require`, or which extra to install."""
    text = " ".join(str(exc).split())
    if "pip install" in text:
        return text
    top = (getattr(exc, "name", None) or "").split(".", 1)[0]
    if top in EXTRA_OF:
        return (
            f"this needs the optional package `{top}`, which is not installed; install it "
            f"with `{install_hint(EXTRA_OF[top])}`."
        )
    return text or type(exc).__name__


#: The SI units a pint Quantity of each kind is converted to (the first that fits its
#: dimension; the second is the rotary axis).
SI_UNITS: dict[str, tuple[str, ...]] = {
    "position": ("m", "rad"),
    "velocity": ("m/s", "rad/s"),
    "acceleration": ("m/s**2", "rad/s**2"),
    "force": ("N", "N*m"),
    "time": ("s",),
    "mass": ("kg", "kg*m**2"),
    "stiffness": ("N/m", "N*m/rad"),
    "damping": ("N*s/m", "N*m*s/rad"),
    "integral gain": ("N/m/s", "N*m/rad/s"),
    "density of stiffness": ("N/m**2", "N*m/rad**2"),
    "force per length": ("N/m",),
    "frequency": ("Hz",),
    "angular frequency": ("rad/s",),
    "modal amplitude": ("m*kg**0.5",),  # a mass-normalised mode's coordinate
    "compliance": ("m/N", "rad/(N*m)"),
}

#: The kind of each physical argument of the public API, by the argument's name (the name
#: the validation helpers are given): a pint Quantity passed for it is converted to SI
#: after its dimension is checked. A name whose meaning differs between functions
#: (``tolerance``) is not listed: those functions give the kind where they validate it.
QUANTITY_KINDS: dict[str, str] = {
    **dict.fromkeys(
        ("displacement", "y", "r", "position", "initial_position", "threshold",
         "threshold_negative", "thresholds", "max_threshold", "length", "slip_displacement",
         "amplitude", "amplitudes", "reference", "last_input", "play", "base", "turning",
         "contact_displacement", "deformation", "reversal_positions", "reversal_tolerance",
         "bristle", "breaks", "grid", "atol", "plastic", "initial_creep"),
        "position",
    ),
    **dict.fromkeys(
        ("velocity", "initial_velocity", "stribeck_velocity", "rest_speed", "min_speed"),
        "velocity",
    ),
    "acceleration": "acceleration",
    **dict.fromkeys(
        ("coulomb", "coulomb_negative", "breakaway", "breakaway_negative", "coulomb_level",
         "min_coulomb_level", "applied_force", "elastic_force", "force", "force_amplitude",
         "slip_force", "static", "limit", "feedforward", "friction_force", "axial_stiffness",
         "static_level", "forces"),
        "force",
    ),
    **dict.fromkeys(("stiffness", "spring", "kp"), "stiffness"),
    **dict.fromkeys(("viscous", "viscous_negative", "damping", "kd"), "damping"),
    "ki": "integral gain",
    "mass": "mass",
    **dict.fromkeys(
        ("time", "t", "t_end", "t_start", "t_eval", "dt", "step", "time_step", "settle_time",
         "filter_time", "tracking_time", "start", "end", "after", "reversal_times",
         "last_time", "lead_in", "duration", "trim", "creep_time", "lag_time"),
        "time",
    ),
    **dict.fromkeys(("height", "heights", "values"), "density of stiffness"),
    "shear_strength": "force per length",
    "compliance": "compliance",
    **dict.fromkeys(("cutoff", "sample_rate"), "frequency"),
    **dict.fromkeys(("frequencies", "frequency", "band"), "angular frequency"),
}  # fmt: skip


def quantity_kind(name: str) -> str | None:
    """The kind of the argument `name` (``"stiffness"``, or an element such as
    ``"stiffness[2]"`` or ``"displacement of record 2"``), None if it has no unit here."""
    match = re.match(r"[A-Za-z_][A-Za-z0-9_]*", name)
    return QUANTITY_KINDS.get(match.group(0)) if match else None


def is_quantity(value: Any) -> bool:
    """A pint Quantity (found by its type's module: pint is not imported for the test)."""
    return type(value).__module__.split(".", 1)[0] == "pint" and hasattr(value, "to")


#: kinds whose SI unit pint equates with another kind's: 1 Hz = 1 rad/s for pint (a radian
#: is dimensionless), which would silently lose a factor 2π
_NOT_WITH = {"angular frequency": "hertz", "frequency": "radian"}


def si_magnitude(value: Any, kind: str) -> Any | None:
    """The magnitude in SI of a pint Quantity of `kind` (the first of `SI_UNITS` its
    dimension fits), or None when it is of another dimension."""
    unit_text = str(value.units)
    if kind in _NOT_WITH and _NOT_WITH[kind] in unit_text:
        return None
    for unit in SI_UNITS[kind]:
        try:
            return value.to(unit).magnitude
        except Exception as exc:  # pint's DimensionalityError: try the next unit
            if type(exc).__name__ != "DimensionalityError":
                raise
    return None
