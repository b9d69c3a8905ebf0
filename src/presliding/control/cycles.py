"""`LimitCycles`: the result of `predict_limit_cycles` (cycles, curves, plot, report)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from presliding._display import fill_attrs, result_html, short_repr, summarise
from presliding._interop import require

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

FloatArray = NDArray[np.float64]

__all__ = ["LimitCycles"]


@dataclass(frozen=True, eq=False)
class LimitCycles:
    """Limit cycles predicted by harmonic balance, G(jω)·N(A) = −1.

    Attributes
    ----------
    amplitude : ndarray, shape (n,)
        A of each cycle [m] (of the position), increasing.
    frequency : ndarray, shape (n,)
        ω of each cycle [rad/s].
    stable : ndarray of bool, shape (n,)
        Loeb's criterion: True where nearby amplitudes return to the cycle.
    amplitudes, minus_inverse_df : ndarray, shape (M,)
        The amplitude grid and −1/N(A) on it (the curve of the plot).
    frequencies, loop_response : ndarray, shape (W,)
        The frequency grid and G(jω) on it.
    status : str
        "predicted" (at least one cycle) or "none".
    message : str
    model : PIFriction
    """

    amplitude: FloatArray
    frequency: FloatArray
    stable: NDArray[np.bool_]
    amplitudes: FloatArray
    minus_inverse_df: FloatArray
    frequencies: FloatArray
    loop_response: FloatArray
    status: str
    message: str
    model: Any

    @property
    def success(self) -> bool:
        """True: the search ran (with or without cycles)."""
        return self.status in ("predicted", "none")

    @property
    def period(self) -> FloatArray:
        """2π/ω of each cycle [s]."""
        return 2.0 * np.pi / self.frequency

    @property
    def n_cycles(self) -> int:
        """Number of limit cycles predicted (stable or not)."""
        return int(self.amplitude.shape[0])

    def plot(self, ax: Axes | None = None) -> Axes:
        """Nyquist curve of G(jω) with −1/N(A); cycles marked (filled: stable)."""
        from presliding.plotting import new_axes, place_legend

        ax = new_axes(ax)
        g = self.loop_response
        z = self.minus_inverse_df
        ax.plot(g.real, g.imag, color="C0", lw=1.3, label="G(jω), ω > 0")
        ax.plot(g.real, -g.imag, color="C0", lw=0.8, ls=":", label="G(jω), ω < 0")
        ax.plot(z.real, z.imag, color="C3", lw=1.3, label="−1/N(A)")
        for a, w, st in zip(self.amplitude, self.frequency, self.stable, strict=True):
            i = int(np.argmin(np.abs(self.amplitudes - a)))
            kind = "stable" if st else "unstable"
            ax.plot(z[i].real, z[i].imag, "o", ms=8, mew=1.6, color="k",
                    mfc="k" if st else "none",
                    label=f"A = {a:.3g} m, ω = {w:.3g} rad/s ({kind})")  # fmt: skip
        ax.axhline(0.0, color="0.75", lw=0.7)
        ax.axvline(0.0, color="0.75", lw=0.7)
        pts = [complex(z[np.argmin(np.abs(self.amplitudes - a))]) for a in self.amplitude]
        if pts:
            scale = 2.5 * max(abs(p) for p in pts)
        else:
            finite = np.abs(z[np.isfinite(z)])
            scale = float(np.median(finite)) if finite.size else 1.0
        ax.set_xlim(-scale, 0.6 * scale)
        ax.set_ylim(-0.6 * scale, scale)
        ax.set_xlabel("Re G(jω), Re −1/N(A) [m/N]")
        ax.set_ylabel("Im G(jω), Im −1/N(A) [m/N]")
        ax.set_title("Nyquist curve of G and −1/N(A)")
        place_legend(ax, fontsize=7)
        return ax

    def report(self) -> str:
        """The cycles as a table."""
        lines = [f"Limit cycles by harmonic balance: {self.status} ({self.message})"]
        if self.n_cycles:
            lines.append("  amplitude [m]    frequency [rad/s]    period [s]    stable")
            for a, w, st in zip(self.amplitude, self.frequency, self.stable, strict=True):
                lines.append(f"  {a:<15.6g}  {w:<19.6g}  {2 * np.pi / w:<12.6g}  {bool(st)}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """The cycles and the curves as plain values."""
        return {
            "amplitude": self.amplitude, "frequency": self.frequency, "stable": self.stable,
            "amplitudes": self.amplitudes, "minus_inverse_df": self.minus_inverse_df,
            "frequencies": self.frequencies, "loop_response": self.loop_response,
            "status": self.status, "success": self.success, "message": self.message,
        }  # fmt: skip

    def to_pandas(self) -> Any:
        """One row per cycle."""
        pd = require("pandas", "`to_pandas()`")

        frame = pd.DataFrame({"amplitude": self.amplitude, "frequency": self.frequency,
                              "period": self.period, "stable": self.stable})  # fmt: skip
        return fill_attrs(frame, self)

    def __repr__(self) -> str:
        return short_repr(self, ("amplitude", "frequency", "stable", "amplitudes", "frequencies",
                                 "model"))  # fmt: skip

    def _repr_html_(self) -> str:
        """The status and the cycles (amplitude, frequency, period, stability), for notebooks."""
        figures = [("cycles", str(self.n_cycles), ""),
                   ("amplitude grid", summarise(self.amplitudes), "m"),
                   ("frequency grid", summarise(self.frequencies), "rad/s")]  # fmt: skip
        rows = [
            (f"{a:.6g}", f"{w:.6g}", f"{2 * np.pi / w:.6g}", "stable" if st else "unstable")
            for a, w, st in zip(self.amplitude, self.frequency, self.stable, strict=True)
        ]
        cols = ("amplitude [m]", "frequency [rad/s]", "period [s]", "Loeb")
        return result_html(self, figures, (cols, rows) if rows else None)
