"""`compile_network`: a slider network driven through one input as one exact PI operator.

Krejčí, Lamba, Melnik and Rachinskii (Phys. Rev. E 90, 032822, 2014): a
quasi-static network of stops and Coulomb sliders driven through one input
(one node, or several nodes moved by one signal times a load vector of one
sign) is order-preserving, and its input–output map (the input u to the
work-conjugate force F = Σ a_i·R_i) is a Prandtl–Ishlinskii operator, fixed by
its response to a monotone input from the relaxed state. That virgin curve is
piecewise linear and concave, F(u) = c1 + Σ_j k_j·min(u, r_j) (eq. 8 with the
virgin branch of eq. 10), so its exact breakpoints r_j and slope drops k_j are
the thresholds and stiffnesses of the PI elements, and its jump at u = 0+ is
the Coulomb element c1 (sliders between driven nodes and the ground).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from threadpoolctl import threadpool_limits

from presliding._validation import check_type, fmt
from presliding.friction import PIFriction
from presliding.network.sliders._qs_solver import EventSolver
from presliding.network.sliders.slider_network import SliderNetwork

__all__ = ["compile_network", "network_virgin_curve"]

FloatArray = NDArray[np.float64]

#: Relative deviation (of the force range) above which the verification fails.
VERIFY_RTOL = 1e-9


def _load(network: SliderNetwork, load: Any) -> tuple[NDArray[np.int64], FloatArray]:
    if isinstance(load, (int, np.integer)) and not isinstance(load, bool):
        load = {int(load): 1.0}
    check_type("load", load, dict)
    if not load:
        raise ValueError("`load` must drive at least one node; got an empty dict.")
    nodes, coef = [], []
    for node, a in load.items():
        if isinstance(node, bool) or not isinstance(node, (int, np.integer)):
            raise TypeError(f"`load` must map node indices to coefficients; got key {fmt(node)}.")
        if not 0 <= int(node) < network.n_nodes:
            raise ValueError(f"`load` must drive nodes 0..{network.n_nodes - 1}; got {fmt(node)}.")
        a = float(a)
        if not np.isfinite(a) or a == 0.0:
            raise ValueError(f"`load` coefficients must be finite and nonzero; got {fmt(a)}.")
        nodes.append(int(node))
        coef.append(a)
    return np.array(nodes, dtype=np.int64), np.array(coef)


def _check_sign(coef: FloatArray) -> None:
    if np.any(coef > 0) and np.any(coef < 0):
        raise ValueError(
            f"`load` must have coefficients of one sign for the network to be order-preserving "
            f"(then it is one PI operator); got {fmt(coef)}: with a mixed-sign load the "
            f"reduction to a PI operator can fail, so none is returned."
        )


def network_virgin_curve(
    network: SliderNetwork, load: Any
) -> tuple[float, FloatArray, FloatArray, FloatArray]:
    """The exact virgin curve of a network driven by u·a from the relaxed state.

    Any load vector a is accepted here (a mixed-sign one too: its virgin curve
    exists, but need not fix the response to other inputs).

    Returns
    -------
    coulomb : float
        F(0+) [N], the force jump of sliders between driven nodes and the ground.
    breakpoints : ndarray, shape (m,)
        Inputs u_j > 0 [m] where a slider starts to slip.
    forces : ndarray, shape (m,)
        F(u_j) [N].
    slopes : ndarray, shape (m + 1,)
        dF/du [N/m] before each breakpoint and after the last one.
    """
    nodes, coef = _load(network, load)
    if np.all(coef < 0):  # the network is odd: −a gives the same operator
        coef = -coef
    solver = EventSolver(network, nodes, np.empty(0, dtype=np.int64))
    dd = solver.bd_ext.T @ coef
    f = np.zeros(solver.c.shape[0])
    f[~solver.internal] = solver.c_ext * np.sign(dd)
    coulomb = float(coef @ (solver.bd_all @ f))
    f_int = np.zeros(int(solver.internal.sum()))
    slipping = np.zeros(f_int.shape[0], dtype=bool)
    x_f = np.zeros(solver.free.shape[0])
    pdot = np.zeros(0)
    u, force = 0.0, coulomb
    breaks, forces, slopes = [], [], []
    for _ in range(4 * f_int.shape[0] + 10):
        v, fdot, slipping = solver.rates(f_int, slipping, coef, pdot)
        slope = float(coef @ (solver.kdf @ v + solver.kdd @ coef + solver.bd_int @ fdot))
        which, t_ev, target = solver.next_event(f_int, fdot, slipping)
        slopes.append(slope)
        if not np.isfinite(t_ev):
            break
        x_f = x_f + v * t_ev
        f_int = np.clip(f_int + fdot * t_ev, -solver.c_int, solver.c_int)
        f_int[which] = target[which]
        slipping[which] = True  # the likely next active set
        u, force = u + t_ev, force + slope * t_ev
        breaks.append(u)
        forces.append(force)
    else:  # pragma: no cover - every slider slips at most once on a monotone input
        raise RuntimeError("the virgin curve did not end: more events than sliders allow")
    return coulomb, np.array(breaks), np.array(forces), np.array(slopes)


def compile_network(network: SliderNetwork, load: Any, *, verify: bool | None = None) -> PIFriction:
    """The PI operator (eq. 8) of a slider network driven through one input.

    Input: u, the nodes of `load` moved to a_i·u (displacement-driven, every
    other node free); output: the work-conjugate force F = Σ a_i·R_i [N]. The
    elements come from the exact breakpoints of the virgin curve (see the
    module notes); the result is a `PIFriction` that every tool takes
    (`turning_points`, the describing function, the inverse, the fits).

    Parameters
    ----------
    network : SliderNetwork
    load : int or dict {node: coefficient}
        The driven node (coefficient 1), or the load vector a: coefficients of
        one sign (an order-preserving load); a mixed-sign load raises.
    verify : bool, optional
        Also run the network and the compiled operator over a history with
        ten nested reversals and raise if they differ by more than 1e-9 of the
        force range. Default (None): for networks with at most 64 sliders
        (the replay costs about ten virgin curves). The load's sign, the
        hypothesis of the reduction, is checked on every call.

    Returns
    -------
    PIFriction

    Raises
    ------
    ValueError
        A mixed-sign load; a network whose force grows without bound (a path
        of springs from the load to the ground without a slider: a PI
        operator plus a linear spring, which `PIFriction` does not hold); a
        failed verification.

    Examples
    --------
    >>> net = SliderNetwork(2, springs=[(0, 1, 50.0)], sliders=[(1, -1, 1.0)],
    ...                     stops=[(0, -1, 100.0, 0.5)])
    >>> model = compile_network(net, 0)
    >>> model.stiffness.tolist(), model.threshold.tolist()
    ([100.0, 50.0], [0.005, 0.02])
    """
    check_type("network", network, SliderNetwork)
    if verify is not None:
        check_type("verify", verify, (bool, np.bool_))
    nodes, coef = _load(network, load)
    _check_sign(coef)
    with threadpool_limits(1):  # small dense solves: threads only cost
        coulomb, breaks, _, slopes = network_virgin_curve(network, load)
    scale = float(np.max(slopes)) if slopes.shape[0] else 0.0
    if slopes[-1] > 1e-12 * scale:
        raise ValueError(
            f"`network` must not hold the driven nodes to the ground by springs alone: its force "
            f"grows without bound (stiffness {slopes[-1]:.6g} N/m after every slider slips), a "
            f"PI operator plus a linear spring that PIFriction does not represent."
        )
    drops = slopes[:-1] - slopes[1:]
    if np.any(drops < -1e-12 * scale):
        raise ValueError(
            "`network` gives a virgin curve that is not concave for this load, so it is not a "
            "PI operator; none is returned."
        )
    keep = drops > 1e-13 * scale
    stiffness, threshold = drops[keep], breaks[keep]
    model = PIFriction(max(coulomb, 0.0), stiffness, threshold=threshold)
    if verify is None:
        verify = network.n_sliders <= 64
    if verify:
        with threadpool_limits(1):
            _verify(network, nodes, coef if np.all(coef > 0) else -coef, model)
    return model


def verification_history(model: PIFriction) -> FloatArray:
    """Inputs with nested reversals that reach beyond the largest threshold."""
    thresholds = model.threshold if model.threshold is not None else np.ones(1)
    big = 1.25 * float(np.max(thresholds)) if thresholds.shape[0] else 1.0
    return big * np.array([0.0, 1.0, -0.7, 0.45, -0.2, 0.3, -0.05, 0.6, -1.1, 0.35, 0.1])


def network_force(network: SliderNetwork, nodes: Any, coef: FloatArray, u: FloatArray) -> Any:
    """F = Σ a_i·R_i of the network driven by u·a (u linear between samples)."""
    solver = EventSolver(network, nodes, np.empty(0, dtype=np.int64))
    path, _ = solver.run(np.outer(u, coef), np.zeros((u.shape[0], 0)), 10**9, False)
    s = np.array(path.s)
    idx = np.searchsorted(s, np.arange(u.shape[0], dtype=np.float64), side="left")
    return np.array(path.force)[idx] @ coef


def _verify(network: SliderNetwork, nodes: Any, coef: FloatArray, model: PIFriction) -> None:
    u = verification_history(model)
    net = network_force(network, nodes, coef, u)
    pi = model.force(u)[0]
    scale = max(float(np.max(np.abs(net))), 1e-300)
    dev = float(np.max(np.abs(net - pi))) / scale
    if dev > VERIFY_RTOL:
        raise ValueError(
            f"`network` is not reproduced by the PI operator of its virgin curve for this load: "
            f"deviation {dev:.3g} of the force range over a history with nested reversals; none "
            f"is returned."
        )
