"""``presliding precompile``: fill numba's cache ahead of the first run (CI images, containers).

A first call compiles only the kernels of the branch it takes (an undamped
motion leaves the damped pieces out, a PID loop the state-space controller):
`run` runs the demo's computations, then every other route a command or a
first call can take (viscous pieces, the implicit finite-element stepper, the
pooled and quasi-static fits, loops with viscous friction and in batches, both
network paths), each once on a small case, so that all of them are cached.
"""

from __future__ import annotations

from typing import Any

from presliding._progress import Progress


def run(args: Any) -> int:
    """``presliding precompile``: every compiled route once, into numba's cache; say where."""
    import tempfile
    from pathlib import Path

    from presliding import _numba_cache
    from presliding.cli.demo.command import run_demo

    compiled: list[str] = []
    with tempfile.TemporaryDirectory() as tmp, _numba_cache.compiling(compiled.append):
        run_demo(Path(tmp), quiet=args.quiet, desc="presliding precompile: the demo")
        with Progress("presliding precompile", total=len(ROUTES), unit="route",
                      quiet=args.quiet) as bar:  # fmt: skip
            for name, route in ROUTES:
                bar.part(name)
                route()
                bar.update()
    if not args.quiet:
        where = {
            "NUMBA_CACHE_DIR": f"in NUMBA_CACHE_DIR = {_numba_cache.FOLDER}",
            "in-tree": "next to the package's modules (__pycache__)",
            "user": "in numba's user cache folder",
            "temporary": f"in {_numba_cache.FOLDER}",
            "uncached": "nowhere: no folder can be written, so every process compiles them",
        }.get(str(_numba_cache.LOCATION), str(_numba_cache.LOCATION))
        print(
            f"presliding precompile: {len(compiled)} kernels compiled; the kernels are "
            f"cached {where}."
        )
    return 0


def motion_kernels() -> None:
    """The motion routes the demo does not take: viscous (damped) pieces, exact and in a
    batch, the implicit stepper of finite elements, a free response."""
    import numpy as np

    import presliding as ps

    model = ps.PIFriction(0.3, [2e4, 5e3], [0.175, 0.175], viscous=2.0)
    ps.simulate(model, 1.0, initial_velocity=0.06, initial_state="saturated", t_end=0.05)
    ps.simulate(model, 1.0, initial_velocity=0.06, t_end=0.01, method="implicit", step=1e-4)
    t_eval = np.linspace(0.0, 0.05, 3)
    ps.simulate_batch(coulomb=[0.3, 0.2], stiffness=[[2e4, 5e3]] * 2,
                      breakaway=[[0.175, 0.175]] * 2, mass=1.0, viscous=2.0,
                      initial_velocity=0.06, t_end=0.05, t_eval=t_eval)  # fmt: skip
    ps.free_response(1.0, 0.3, [2e4, 5e3], [0.175 / 2e4, 0.175 / 5e3], 0.06, 1e-3, 50,
                     viscous=2.0)  # fmt: skip


def fit_kernels() -> None:
    """The pooled output-error fit (one parameter set and a Jacobian's many) and the
    quasi-static fit, on small simulated records."""
    import numpy as np

    import presliding as ps

    truth = ps.PIFriction(coulomb=0.3, stiffness=[4000.0, 1000.0], breakaway=[0.35, 0.35])
    t = np.linspace(0.0, 0.299, 300)
    records = []
    for v0 in (0.03, -0.045):
        d = np.sign(v0)
        u = np.where(t < 0.05, -0.3 * d, 0.0)
        res = ps.simulate(truth, 2.0, applied_force=(t, u), initial_velocity=v0,
                          initial_state=ps.preloaded_state(truth, 0.5 * d, direction=d),
                          t_eval=t)  # fmt: skip
        records.append(ps.Measurement(t, position=res.position, applied_force=u))
    ps.fit_response(records, n_elements=2, signal="position", initial_state="preload")
    u = 0.8 * np.sin(np.linspace(0.0, 4 * np.pi, 200))
    y = ps.quasi_static_response(truth, u).position
    slow = [ps.Measurement(np.linspace(0.0, 4.0, 200), position=y, applied_force=u)]
    ps.fit_quasi_static(slow, 2, initial_state="relaxed")


def loop_kernels() -> None:
    """A PID loop with viscous friction, a state-space controller, a batch of gain sets."""
    import numpy as np

    import presliding as ps

    model = ps.PIFriction(0.3, [2e4, 5e3], [0.175, 0.175], viscous=2.0)
    pid = ps.PID(400.0, 4e4, 0.0, dt=1e-4, limit=5.0)
    ps.simulate_loop(model, 1.0, pid, reference=1e-3, t_end=0.01)
    a, b, c, d = (np.array([[x]]) for x in (1.0, 1e-4, 4e4, 400.0))
    controller = ps.DiscreteController(a, b, c, d, dt=1e-4)
    ps.simulate_loop(model, 1.0, controller, reference=1e-3, t_end=0.01)
    ps.simulate_loop_batch(model, 1.0, pid, 1e-3, kp=[300.0, 400.0], t_end=0.01)


def network_kernels() -> None:
    """Run both network paths once on a small chain, so their kernels are cached too (the
    demo does not use them)."""
    import numpy as np

    from presliding import PIFriction
    from presliding.network import chain_structure, simulate_network_moreau
    from presliding.network.events import exact

    exact.compile_now()  # in this process (a run on a cold cache leaves it to a second one)
    friction = PIFriction(0.2, [400.0, 150.0], [0.1, 0.15])
    for sparse in (False, True):
        chain = chain_structure(2, 1.0, 1000.0, friction, sparse=sparse)
        simulate_network_moreau(chain, 0.05, 1e-3, initial_velocity=np.array([0.3, -0.2]))


#: What `run` compiles beyond the demo, in order: (progress name, route)
ROUTES = (
    ("viscous and implicit motion", motion_kernels),
    ("pooled and quasi-static fits", fit_kernels),
    ("closed loops", loop_kernels),
    ("networks", network_kernels),
)

__all__ = ["ROUTES", "fit_kernels", "loop_kernels", "motion_kernels", "network_kernels", "run"]
