"""Constants and figure helpers shared by the parts of ``presliding demo``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from presliding.friction.pi_friction import PIFriction

#: The paper's Figure 3 model: c = [1, 1, 1], k2,3 = [10, 4], k1 in {500, 50, 5}.
FIGURE3_FIRST_STIFFNESS = (500.0, 50.0, 5.0)
#: Pixels per inch of the demo figures (sizes are exact: figsize × DPI).
DPI = 110
#: The free-stop model: F_c = 1 N, c1 = 0.3 N, four elements with equal break-away
#: forces (F_c − c1)/4 as in the paper's fits, mass 1 kg.
STOP_COULOMB, STOP_LEVEL, STOP_MASS = 0.3, 1.0, 1.0
STOP_STIFFNESS = (2.0e4, 5.0e3, 1.5e3, 500.0)
STOP_SPEED = 0.06  # m/s at the start of the free response


def figure3_models() -> list[PIFriction]:
    """The three models of the paper's Figure 3 (c1 = 0, eq. 4)."""
    return [
        PIFriction(coulomb=0.0, stiffness=[k1, 10.0, 4.0], breakaway=[1.0, 1.0, 1.0])
        for k1 in FIGURE3_FIRST_STIFFNESS
    ]


def stop_model(coulomb: float = STOP_COULOMB) -> PIFriction:
    """Four elements with equal break-away forces (F_c − c1)/4, F_c = STOP_LEVEL."""
    c = (STOP_LEVEL - STOP_COULOMB) / len(STOP_STIFFNESS)
    return PIFriction(coulomb, list(STOP_STIFFNESS), [c] * len(STOP_STIFFNESS))


def _figure(ncols: int, size: tuple[float, float]) -> tuple[Any, Any]:
    from presliding.cli.common import new_figure

    fig, axes = new_figure(ncols, 1, size=size)
    return fig, axes[0]


def _save(fig: Any, path: Path) -> Path:
    from presliding.plotting import save_figure

    save_figure(fig, path, dpi=DPI, tight=False)
    return path


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")
