"""Set-up of batches of exact motions (`simulate_batch`, `free_response`): parameters,
broadcasting, initial deformations, the kernel call on threads."""

from __future__ import annotations

import itertools
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from presliding._validation import (
    as_list,
    as_nonnegative_scalar,
    as_parameter_matrix,
    as_parameter_vector,
    as_real_vector,
    check_same_length,
    fmt,
)
from presliding.friction._model_checks import check_derived, check_has_friction
from presliding.friction.pi_friction import PIFriction
from presliding.motion._event import kernel_array
from presliding.motion._run import check_model, saturation_direction

FloatArray = NDArray[np.float64]


def single_bank(
    coulomb: Any, stiffness: Any, threshold: Any
) -> tuple[float, FloatArray, FloatArray]:
    """c1, k (N,), r (N,) of one model given by its parameter vectors, validated as PIFriction."""
    c1 = as_nonnegative_scalar("coulomb", coulomb)
    k = as_parameter_vector("stiffness", stiffness, allow_empty=True)
    r = as_parameter_vector("threshold", threshold, allow_empty=True)
    check_same_length(stiffness=k, threshold=r)
    with np.errstate(over="ignore", under="ignore"):  # reported by check_derived
        c = k * r
    check_derived(k, c, r, given="threshold")
    check_has_friction(np.array([c1]), k.shape[0])
    return c1, np.array(k), np.array(r)


def stack_models(models: Any) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """c1 (B,), σ (B,), k (B, N), r (B, N) from PIFriction models; shorter banks padded inertly."""
    seq = [models] if isinstance(models, PIFriction) else as_list("models", models)
    if not seq:
        raise ValueError("`models` must not be empty; got 0 models.")
    for i, model in enumerate(seq):
        if not isinstance(model, PIFriction):
            raise TypeError(f"`models` must hold PIFriction models; got {type(model).__name__} "
                            f"at index {i}.")  # fmt: skip
        check_model(model)
    n = max(mod.n_elements for mod in seq)
    # an inert element: no stiffness, never reaches its threshold
    k = np.zeros((len(seq), n))
    r = np.full((len(seq), n), np.inf)
    for i, mod in enumerate(seq):
        k[i, : mod.n_elements] = mod.stiffness
        r[i, : mod.n_elements] = mod.threshold
    sigma = np.array([mod.viscous for mod in seq], dtype=np.float64)
    return np.array([mod.coulomb for mod in seq]), sigma, k, r


def stack_parameters(
    coulomb: Any, stiffness: Any, breakaway: Any, threshold: Any, viscous: Any = 0.0
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, str, dict[str, int]]:
    """Validated parameter arrays of a batch, before broadcasting to the batch size.

    Returns c1 (Bc,), σ (Bv,), k (Bk, N), the given `breakaway` or `threshold`
    (Bo, N), its name, and the lengths {name: B} for `batch_size`.
    """
    if coulomb is None or stiffness is None:
        missing = " and ".join(
            f"`{n}`" for n, v in (("coulomb", coulomb), ("stiffness", stiffness)) if v is None
        )
        raise TypeError(
            "`coulomb` and `stiffness` (with `breakaway` or `threshold`) must be given when "
            f"`models` is not; got no {missing}."
        )
    if (breakaway is None) == (threshold is None):
        raise TypeError(
            "`breakaway` or `threshold` must be given, not both; got "
            + ("both." if breakaway is not None else "neither.")
        )
    c1 = np.array(as_parameter_vector("coulomb", coulomb, positive=False))
    sigma = np.array(as_parameter_vector("viscous", viscous, positive=False))
    k = as_parameter_matrix("stiffness", stiffness)
    name = "breakaway" if threshold is None else "threshold"
    raw = breakaway if threshold is None else threshold
    other = as_parameter_matrix(name, raw)
    if np.ndim(raw) == 0:  # one value for every element
        other = np.full((1, k.shape[1]), other[0, 0])
    if other.shape[1] != k.shape[1]:
        raise ValueError(
            f"`{name}` must have as many elements (columns) as `stiffness`; got {other.shape[1]} "
            f"and {k.shape[1]}."
        )
    sizes = {"coulomb": c1.shape[0], "viscous": sigma.shape[0], "stiffness": k.shape[0],
             name: other.shape[0]}  # fmt: skip
    return c1, sigma, k, other, name, sizes


