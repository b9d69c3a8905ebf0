"""``presliding analyze``: key quantities and the stop analysis of a model file."""

from __future__ import annotations

import argparse
import json
from typing import Any

from presliding.cli.common import check_readable


def analyze(model: Any, mass: float, initial_velocity: float) -> dict[str, Any]:
    """The numbers `presliding analyze` prints, by name (JSON-ready).

    The reversal count is that of a free motion from a saturated start (a long
    slide before, the paper's assumption for eqs. 13–16); it depends neither on
    the mass nor on the speed, so a zero `initial_velocity` is replaced by 1.
    Eqs. 14–16 assume no viscous friction (assumption (i)): for a model with
    σ > 0 the stop analysis is left out (None) with a note to simulate it.
    """
    from presliding.analysis.stops import phi, stops_at_turning_point, turning_point, turning_points

    c1, fm = model.coulomb, model.max_elastic_force
    out: dict[str, Any] = {
        "coulomb": c1,
        "max_elastic_force": fm,
        "coulomb_level": model.coulomb_level,
        "initial_stiffness": model.initial_stiffness,
        "elements": model.n_elements if model.is_discrete else None,
        "density": None if model.is_discrete else repr(model.density),
        "viscous": model.viscous,
        "turning_point": None,
        "phi_at_turning_point": None,
        "stops_at_turning_point": None,
    }
    if model.viscous:
        out["free_motion"] = None
        out["note"] = (
            f"viscous term σ = {model.viscous:.6g} N s/m: eqs. 14-16 assume σ = 0 (the paper's "
            "assumption (i)); simulate the motion with `presliding simulate`"
        )
        return out
    out["stops_at_turning_point"] = bool(stops_at_turning_point(model))
    if c1 < fm:
        y_e = turning_point(model)
        out["turning_point"] = y_e
        out["phi_at_turning_point"] = float(phi(model, y_e))
    v0 = initial_velocity if initial_velocity != 0.0 else 1.0
    tp = turning_points(model, mass, v0, "saturated")
    note = (
        "motion.initial_velocity is 0, so the free motion starts at 1 m/s instead (the number "
        "of reversals from a saturated start depends neither on the speed nor on the mass)"
        if initial_velocity == 0.0
        else ""
    )
    out["free_motion"] = {
        "mass": mass,
        "initial_velocity": v0,
        "status": tp.status,
        "reversals": int(tp.n_reversals),
        "turning_points": [float(y) for y in tp.positions[:50]],
        "rest_position": None if tp.rest_position is None else float(tp.rest_position),
        "message": tp.message,
        "note": note,
    }
    return out


def _text(name: str, a: dict[str, Any]) -> str:
    def row(label: str, value: str, note: str = "") -> str:
        return f"  {label:<34}{value:<18}{note}".rstrip()

    lines = [f"{name}"]
    what = f"{a['elements']} elements" if a["elements"] is not None else a["density"]
    lines.append(row("model", what))
    lines.append(row("Coulomb element c1", f"{a['coulomb']:.6g} N"))
    lines.append(row("max elastic force F_m", f"{a['max_elastic_force']:.6g} N", "Σ c_j = ∫ r dμ"))
    lines.append(row("Coulomb level F_c", f"{a['coulomb_level']:.6g} N", "eq. 9"))
    lines.append(
        row("stiffness after a reversal", f"{a['initial_stiffness']:.6g} N/m", "Σ k_j, eq. 7")
    )
    if a["viscous"]:
        lines.append(row("viscous term σ", f"{a['viscous']:.6g} N s/m", "σ·ẏ"))
        lines.append(f"  {a['note']}")
        return "\n".join(lines)
    if a["turning_point"] is None:
        lines.append(row("travel back y_e (eq. 15)", "none", "c1 >= F_m: no reversal"))
        verdict = "stops at the first turning point (c1 >= F_m)"
    else:
        y_e = f"{a['turning_point']:.6g} m"
        lines.append(row("travel back y_e (eq. 15)", y_e, "from the 1st turning point to the 2nd"))
        lines.append(row("Φ(y_e)", f"{a['phi_at_turning_point']:.6g} N", "eq. 14"))
        verdict = (
            "c1 >= Φ(y_e): stops at y_e after one reversal"
            if a["stops_at_turning_point"]
            else "c1 < Φ(y_e): does not stop at y_e (more reversals)"
        )
    lines.append(row("stop test (eq. 16)", verdict))
    fm = a["free_motion"]
    lines.append(
        f"  free motion from a saturated start (m = {fm['mass']:g} kg, v0 = "
        f"{fm['initial_velocity']:g} m/s): {fm['reversals']} reversal(s), {fm['status']}"
    )
    if fm["rest_position"] is not None:
        lines.append(f"    rest position {fm['rest_position']:.6g} m")
    lines.append(f"    {fm['message']}")
    if fm["note"]:
        lines.append(f"    note: {fm['note']}")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Print the analysis of a model file (text or JSON)."""
    from presliding.model_io import load_model

    check_readable(args.model, "model file")
    spec = load_model(args.model)
    result = analyze(spec.model, spec.motion.mass, spec.motion.initial_velocity)
    if args.json:
        print(json.dumps({"model_file": str(args.model), **result}, indent=2))
    elif not args.quiet:
        print(_text(str(args.model), result))
    return 0


__all__ = ["analyze", "run"]
