"""``presliding network``: a structure with friction contacts from a specification file,
simulated exactly (or by Moreau–Jean steps), with a report and figures."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import numpy as np

from presliding.cli.common import (
    UserError,
    check_folder,
    check_outputs,
    check_readable,
    new_figure,
    record_outputs,
    write_csv,
)
from presliding.model_io import MAX_SAMPLES

#: The specification file, printed by ``presliding network --help``.
SCHEMA = """\
  [structure]
  kind = "chain"                   # "chain", "multi_contact", "modal" or "matrices"
  n_masses = 3                     # chain: masses in a row, each on a contact to the ground
  mass = 1.0                       # chain: m [kg] (or one per mass); multi_contact: m
  spring = 1000.0                  # chain: springs [N/m] (mass 0 tied to the ground)
  damping = 0.0                    # chain: dashpots [N s/m] parallel to the springs (optional)
  # multi_contact: mass, stiffness [N/m], damping; one mass on every contact
  # modal: frequencies [rad/s], mode_shapes [[...]] (n × n_c), damping_ratios (optional)
  # matrices: mass, stiffness, contacts [[...]] (n × n_c), damping (optional)
  [friction]                       # one model for every contact (finite elements), or
  coulomb = 0.5                    # one [[contact]] table per contact with the same keys
  stiffness = [1e4, 2e3]           # k_j [N/m]
  breakaway = [0.2, 0.3]           # c_j [N] (or threshold = [...] r_j [m])
  viscous = 0.0                    # σ_v [N s/m] (optional)
  [forcing]                        # optional
  values = [0.0, 0.0, 3.0]         # f [N] on each coordinate, constant; or with times,
  # times = [0.0, 0.5]             # one row per time: values = [[0, 0, 3], [0, 0, 0]],
                                   # f = values[i] on [times[i], times[i+1])
  [motion]
  t_end = 1.0                      # [s]
  initial_position = [0, 0, 0]     # [m] (optional)
  initial_velocity = [0.2, 0, 0]   # [m/s] (optional)
  samples = 1001                   # (optional, 2 to 10,000,000)
  method = "exact"                 # or "moreau" (time stepping; needs step)
  # step = 1e-4                    # method = "moreau": its step [s]
  # chain only: sparse = true in [structure] keeps the matrices sparse (long chains,
  # method = "moreau")
