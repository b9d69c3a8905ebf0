"""A batch of Prandtl–Ishlinskii operators on one input: B parameter sets, output F[T, B].

`PIBatch` holds B operators of N elements each (eq. 4, optionally with a linear
term a·y and a Coulomb element c·sign(ẏ) of eq. 8) and evaluates all of them
along one sampled input in a single compiled pass, the batch being the SIMD
axis (`presliding.hysteresis._batch_kernels`). Member b gives bit for bit the
play states of ``PIOperator(threshold[b], weight[b]).apply(y)``, and forces
within 1e-12 of F_m. State is explicit: `PIBatchState` holds the play outputs
of every member, so a long input can be processed in chunks with the same
result, bit for bit, as one call.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from presliding._out import as_output
from presliding._validation import (
    as_count,
    as_list,
    as_real_array,
    as_real_scalar,
    as_signal,
    check_size,
    fmt,
)
from presliding.hysteresis import _batch_kernels
from presliding.hysteresis.operators import _SLACK, PIOperator, PIState, check_input_range

__all__ = ["PIBatch", "PIBatchState"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class PIBatchState:
    """Memory of every member of a `PIBatch` after a sample.

    Parameters
    ----------
    last_input : float
        The last input value y seen (shared by all members).
    play : ndarray, shape (B, N)
        Play outputs x_j of every member at that input (eq. 3).
    direction : {-1.0, 0.0, 1.0}
        Sign of the last nonzero input increment, 0 before any motion.
    """

    last_input: float
    play: FloatArray
    direction: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "last_input", as_real_scalar("last_input", self.last_input))
        play = as_real_array("play", self.play)
        if play.ndim != 2:
            raise ValueError(f"`play` must have shape (B, N); got shape {play.shape}.")
        play.setflags(write=False)
        object.__setattr__(self, "play", play)
        d = as_real_scalar("direction", self.direction)
        if d not in (-1, 0, 1):
            raise ValueError(f"`direction` must be -1, 0 or 1; got {fmt(d)}.")
        object.__setattr__(self, "direction", d)

    def member(self, b: int) -> PIState:
        """The `PIState` of member b."""
        b = as_count("b", b, maximum=self.play.shape[0] - 1)
        return PIState(self.last_input, self.play[b].copy(), self.direction)

    @classmethod
    def stack(cls, states: Sequence[PIState]) -> PIBatchState:
        """One batch state from the states of the members (same input and direction).

        Raises
        ------
        ValueError
            If the states differ in `last_input`, `direction` or size.
        """
        states = as_list("states", states)
        for i, s in enumerate(states):
            if not isinstance(s, PIState):
                raise TypeError(
                    f"`states` must hold PIState objects; got {type(s).__name__} at {i}."
                )
        if not states:
            raise ValueError("`states` must not be empty; got 0 states.")
        first = states[0]
        for i, s in enumerate(states):
            if s.last_input != first.last_input or s.direction != first.direction:
                raise ValueError(
                    "`states` must share `last_input` and `direction` (one input drives the "
                    f"batch); got {fmt(s.last_input)}, {fmt(s.direction)} at index {i} against "
                    f"{fmt(first.last_input)}, {fmt(first.direction)} at index 0."
                )
            if s.play.shape != first.play.shape:
                raise ValueError(
                    f"`states` must all hold {first.play.shape[0]} play states; "
                    f"got {s.play.shape[0]} at index {i}."
                )
        return cls(first.last_input, np.stack([s.play for s in states]), first.direction)


@dataclass(frozen=True, eq=False)
class PIBatch:
    """B Prandtl–Ishlinskii operators driven by one input (eq. 4, eq. 8).

    Member b gives F_b = a_b·y + c_b·sign(ẏ) + Σ_j w_bj (y − x_bj).

    Parameters
    ----------
    threshold : array_like, shape (B, N)
        Thresholds r_bj >= 0 of the play operators (eq. 3), one row per member
        (r = 0 is the identity x = y, as in `PIOperator`).
    weight : array_like, shape (B, N)
        Weights w_bj (the stiffnesses k_j of a friction bank); any finite real.
    linear : float or array_like, shape (B,), keyword only, default 0.0
        Coefficients a_b of a linear term a·y (as `PIOperator.linear`).
    coulomb : float or array_like, shape (B,), keyword only, default 0.0
        Coulomb elements c_b >= 0 of eq. 8, contributing c·sign(ẏ) (as in
        `presliding.friction.PIFriction`).

    Notes
    -----
    Evaluating B members at once costs one compiled pass over the input, the
    batch being the vector axis; a member gives bit for bit the play states
    of its own `PIOperator`, and forces within 1e-12 of F_m = Σ_j |w_bj| r_bj.
    Members with fewer elements can be padded with elements of weight 0 (any
    positive threshold): they add exact zeros.

    Examples
    --------
    >>> import numpy as np
    >>> batch = PIBatch(threshold=[[0.1, 0.25], [0.2, 0.5]], weight=[[10.0, 4.0], [5.0, 2.0]])
    >>> force, state = batch.apply(np.array([0.0, 0.05, 0.3, 0.2]))
    >>> force.shape, state.play.shape
    ((4, 2), (2, 2))
    >>> force[:, 0].round(6).tolist()
    [0.0, 0.7, 2.0, 0.6]
    """

    threshold: FloatArray
    weight: FloatArray
    linear: FloatArray = field(default_factory=lambda: np.zeros(()), kw_only=True)  # 0.0
    coulomb: FloatArray = field(default_factory=lambda: np.zeros(()), kw_only=True)  # 0.0
    _kernel_bank: tuple[FloatArray, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        r = as_real_array("threshold", self.threshold)
        r = r.reshape(1, -1) if r.ndim < 2 else r
        if r.ndim != 2:
            raise ValueError(f"`threshold` must have shape (B, N) or (N,); got shape {r.shape}.")
        if (r < 0).any():  # r = 0 is allowed, as for `PIOperator`: the identity x = y
            b, j = (int(k) for k in np.argwhere(r < 0)[0])
            raise ValueError(
                f"`threshold` must be nonnegative; got {fmt(r[b, j])} at index ({b}, {j})."
            )
        w = as_real_array("weight", self.weight)
        if w.ndim < 2:
            w = w.reshape(1, -1)
        if w.shape != r.shape:
            raise ValueError(
                f"`weight` must have the shape of `threshold` {r.shape}; got shape {w.shape}."
            )
        n_batch = r.shape[0]
        lin = _per_member("linear", self.linear, n_batch)
        c = _per_member("coulomb", self.coulomb, n_batch)
        if (c < 0).any():
            i = int(np.argmax(c < 0))
            raise ValueError(f"`coulomb` must be nonnegative; got {fmt(c[i])} at index {i}.")
        for name, arr in (("threshold", r), ("weight", w), ("linear", lin), ("coulomb", c)):
            arr = np.array(arr)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        # element-major copies for the kernel: the batch index is contiguous
        bank = (np.ascontiguousarray(r.T), np.ascontiguousarray(w.T), lin.copy(), c.copy())
        object.__setattr__(self, "_kernel_bank", bank)

    # ------------------------------------------------------------------ construction
    @classmethod
    def stack(cls, operators: Sequence[PIOperator]) -> PIBatch:
        """A batch of the given operators (all with the same number of elements N).

        Parameters
        ----------
        operators : sequence of PIOperator
            The members; their `linear` coefficients are kept.
        """
        ops = as_list("operators", operators)
        for i, op in enumerate(ops):
            if not isinstance(op, PIOperator):
                raise TypeError(
                    f"`operators` must hold PIOperator objects; got {type(op).__name__} at {i}."
                )
        if not ops:
            raise ValueError("`operators` must not be empty; got 0 operators.")
        n = ops[0].n_elements
        for i, op in enumerate(ops):
            if op.n_elements != n:
                raise ValueError(
                    f"`operators` must all have {n} elements (pad with weight-0 elements); "
                    f"got {op.n_elements} at index {i}."
                )
        return cls(
            np.stack([op.threshold for op in ops]),
            np.stack([op.weight for op in ops]),
            linear=np.array([op.linear for op in ops]),
        )

    # ------------------------------------------------------------------ properties
    @property
    def n_members(self) -> int:
        """Number B of operators in the batch."""
        return int(self.threshold.shape[0])

    @property
    def n_elements(self) -> int:
        """Number N of stop elements of each member."""
        return int(self.threshold.shape[1])

    def __len__(self) -> int:
        return self.n_members

    def member(self, b: int) -> PIOperator:
        """Member b as a `PIOperator` (its Coulomb element, if any, is not part of it)."""
        b = as_count("b", b, maximum=self.threshold.shape[0] - 1)
        return PIOperator(self.threshold[b], self.weight[b], linear=float(self.linear[b]))

    def relaxed_state(self, position: float = 0.0) -> PIBatchState:
        """Every member relaxed at `position`: x_bj = y, no motion yet."""
        position = as_real_scalar("position", position)
        return PIBatchState(position, np.full(self.threshold.shape, position), 0.0)

    # ------------------------------------------------------------------ evaluation
    def apply(
        self, y: ArrayLike, state: PIBatchState | None = None, *, out: np.ndarray | None = None
    ) -> tuple[FloatArray, PIBatchState]:
        """Evaluate every member along one sampled input.

        Parameters
        ----------
        y : array_like, shape (T,)
            Input samples, monotone between consecutive samples. A C-contiguous
            float64 array is read in place (not copied).
        state : PIBatchState, optional
            Memory before the first sample (as returned by a previous call).
            Default: every member relaxed at ``y[0]``, no motion yet.
        out : ndarray, shape (T, B), optional, keyword only
            C-contiguous float64 array to write the forces into (as numpy's
            ``out=``); a new array by default.

        Returns
        -------
        force : ndarray, shape (T, B)
            a_b·y + c_b·sign(ẏ) + Σ_j w_bj (y − x_bj) at each sample.
        final_state : PIBatchState
            Memory after the last sample; passing it to the next call on the
            continuation of the input gives bit-identical results to one call.
        """
        yv = as_signal("y", y, copy=False, kind="position")  # only read; a Quantity in SI
        shape = (yv.shape[0], self.n_members)
        if out is None:  # the T × B output is the one O(T) allocation: checked first
            check_size("y", yv, float(shape[0]) * shape[1], what="forces (T × B)")
        out = as_output("out", out, shape)
        if np.may_share_memory(yv, out) and np.shares_memory(yv, out):
            yv = yv.copy()  # `out` is (a view of) the input: read the input before it is written
        x, prev, d0 = self._start(yv, state)
        r, w, lin, c = self._kernel_bank
        # y ± r and every output stay finite (a bound over all members at once)
        check_input_range(yv, r.ravel(), w.ravel(), float(np.abs(lin).max(initial=0.0)))
        d = _batch_kernels.batch_apply(yv, r, w, lin, c, x, prev, d0, out)
        return out, PIBatchState(float(yv[-1]), np.ascontiguousarray(x.T), d)

    def _start(self, y: FloatArray, state: PIBatchState | None) -> tuple[FloatArray, float, float]:
        """Play states (N, B) (a fresh array), input and direction before the first sample."""
        if state is None:
            return np.full((self.n_elements, self.n_members), y[0]), float(y[0]), 0.0
        if not isinstance(state, PIBatchState):
            raise TypeError(f"`state` must be a PIBatchState or None; got {type(state).__name__}.")
        if state.play.shape != self.threshold.shape:
            raise ValueError(
                f"`state` must hold play states of shape {self.threshold.shape} for this batch; "
                f"got shape {state.play.shape}."
            )
        excess = np.abs(state.last_input - state.play) - self.threshold
        bad = excess > _SLACK * (abs(state.last_input) + self.threshold)
        if bad.any():
            b, j = (int(k) for k in np.argwhere(bad)[0])
            raise ValueError(
                "`state` must satisfy |last_input − play_bj| <= threshold_bj; "
                f"got |{fmt(state.last_input)} − {fmt(state.play[b, j])}| > "
                f"{fmt(self.threshold[b, j])} at index ({b}, {j})."
            )
        return state.play.T.copy(), state.last_input, state.direction


def _per_member(name: str, value: ArrayLike, n_batch: int) -> FloatArray:
    """A scalar broadcast to every member, or a vector of one value per member."""
    arr = as_real_array(name, value)
    if arr.ndim == 0:
        return np.full(n_batch, float(arr))
    if arr.shape != (n_batch,):
        raise ValueError(
            f"`{name}` must be a scalar or have shape ({n_batch},) (one per member); "
            f"got shape {arr.shape}."
        )
    return np.ascontiguousarray(arr, dtype=np.float64)