def broadcast_parameters(c1, sigma, k, other, name: str, n_b: int):
    """c1 (B,), σ (B,), k (B, N), r (B, N) of a batch of size `n_b`, checked as PIFriction."""
    c1 = np.array(np.broadcast_to(c1, (n_b,)))
    sigma = np.array(np.broadcast_to(sigma, (n_b,)))
    k = np.array(np.broadcast_to(k, (n_b, k.shape[1])))
    other = np.array(np.broadcast_to(other, k.shape))
    with np.errstate(over="ignore", under="ignore"):  # reported by check_derived
        c, r = (other, other / k) if name == "breakaway" else (k * other, other)
    check_derived(k, c, r, given=name)
    check_has_friction(c1, k.shape[1])
    return c1, sigma, k, np.ascontiguousarray(r)


def as_batch_vector(name: str, value: Any, positive: bool = False) -> FloatArray:
    """A finite scalar or 1-D array (positive if asked), as a 1-D array."""
    if positive:
        return as_parameter_vector(name, value)
    return as_real_vector(name, value)


def batch_size(sizes: dict[str, int]) -> int:
    """The common batch size: every length is 1 or the same B."""
    big = {n for n in sizes.values() if n != 1}
    if len(big) > 1:
        long = {k: v for k, v in sizes.items() if v != 1}
        names = ", ".join(f"`{k}`" for k in long)
        got = ", ".join(f"{k} {v}" for k, v in long.items())
        raise ValueError(
            f"{names} must have length 1 or one common length B (the batch size); got "
            f"lengths {got}."
        )
    return big.pop() if big else 1


def batch_deformation(initial_state: Any, r: FloatArray, v0: FloatArray, u0: float):
    """Deformations (B, N) for "relaxed" or "saturated" starts, and the trajectory's
    last directions (B,): sign(v0), since a start from rest is never a reversal."""
    if not isinstance(initial_state, str):
        raise TypeError(
            f"`initial_state` must be 'relaxed' or 'saturated'; got {type(initial_state).__name__}."
        )
    vdir = np.sign(v0)
    if initial_state == "relaxed":
        f = np.zeros(r.shape)
    elif initial_state == "saturated":
        sat = saturation_direction(vdir, u0)
        f = np.where(np.isfinite(r), np.reshape(sat, (-1, 1)) * r, 0.0)
    else:
        raise ValueError(
            f"`initial_state` must be 'relaxed' or 'saturated'; got {fmt(initial_state)}."
        )
    return np.ascontiguousarray(f), np.ascontiguousarray(vdir, dtype=np.float64)


def run_batch(m, c1, sigma, k, r, f0, y0, v0, last_dir, u_t, u_val, times, t_end, max_events):
    """Run the batch kernel on ranges of members in threads and wrap the outputs."""
    from presliding.motion._batch_events import batch_events
    from presliding.motion._event import damped_flag
    from presliding.motion.results import MotionBatch, member_statuses

    n_b, n_t = m.shape[0], times.shape[0]
    # C-contiguous writable float64 throughout: the kernels compile once for every call
    m, c1, sigma, k, r, f0, y0, v0, last_dir, u_t, u_val, times = (
        kernel_array(a) for a in (m, c1, sigma, k, r, f0, y0, v0, last_dir, u_t, u_val, times)
    )
    o_y = np.full((n_b, n_t), np.nan)
    o_v = np.full((n_b, n_t), np.nan)
    stop = np.empty(n_b)
    n_rev = np.empty(n_b, dtype=np.int64)
    status = np.empty(n_b, dtype=np.int64)
    y_end = np.empty(n_b)
    v_end = np.empty(n_b)
    args = (m, c1, sigma, k, r, f0, y0, v0, last_dir, u_t, u_val, times, float(t_end),
            int(max_events), o_y, o_v, stop, n_rev, status, y_end, v_end,
            damped_flag(sigma))  # fmt: skip
    n_threads = min(n_b, numba.get_num_threads())
    if n_threads <= 1:
        batch_events(0, n_b, *args)
    else:  # a few ranges per thread: members differ in cost
        edges = [int(e) for e in np.linspace(0, n_b, min(n_b, 4 * n_threads) + 1)]
        with ThreadPoolExecutor(n_threads) as pool:
            done = [pool.submit(batch_events, a, b, *args)
                    for a, b in itertools.pairwise(edges) if b > a]  # fmt: skip
            for job in done:
                job.result()
    stop = np.where(np.isnan(stop), np.inf, stop)
    failed = int(np.sum(status != 0))
    message = (
        "all motions solved exactly"
        if not failed
        else (f"{failed} of {n_b} motions reached the event limit max_events = {max_events}")
    )
    member = member_statuses(status)
    return MotionBatch(times, o_y, o_v, stop, n_rev, y_end, v_end, member, message)
