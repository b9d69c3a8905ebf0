"""`modal_backbone`: amplitude-dependent natural frequency and damping of one mode, exactly.

Quasi-static modal analysis (Lacayo and Allen): load the structure along M·φ (φ a
mass-normalised linear mode with the joints stuck) by a modal force P, and take the
modal displacement a = φᵀM·q. The virgin curve P(a) is the modal backbone, and with
Masing's rules the loop between −a and +a gives

    frequency      ω(a) = √(P(a)/a)                 (secant, unit modal mass)
    dissipation    D(a) = 8∫₀ᵃ P du − 4·a·P(a)       (the loop's area)
    damping ratio  ζ(a) = D/(2π·P·a) = D/(4π·E),  E = ½·ω²a²

and what a slowly decaying free vibration of the mode shows instead (`_slow_flow`): the
loop's first-harmonic frequency ω₁(a) and the decay's ζ_d(a) = D/(2π·a²·P'(a)). The
structure's own damping C adds its modal part c = φᵀCφ to both ratios: c/(2ω) and
c/(2ω₁) (a decay rate c/2 of the unit modal mass); D is the joints' dissipation.

For joints with finite elements, P(a) is the exact operator of `compile_structure`
(a linear spring plus a PI operator: D is that operator's, `amplitude_response`); a
structure with a single joint of any density (an Iwan joint) has P(a) in closed form
(`_single_joint`). Both are exact for the model: nothing is fitted to sample points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._display import fill_attrs
from presliding._validation import as_choice, as_parameter_vector, as_si, fmt
from presliding.analysis import amplitude_response
from presliding.hysteresis._results import ResultMixin
from presliding.network import CompiledStructure, compile_structure
from presliding.structural._single_joint import single_joint_curve
from presliding.structural._slow_flow import harmonic_stiffness_elements
from presliding.structural.structure import JointedStructure, as_structure

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["ModalBackbone", "modal_backbone"]

FloatArray = NDArray[np.float64]

#: The units of a backbone's columns (modal quantities of a mass-normalised mode).
UNITS = {
    "amplitude": "m·kg^½", "modal_force": "N/kg^½", "frequency": "rad/s",
    "damping_ratio": "", "dissipation": "J", "harmonic_frequency": "rad/s",
    "decay_damping_ratio": "",
}  # fmt: skip

_PLOTS = {
    "frequency": ("frequency", "natural frequency ω [rad/s]", False),
    "damping": ("damping_ratio", "damping ratio ζ [-]", True),
    "dissipation": ("dissipation", "dissipation per cycle D [J]", True),
    "force": ("modal_force", "modal force P [N/kg^½]", True),
}


@dataclass(frozen=True, eq=False, repr=False)
class ModalBackbone(ResultMixin):
    """A mode's backbone: natural frequency, damping and dissipation against its amplitude.

    Attributes
    ----------
    amplitude : ndarray, shape (m,)
        Modal amplitudes a > 0 [m·kg^½] (the mode is mass-normalised, φᵀMφ = 1).
    modal_force : ndarray, shape (m,)
        P(a) [N/kg^½], the backbone (the virgin curve of the modal loop).
    frequency : ndarray, shape (m,)
        ω(a) = √(P/a) [rad/s].
    damping_ratio : ndarray, shape (m,)
        ζ(a) = D/(2π·P·a) + c/(2ω) [-], c = φᵀCφ the mode's viscous damping.
    dissipation : ndarray, shape (m,)
        D(a) [J], the energy the joints dissipate per cycle between −a and +a.
    harmonic_frequency : ndarray, shape (m,)
        ω₁(a) [rad/s], the first harmonic (describing function) of the Masing loop: the
        frequency a slowly decaying free vibration of the mode shows.
    decay_damping_ratio : ndarray, shape (m,)
        ζ_d(a) = D/(2π·a²·P'(a)) + c/(2ω₁) [-]: the damping a ring-down shows (energy
        balance of a slow decay; the stored energy at a turning point grows as a·P'(a)),
        with the mode's viscous part; inf where
        P' = 0 (every joint slides and nothing holds the mode: status 'macroslip').
    deflection : ndarray, shape (m, n)
        q at the peak of the cycle [m]; ``joint_amplitude`` = deflection·W.
    joint_amplitude : ndarray, shape (m, n_c)
        Each joint's displacement amplitude g_c [m].
    linear_frequency : float
        ω₀ [rad/s] of the linear mode, joints stuck (the limit a → 0).
    mode_shape : ndarray, shape (n,)
        φ, mass-normalised.
    mode : int
    operator : CompiledStructure or None
        P(u) as a linear spring plus a PI operator (joints with finite elements).
    status : str
        'success'; 'no_dissipation' (D = 0 at some amplitudes: no joint slides there; the
        values are exact all the same); 'macroslip' (P' = 0 at some amplitudes: the mode
        has no stiffness left, ζ_d is inf there).
    message : str
    """

    amplitude: FloatArray
    modal_force: FloatArray
    frequency: FloatArray
    damping_ratio: FloatArray
    dissipation: FloatArray
    harmonic_frequency: FloatArray
    decay_damping_ratio: FloatArray
    deflection: FloatArray
    joint_amplitude: FloatArray
    linear_frequency: float
    mode_shape: FloatArray
    mode: int
    operator: CompiledStructure | None = field(default=None)
    structure: JointedStructure | None = field(default=None)
    status: str = "success"
    message: str = ""
    _rows: ClassVar[str] = "amplitude"

    @property
    def success(self) -> bool:
        """True: the quantities are exact for the model."""
        return self.status in ("success", "no_dissipation", "macroslip")

    def __repr__(self) -> str:
        a = self.amplitude
        return (
            f"ModalBackbone(mode={self.mode}, n={a.shape[0]}, amplitude=[{a[0]:.4g}, "
            f"{a[-1]:.4g}] m·kg^½, ω0={self.linear_frequency:.6g} rad/s, status={self.status!r})"
        )

    def report(self) -> str:
        """A table of ω, ζ and D at (up to 12 of) the amplitudes."""
        lines = [repr(self), self.message,
                 f"{'a [m kg^1/2]':>13} {'omega [rad/s]':>14} {'omega/omega0':>12} "
                 f"{'zeta [-]':>11} {'D [J]':>11}"]  # fmt: skip
        n = self.amplitude.shape[0]
        for i in np.unique(np.linspace(0, n - 1, min(n, 12)).astype(int)):
            lines.append(
                f"{self.amplitude[i]:13.5g} {self.frequency[i]:14.7g} "
                f"{self.frequency[i] / self.linear_frequency:12.6f} "
                f"{self.damping_ratio[i]:11.4g} {self.dissipation[i]:11.4g}"
            )
        return "\n".join(lines)

    def to_pandas(self) -> Any:
        """amplitude (index), modal_force, frequency, damping_ratio, dissipation; units in
        ``attrs``."""
        import pandas as pd

        cols = {k: getattr(self, k) for k in ("modal_force", "frequency", "damping_ratio",
                                              "dissipation", "harmonic_frequency",
                                              "decay_damping_ratio")}  # fmt: skip
        frame = pd.DataFrame(cols, index=pd.Index(self.amplitude, name="amplitude"))
        return fill_attrs(frame, self, units=UNITS)

    def plot(self, ax: Axes | None = None, *, quantity: str = "frequency") -> Axes:
        """ω(a) (log amplitude axis), ζ(a), D(a) or P(a) (log-log) with units.

        Parameters
        ----------
        ax : matplotlib Axes, optional
        quantity : {'frequency', 'damping', 'dissipation', 'force'}
        """
        from presliding.plotting import new_axes, place_legend

        name, label, loglog = _PLOTS[as_choice("quantity", quantity, tuple(_PLOTS))]
        ax = new_axes(ax)
        y = getattr(self, name)
        keep = y > 0 if loglog else np.ones(y.shape, dtype=bool)
        ax.plot(self.amplitude[keep], y[keep], label=f"mode {self.mode}, quasi-static (exact)")
        ax.set_xscale("log")
        if loglog:
            ax.set_yscale("log")
        ax.set_xlabel("modal amplitude a [m·kg^½]")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        place_legend(ax)
        return ax


def modal_backbone(
    structure: JointedStructure | Any,
    mode: int,
    amplitudes: ArrayLike,
    *,
    verify: bool | None = None,
) -> ModalBackbone:
    """The exact amplitude-dependent frequency, damping and dissipation of one mode.

    Quasi-static modal analysis: the structure is loaded along M·φ, φ its linear mode
    `mode` with the joints stuck (mass-normalised), and the modal loop follows Masing's
    rules (see the module notes). Exact for the model: joints with finite elements go
    through `compile_structure` (checked to be order-preserving, so that the loops are
    Masing loops); a structure with one joint may have any density (an Iwan joint).

    Parameters
    ----------
    structure : JointedStructure or NetworkStructure
    mode : int
        The linear mode (0: the lowest), joints stuck.
    amplitudes : array_like, shape (m,)
        Modal amplitudes a > 0 [m·kg^½].
    verify : bool, optional
        Passed to `compile_structure` (replay against the operator; default up to 64
        sliders).

    Returns
    -------
    ModalBackbone

    Examples
    --------
    A mass of 1 kg on a spring of 3 N/m and a Jenkins joint (20 N/m, slips at 1 N):

    >>> from presliding import PIFriction
    >>> s = JointedStructure(1.0, 3.0, [[1.0]], [PIFriction(0.0, [20.0], breakaway=[1.0])])
    >>> bb = modal_backbone(s, 0, [0.01, 1.0])
    >>> [round(float(w) ** 2, 12) for w in bb.frequency]
    [23.0, 4.0]
    """
    st = as_structure(structure)
    w0, phi = st.mode(mode)
    amplitudes = as_si("amplitudes", amplitudes, "modal amplitude")  # [m kg^½]
    a = np.array(as_parameter_vector("amplitudes", amplitudes), dtype=np.float64)
    b = st.mass @ phi
    op = None
    if st.is_discrete:
        op = compile_structure(st.stiffness, st.contacts, st.joints, b, verify=verify)
        p = np.asarray(op.virgin_curve(a), dtype=np.float64)
        d = np.zeros_like(a)
        if op.friction is not None:
            d = amplitude_response(op.friction, a).dissipation
        q = op.deflection(a)
        k, r = (np.empty(0), np.empty(0)) if op.friction is None else (
            np.asarray(op.friction.stiffness), np.asarray(op.friction.threshold))  # fmt: skip
        tangent = op.linear_stiffness + (r[None, :] > a[:, None]) @ k
        first = harmonic_stiffness_elements(op.linear_stiffness, k, r, a)
    elif st.n_contacts == 1:
        p, d, q, tangent, first = single_joint_curve(st.stiffness, st.contacts[:, 0], b,
                                                     st.joints[0], a)  # fmt: skip
    else:
        raise ValueError(
            f"`structure` must have joints with finite elements when it has several "
            f"({st.n_contacts}): a density is exact only for one joint; give each joint "
            f"`PIFriction(c1, density.discretize(n))`-style elements."
        )
    freq = np.sqrt(p / a)
    w1 = np.sqrt(first)
    viscous = float(phi @ np.asarray(st.damping) @ phi)  # c = φᵀCφ of the unit modal mass
    zeta = d / (2.0 * math.pi * p * a) + viscous / (2.0 * freq)
    held = tangent > 1e-12 * np.max(np.abs(tangent))
    with np.errstate(divide="ignore", invalid="ignore"):
        decay = np.where(held, d / (2.0 * math.pi * a * a * np.where(held, tangent, 1.0)), np.inf)
    decay = decay + viscous / (2.0 * w1)
    status = "success"
    message = (
        f"mode {int(mode)} at {a.shape[0]} amplitudes: the exact virgin curve of the modal "
        f"loop and its Masing loops (ω0 = {w0:.8g} rad/s)."
    )
    if np.any(d == 0):
        status = "no_dissipation"
        message += (f" D(a) = 0 at {int(np.sum(d == 0))} amplitude(s) up to "
                    f"{fmt(float(a[d == 0].max()))}: no joint slides there.")  # fmt: skip
    if not held.all():
        status = "macroslip"
        message += (
            f" P' = 0 from a = {fmt(float(a[~held].min()))}: every joint slides and nothing "
            f"holds the mode, so a decay there is no slow decay (ζ_d = inf)."
        )
    return ModalBackbone(
        amplitude=a, modal_force=p, frequency=freq, damping_ratio=zeta, dissipation=d,
        harmonic_frequency=w1, decay_damping_ratio=decay,
        deflection=q, joint_amplitude=q @ st.contacts, linear_frequency=w0, mode_shape=phi,
        mode=int(mode), operator=op, structure=st, status=status, message=message,
    )  # fmt: skip
