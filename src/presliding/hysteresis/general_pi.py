"""The exact general Prandtl–Ishlinskii operator ∫ (y − x(y, r)) dμ(r) (eqs. 10, 11).

No discretisation of μ: the memory is the stack of alternating dominant turning
inputs (`MemoryState`), from which the deformation profile r ↦ f(r) is
piecewise linear and the force follows in closed form from the primitives of
the density (see `_general_pi`). Evaluating a sampled input costs O(1) per
sample plus the turning points it wipes out, independent of how finely μ is
resolved. State is explicit: chunked evaluation equals one call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._validation import (
    as_real_array,
    as_real_scalar,
    as_real_vector,
    as_signal,
    check_finite_derived,
    check_type,
    fmt,
)
from presliding.hysteresis import _general_pi as gk
from presliding.hysteresis.densities import Density

__all__ = ["GeneralPIOperator", "MemoryState"]

FloatArray = NDArray[np.float64]


def _sign(x: float) -> float:
    return float(np.sign(x))


@dataclass(frozen=True, eq=False)
class MemoryState:
    """Memory of a continuum of play operators: base, turning inputs, last input.

    The deformation profile it encodes (eq. 11, f = y − x) is, with d the
    direction of the last motion and e_0 = base:

    * f(r) = d·r for r <= ρ (the sliding stops), ρ = |y − e_n|/2, or |y − base|
      when there is no turning input (virgin branch);
    * f(r) = δ_k·r + (y − e_k) on (ρ_k, ρ_{k−1}], δ_k = sign(e_k − e_{k−1}),
      ρ_{k−1} = |e_k − e_{k−1}|/2 (ρ_0 = |e_1 − base|);
    * f(r) = y − base beyond ρ_0.

    Parameters
    ----------
    last_input : float
        The last input y.
    turning : array_like, shape (n,)
        Alternating dominant turning inputs e_1, ..., e_n, oldest first, each
        swing shorter than the one before (wiping-out property).
    base : float
        Input of the relaxed start (f = 0 there); ±inf for a saturated memory of
        an unbounded density (f = d·r for every r).
    direction : {-1.0, 0.0, 1.0}
        Sign of the last nonzero input increment, 0 before any motion.
    """

    last_input: float
    turning: FloatArray
    base: float
    direction: float = 0.0

    def __post_init__(self) -> None:
        y = as_real_scalar("last_input", self.last_input)
        e = as_real_vector("turning", self.turning, allow_empty=True)
        base = self.base
        if not (isinstance(base, (int, float, np.floating)) and math.isinf(base)):
            base = as_real_scalar("base", base)
        d = self.direction
        if isinstance(d, bool) or d not in (-1, 0, 1):
            raise ValueError(f"`direction` must be -1, 0 or 1; got {fmt(d)}.")
        n = e.shape[0]
        with np.errstate(over="ignore", invalid="ignore"):  # s_1 .. s_(n+1); s_1 = ±inf if base is
            steps = np.diff(np.concatenate([[base], e, [y]]))
        check_finite_derived(
            "swing e_k − e_(k−1) between inputs",
            steps if math.isfinite(base) else np.append(0.0, steps[1:]),
            ("base", "turning", "last_input"),
        )
        sgn = np.sign(steps)
        if n and (np.any(sgn[:n] == 0) or np.any(sgn[1:] != -sgn[:-1])):
            raise ValueError(
                f"`turning` must alternate in direction, starting away from `base`, and "
                f"`last_input` must move away from the last turning input; got turning {fmt(e)}, "
                f"base {base!r}, last_input {y!r}."
            )
        radii = np.abs(steps) / 2.0
        radii[0] *= 2.0  # the virgin swing from the base counts in full
        if n and np.any(radii[1:] >= radii[:-1]):
            raise ValueError(
                f"`turning` must have nested swings (each shorter than the one before, "
                f"the first measured from `base`); got turning {fmt(e)}, base {base!r}, "
                f"last_input {y!r}."
            )
        if sgn[-1] != 0 and d != sgn[-1]:
            ref = "turning[-1]" if n else "base"
            raise ValueError(
                f"`direction` must be the sign of `last_input` − `{ref}` ({fmt(sgn[-1])}); "
                f"got {fmt(d)}."
            )
        e.setflags(write=False)
        object.__setattr__(self, "last_input", y)
        object.__setattr__(self, "turning", e)
        object.__setattr__(self, "base", float(base))
        object.__setattr__(self, "direction", float(d))

    @classmethod
    def relaxed(cls, position: float = 0.0) -> MemoryState:
        """Virgin memory at `position`: f(r) = 0 for every threshold.

        Parameters
        ----------
        position : float
            The input y [m] at rest (also the base).

        Returns
        -------
        MemoryState
            No turning inputs, direction 0.
        """
        position = as_real_scalar("position", position)
        return cls(position, np.empty(0), position, 0.0)

    @classmethod
    def saturated(
        cls, position: float = 0.0, direction: float = 1.0, max_threshold: float = math.inf
    ) -> MemoryState:
        """Every stop with r <= max_threshold at f = direction·r after motion in `direction`.

        Parameters
        ----------
        position : float
            The input y [m] reached by that motion.
        direction : {-1, 1}
            Sign of the motion.
        max_threshold : float
            R > 0, the end of the density's support; inf (unbounded support)
            puts the base at ∓inf.

        Returns
        -------
        MemoryState
            Base y − direction·R, no turning inputs.
        """
        position = as_real_scalar("position", position)
        if isinstance(direction, bool) or direction not in (-1, 1):
            raise ValueError(f"`direction` must be -1 or 1; got {fmt(direction)}.")
        max_threshold = as_real_scalar("max_threshold", max_threshold, finite=False)
        if not (max_threshold == math.inf or max_threshold > 0):
            raise ValueError(f"`max_threshold` must be positive; got {fmt(max_threshold)}.")
        base = (
            -direction * math.inf
            if max_threshold == math.inf
            else position - direction * (max_threshold)
        )
        return cls(position, np.empty(0), base, float(direction))

    @property
    def front(self) -> float:
        """ρ: the stops with threshold <= ρ slide (f = d·r) in the current motion."""
        if self.turning.shape[0] == 0:
            return abs(self.last_input - self.base)
        return 0.5 * abs(self.last_input - self.turning[-1])

    def deformation(self, threshold: ArrayLike) -> Any:
        """f(r) = y − x(y, r) (eq. 11) at the given thresholds r >= 0.

        Parameters
        ----------
        threshold : float or array_like, shape (n,)
            Finite thresholds r >= 0 [m].

        Returns
        -------
        float or ndarray
            Deformations f(r) [m], same shape as `threshold`.
        """
        r = as_real_array("threshold", threshold)
        if r.ndim > 1 or r.size == 0 or np.any(r < 0):
            rule = "a nonempty scalar or 1-D array of thresholds r >= 0"
            raise ValueError(f"`threshold` must be {rule}; got {fmt(r)}.")
        y, e, d, prev = self.last_input, self.turning, self.direction, self.base
        out = np.full(r.shape, y - prev if math.isfinite(prev) else 0.0)
        for k in range(e.shape[0]):
            outer = abs(e[k] - prev) * (1.0 if k == 0 else 0.5)
            out = np.where(r <= outer, _sign(e[k] - prev) * r + (y - e[k]), out)
            prev = e[k]
        return np.where(r <= self.front, d * r, out)

    def play(self, threshold: ArrayLike) -> Any:
        """Play outputs x(y, r) = y − f(r) (eq. 3) at the given thresholds.

        Parameters
        ----------
        threshold : float or array_like, shape (n,)
            Finite thresholds r >= 0 [m].

        Returns
        -------
        float or ndarray
            Play outputs x(y, r) [m], same shape as `threshold`.
        """
        return self.last_input - self.deformation(threshold)

    # ------------------------------------------------------------ kernel memory
    def working_memory(self, density: Density) -> tuple[FloatArray, FloatArray]:
        """(head, stack) arrays for the compiled kernels of `_general_pi`.

        Parameters
        ----------
        density : Density
            The distribution μ the kernels integrate over.

        Returns
        -------
        head, stack : ndarray
            The kernel's memory: last input, direction, base and depth in
            `head`; one row per turning input in `stack` (rows beyond the
            depth are spare capacity).
        """
        check_type("density", density, Density)
        return gk.replay(
            self.last_input,
            self.direction,
            self.base,
            np.ascontiguousarray(self.turning),
            density._kind,
            density._par,
            density._tab,
        )

    @classmethod
    def from_working_memory(cls, head: FloatArray, stack: FloatArray) -> MemoryState:
        """The state of kernel arrays (inverse of `working_memory`).

        Parameters
        ----------
        head, stack : ndarray
            Kernel memory as returned by `working_memory` or a kernel run.

        Returns
        -------
        MemoryState
        """
        head = as_real_array("head", head, finite=False)
        stack = check_type("stack", stack, np.ndarray)
        if stack.ndim != 2 or stack.shape[1] < 1:
            raise ValueError(f"`stack` must be two-dimensional; got shape {stack.shape}.")
        if head.shape != (4,) or not 0 <= head[3] <= len(stack) or head[3] % 1:
            raise ValueError(f"`head` must be (last input, direction, base, depth <= "
                             f"len(stack)) of a kernel run; got {fmt(head)}.")  # fmt: skip
        n = int(head[3])
        turning = as_real_vector("stack", stack[:n, 0], allow_empty=True)  # rows beyond: spare
        return cls(float(head[0]), turning.copy(), float(head[2]), float(head[1]))


@dataclass(frozen=True, eq=False)
class GeneralPIOperator:
    """The elastic force ∫_0^R (y − x(y, r)) dμ(r) of eq. 10, evaluated exactly.

    Parameters
    ----------
    density : Density
        The distribution μ.

    Examples
    --------
    >>> from presliding import Uniform
    >>> op = GeneralPIOperator(Uniform(height=2.0, max_threshold=1.0))
    >>> force, state = op.apply([0.0, 0.5, 2.0, 1.0])
    >>> force.round(6).tolist()   # virgin curve, F_m, then F_m − 2·virgin(1/2) (Masing)
    [0.0, 0.75, 1.0, -0.5]
    """

    density: Density

    def __post_init__(self) -> None:
        if not isinstance(self.density, Density):
            raise TypeError(f"`density` must be a Density; got {type(self.density).__name__}.")

    def relaxed_state(self, position: float = 0.0) -> MemoryState:
        """Virgin memory at `position`.

        Parameters
        ----------
        position : float
            The input y [m] at rest.

        Returns
        -------
        MemoryState
            `MemoryState.relaxed` (force 0).
        """
        return MemoryState.relaxed(position)

    def saturated_state(self, position: float = 0.0, direction: float = 1.0) -> MemoryState:
        """Every stop sliding after motion in `direction`: force direction·F_m.

        Parameters
        ----------
        position : float
            The input y [m] reached by that motion.
        direction : {-1, 1}
            Sign of the motion.

        Returns
        -------
        MemoryState
            `MemoryState.saturated` up to the density's R.
        """
        return MemoryState.saturated(position, direction, self.density._big_r)

    def apply(
        self, y: ArrayLike, state: MemoryState | None = None
    ) -> tuple[FloatArray, MemoryState]:
        """Force along a sampled input (monotone between samples) and the final memory.

        Parameters
        ----------
        y : array_like, shape (T,)
            Input samples [m], finite.
        state : MemoryState, optional
            Memory before the first sample; default relaxed at ``y[0]``.

        Returns
        -------
        force : ndarray, shape (T,)
            ∫ (y − x(y, r)) dμ(r) at every sample (eq. 10) [N].
        final_state : MemoryState
        """
        force, _, final = run_density(self.density, as_signal("y", y, copy=False), state)
        return force, final

    def force_at(self, y: float, state: MemoryState) -> tuple[float, float]:
        """(force, slope dF/dy) if the input moved monotonically from the state to `y`.

        Parameters
        ----------
        y : float
            The input reached [m].
        state : MemoryState
            Memory the monotone move starts from.

        Returns
        -------
        force : float
            Elastic force at `y` [N] (eq. 10).
        slope : float
            dF/dy at `y` [N/m]: μ((ρ, R]), the stiffness of the stops that
            still stick (ρ the front at `y`).
        """
        check_type("state", state, MemoryState)
        yv = as_real_scalar("y", y)
        head, stack = _memory(self.density, state, yv)
        d = self.density
        f, s = gk.force_at(yv, head, stack, d._kind, d._par, d._tab)
        return float(f), float(s)

    def elastic_energy(self, state: MemoryState) -> float:
        """½∫ f(r)² dμ(r), the energy stored in the stops (eq. after 12).

        Parameters
        ----------
        state : MemoryState
            Memory of the stops.

        Returns
        -------
        float
            Stored elastic energy [J].
        """
        head, stack = _memory(self.density, check_type("state", state, MemoryState), 0.0)
        d = self.density
        return float(gk.elastic_energy(head, stack, d._kind, d._par, d._tab))


def _memory(
    density: Density,
    state: object,
    y0: float,  # a MemoryState or None; else TypeError
) -> tuple[FloatArray, FloatArray]:
    if state is None:
        return gk.relaxed_memory(y0, 8)
    if not isinstance(state, MemoryState):
        raise TypeError(
            f"`state` must be a MemoryState or None for a density model; "
            f"got {type(state).__name__}."
        )
    return state.working_memory(density)


def run_density(
    density: Density,
    y: FloatArray,
    state: object,  # a MemoryState or None (anything else raises TypeError)
    *,
    dissipation: bool = False,
) -> tuple[FloatArray, FloatArray, MemoryState]:
    """Elastic force along y, cumulative stop dissipation (or empty) and the final memory."""
    head, stack = _memory(density, state, float(y[0]))
    out = np.empty(y.shape[0])
    diss = np.empty(y.shape[0] if dissipation else 0)
    stack = gk.run(y, head, stack, density._kind, density._par, density._tab, out, diss)
    return out, diss, MemoryState.from_working_memory(head, stack)
