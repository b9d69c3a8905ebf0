"""Ready at first call: on an empty numba cache a call compiles the branch it takes, no more.

An undamped motion leaves the damped closed forms out (the event kernels take
``damped=None``, which numba prunes by type), a finite-element model's density
primitives are a numpy table lookup, and the preload walk sorts its thresholds
without numba's quicksort. One fresh interpreter on an empty cache folder lists
what it compiles (numba's compile events, presliding's and numba's own);
about 3 s of CPU, the price of checking a cold cache at all.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

PROBE = """
import json
from numba.core import event
import presliding as ps

compiled = []


class Listener(event.Listener):
    def on_start(self, ev):
        func = ev.data["dispatcher"].py_func
        compiled.append(f"{func.__module__}.{func.__qualname__}")

    def on_end(self, ev):
        pass


with event.install_listener("numba:compile", Listener()):
    model = ps.PIFriction(0.3, [2e4, 5e3, 1.5e3, 500.0], [0.175] * 4)
    res = ps.simulate(model, 1.0, initial_velocity=0.06, initial_state="saturated", t_end=0.1)
    ps.preloaded_state(model, 0.5)
print(json.dumps({"compiled": compiled, "rest": res.rest_position}))
"""


def test_an_undamped_first_simulate_compiles_only_its_own_branch(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    run = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True,
                         text=True, timeout=600)  # fmt: skip
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout.splitlines()[-1])
    compiled = out["compiled"]
    assert "presliding.motion._event.run_events_sided" in compiled
    assert "presliding.friction.preload.preload_deformation" in compiled
    # the damped closed forms, the primitives of continuous densities, numba's quicksort
    for module in ("presliding.motion._damped", "presliding.hysteresis._density_primitives",
                   "numba.misc.quicksort"):  # fmt: skip
        assert not [name for name in compiled if name.startswith(module)], compiled
    ours = [name for name in compiled if name.startswith("presliding.")]
    assert len(ours) <= 12, ours  # 9 today (32 before)
