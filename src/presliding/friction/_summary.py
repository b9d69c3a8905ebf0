"""What a `PIFriction` shows in a notebook: its levels and stiffness (eqs. 7, 9), either form.

`figures` gives the rows of `PIFriction._repr_html_` (`presliding._display.model_html`),
for finite elements or a density, symmetric or not. It reads the model's properties only,
so that `pi_friction` imports it without a cycle.
"""

from __future__ import annotations

from typing import Any

__all__ = ["figures"]


def figures(model: Any) -> list[tuple[str, str, str]]:
    """(name, value, unit) of the levels and stiffness of `model` (eqs. 7, 9), in either form."""
    n = model.n_elements if model.is_discrete else 0
    form = (f"{n} element{'' if n == 1 else 's'}" if model.is_discrete
            else type(model.density).__name__ + " density")  # fmt: skip
    rows = [("form", form, "")]
    if model.is_symmetric:
        rows += [("Coulomb level F_c (eq. 9)", f"{model.coulomb_level:.6g}", "N"),
                 ("largest elastic force F_m", f"{model.max_elastic_force:.6g}", "N")]  # fmt: skip
    else:
        up, down = model.coulomb_levels
        rows.append(("Coulomb levels F_c⁺, F_c⁻ (eq. 9)", f"{up:.6g}, {down:.6g}", "N"))
    rows.append(("stiffness after a reversal Σk (eq. 7)", f"{model.initial_stiffness:.6g}", "N/m"))
    return rows