"""

OUTPUTS = ("network.csv", "hysteresis.png", "timeline.png", "energy.png", "report.md",
           "report.html")  # fmt: skip
_KEYS = {
    "structure": {"kind", "n_masses", "mass", "spring", "damping", "stiffness", "contacts",
                  "frequencies", "mode_shapes", "damping_ratios", "sparse"},
    "forcing": {"values", "times"},
    "motion": {"t_end", "initial_position", "initial_velocity", "samples", "method", "step"},
}  # fmt: skip


def _friction(path: Path, table: Any, where: str) -> Any:
    from presliding.model_io import model_from_tables

    if not isinstance(table, dict):
        raise UserError(f"{path}: `{where}` must be a table (coulomb, stiffness, ...).")
    try:
        model = model_from_tables(path, {"friction": table}).model
    except ValueError as exc:
        raise UserError(str(exc).replace("`friction", f"`{where}")) from None
    return model


def _table(path: Path, data: dict, name: str, required: bool) -> dict:
    table = data.get(name, {} if not required else None)
    if not isinstance(table, dict):
        raise UserError(f"{path}: missing table `{name}`; see `presliding network --help`.")
    bad = sorted(set(table) - _KEYS[name])
    if bad:
        raise UserError(f"{path}: unknown key `{name}.{bad[0]}`; allowed: "
                        f"{', '.join(sorted(_KEYS[name]))}.")  # fmt: skip
    return table


def load_spec(path: Path) -> dict[str, Any]:
    """The structure and run settings of a specification; a `UserError` names the field."""
    from presliding.model_io import read_tables
    from presliding.network import (
        NetworkStructure,
        chain_structure,
        modal_structure,
        multi_contact_structure,
    )

    check_readable(path, "network specification")
    data = read_tables(path)
    unknown = sorted(set(data) - {"friction", "contact", *_KEYS})
    if unknown:
        raise UserError(f"{path}: unknown table `{unknown[0]}`; allowed: structure, friction, "
                        "contact, forcing, motion.")  # fmt: skip
    st, fo, mo = (_table(path, data, n, n != "forcing") for n in ("structure", "forcing",
                                                                  "motion"))  # fmt: skip
    if ("friction" in data) == ("contact" in data):
        raise UserError(f"{path}: give either a `friction` table (one model for every contact) "
                        "or one `[[contact]]` table per contact.")  # fmt: skip
    if "friction" in data:
        models: Any = _friction(path, data["friction"], "friction")
    else:
        if not isinstance(data["contact"], list):
            raise UserError(f"{path}: `contact` must be an array of tables ([[contact]]).")
        models = [_friction(path, t, f"contact[{i}]") for i, t in enumerate(data["contact"])]
    forcing: Any = None
    if "values" in fo:
        forcing = (fo["times"], fo["values"]) if "times" in fo else fo["values"]
    elif "times" in fo:
        raise UserError(f"{path}: `forcing.times` needs `forcing.values` (one row per time).")
    kind = st.get("kind", "chain")
    if "sparse" in st and kind != "chain":
        raise UserError(f"{path}: `structure.sparse` is for kind = 'chain'; got kind = {kind!r}.")

    def need(key: str) -> Any:
        if key not in st:
            raise UserError(f"{path}: missing `structure.{key}` for kind = {kind!r}.")
        return st[key]

    try:
        if kind == "chain":
            n = st.get("n_masses", len(models) if isinstance(models, list) else None)
            if n is None:
                n = need("n_masses")
            structure = chain_structure(
                n, st.get("mass", 1.0), st.get("spring", 0.0), models,
                damping=st.get("damping", 0.0), sparse=st.get("sparse", False),
            )  # fmt: skip
        elif kind == "multi_contact":
            ms = models if isinstance(models, list) else [models]
            structure = multi_contact_structure(
                st.get("mass", 1.0), st.get("stiffness", 0.0), ms,
                damping=st.get("damping", 0.0),
            )  # fmt: skip
        elif kind == "modal":
            structure = modal_structure(need("frequencies"), need("mode_shapes"), models,
                                        damping_ratios=st.get("damping_ratios", 0.0))  # fmt: skip
        elif kind == "matrices":
            w = np.asarray(need("contacts"), dtype=float)
            ms = models if isinstance(models, list) else [models] * (w.shape[1] if w.ndim == 2
                                                                      else 1)  # fmt: skip
            structure = NetworkStructure(need("mass"), need("stiffness"), w, ms,
                                         damping=st.get("damping"))  # fmt: skip
        else:
            raise UserError(f"{path}: `structure.kind` must be 'chain', 'multi_contact', "
                            f"'modal' or 'matrices'; got {kind!r}.")  # fmt: skip
    except (TypeError, ValueError) as exc:
        if isinstance(exc, UserError):
            raise
        text = str(exc).replace("Pass sparse=True", "Set sparse = true in [structure] (with "
                                "method = 'moreau')")  # fmt: skip
        raise UserError(f"{path}: [structure] {text}") from None
    if forcing is not None:
        try:
            structure = structure.with_forcing(forcing)
        except (TypeError, ValueError) as exc:
            raise UserError(f"{path}: [forcing] {exc}") from None
    t_end = mo.get("t_end")
    if isinstance(t_end, bool) or not isinstance(t_end, (int, float)) or not math.isfinite(t_end):
        raise UserError(f"{path}: `motion.t_end` must be a finite number; got {t_end!r}.")
    method = mo.get("method", "exact")
    if method not in ("exact", "moreau"):
        raise UserError(f"{path}: `motion.method` must be 'exact' or 'moreau'; got {method!r}.")
    if method == "moreau" and "step" not in mo:
        raise UserError(f"{path}: `motion.step` is needed with method = 'moreau'.")
    if method == "exact" and "step" in mo:
        raise UserError(f"{path}: `motion.step` is the step of method = 'moreau'; the exact "
                        "method has none: remove it, or set method = 'moreau'.")  # fmt: skip
    samples = mo.get("samples", 1001)
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
        raise UserError(f"{path}: `motion.samples` must be a whole number >= 2; got {samples!r}.")
    if samples > MAX_SAMPLES:
        raise UserError(f"{path}: `motion.samples` must be at most {MAX_SAMPLES:,}; got "
                        f"{samples:,}.")  # fmt: skip
    return {"structure": structure, "t_end": float(t_end), "method": method,
            "q0": mo.get("initial_position"), "v0": mo.get("initial_velocity"),
            "samples": samples, "step": mo.get("step")}  # fmt: skip


def add_parser(sub: Any, parents: list) -> argparse.ArgumentParser:
    """The ``network`` sub-parser (its handler is set by `presliding.cli.commands`)."""
    net = sub.add_parser(
        "network",
        help="a structure with many friction contacts: exact stick/slip per contact",
        description="Simulate masses, springs and dampers with friction contacts (each a "
        "PIFriction, eq. 8): exactly, with events in closed form and the stick/slip of all "
        "contacts decided together, or by Moreau–Jean time steps. Writes network.csv (the "
        "samples, units in the header), hysteresis.png (force against displacement per "
        "contact), timeline.png (stick/slip per contact), energy.png and report.md/.html.",
        epilog="example:\n  presliding network spec.toml -o net/\n\n"
        "specification file (TOML, or JSON with the same tables; units in brackets):\n" + SCHEMA,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        parents=parents,
    )
    net.add_argument("spec", type=Path, help="network specification (.toml, or .json)")
    net.add_argument("-o", "--output", type=Path, default=Path("presliding-network"),
                     help="output folder (default: ./presliding-network)")  # fmt: skip
    return net


def run(args: argparse.Namespace) -> int:
    """Load, simulate, write the CSV, figures and report."""
    from presliding.network import simulate_network, simulate_network_moreau

    spec = load_spec(args.spec)
    out = check_folder(args.output)
    paths = [out / name for name in OUTPUTS]
    check_outputs(paths, (args.spec,), overwrite=args.overwrite)
    s = spec["structure"]
    try:
        if spec["method"] == "exact":
            t_eval = np.linspace(0.0, spec["t_end"], spec["samples"])
            res = simulate_network(s, spec["t_end"], spec["q0"], spec["v0"], t_eval=t_eval)
        else:
            res = simulate_network_moreau(s, spec["t_end"], spec["step"], spec["q0"], spec["v0"],
                                          samples=spec["samples"])  # fmt: skip
    except (TypeError, ValueError) as exc:
        raise UserError(f"{args.spec}: cannot simulate the network: {exc}") from None
    record_outputs(paths)
    n, n_c = s.n_coordinates, s.n_contacts
    header = ["time [s]"] + [f"q{i} [m]" for i in range(n)] + [f"v{i} [m/s]" for i in range(n)]
    header += [f"g{c} [m]" for c in range(n_c)] + [f"force{c} [N]" for c in range(n_c)]
    header += [f"mode{c}" for c in range(n_c)]
    cols = [res.time, *res.position.T, *res.velocity.T, *res.contact_displacement.T,
            *res.contact_force.T, *res.contact_mode.T]  # fmt: skip
    write_csv(paths[0], header, cols, quiet=args.quiet)
    _figures(res, paths[1:4])
    _report(out, res, paths[1:4], args.spec)
    if not args.quiet:
        print(res.report())
        for p in paths:
            print(f"wrote {p}")
    return 0 if res.success else 1


def _figures(res: Any, pngs: list[Path]) -> None:
    from presliding.plotting import save_figure

    for kind, png in zip(("hysteresis", "timeline", "energy"), pngs, strict=True):
        fig, axes = new_figure(1, 1, size=(7.0, 4.4))
        res.plot(ax=axes[0, 0], kind=kind)
        save_figure(fig, png)


def _report(out: Path, res: Any, pngs: list[Path], spec: Path) -> None:
    from presliding.cli.report import Section, write_report

    rows = [("contact", "reversals", "stop time [s]", "Coulomb [J]", "hysteretic [J]",
             "viscous [J]")]  # fmt: skip
    for c in range(res.contact_force.shape[1]):
        stop = res.stop_times[c]
        rows.append((str(c), str(res.n_reversals[c]), "moving" if np.isnan(stop) else f"{stop:.6g}",
                     f"{res.energy.coulomb[-1, c]:.4g}", f"{res.energy.hysteretic[-1, c]:.4g}",
                     f"{res.energy.viscous[-1, c]:.4g}"))  # fmt: skip
    sections = [
        Section("Motion", "Each contact sticks (its velocity exactly zero) or slides; the "
                "stick/slip of the contacts at rest is decided together at every event.",
                (pngs[0], pngs[1]), code=res.report(), table=rows),
        Section("Energy", "Stored (kinetic, springs, elements), dissipated per kind and the "
                "work of the applied force.", (pngs[2],)),
    ]  # fmt: skip
    write_report(out, f"presliding network: {spec.name}", sections)


__all__ = ["OUTPUTS", "SCHEMA", "add_parser", "load_spec", "run"]
