"""Local worker processes: functions from notebooks and scripts, dead workers, Ctrl-C."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
import types
from pathlib import Path

import numpy as np
import pytest

from presliding.sweep import sweep

SRC = str(Path(__file__).resolve().parents[2] / "src")
GRID = {"a": np.linspace(0.0, 1.0, 5), "b": np.array([1.0, 2.0, 3.0])}


def _run(code: str, tmp_path: Path, timeout: float = 240.0) -> subprocess.CompletedProcess:
    script = tmp_path / "script.py"
    script.write_text(textwrap.dedent(code))
    env = {**os.environ, "PYTHONPATH": SRC + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          timeout=timeout, cwd=tmp_path, env=env)  # fmt: skip


def test_a_function_defined_in_a_notebook_runs_in_worker_processes(monkeypatch):
    # a notebook's functions live in __main__, which the workers do not have
    main = types.ModuleType("__main__")
    exec("import numpy as np\ndef cell_fn(a, b):\n    return np.hypot(a, b) + SHIFT\nSHIFT = 2.0",
         main.__dict__)  # fmt: skip
    monkeypatch.setitem(sys.modules, "__main__", main)
    res = sweep(main.cell_fn, GRID, n_workers=2, chunk_size=4)
    assert res.status == "ok" and res.backend == "processes", res.message
    a, b = np.meshgrid(GRID["a"], GRID["b"], indexing="ij")
    np.testing.assert_array_equal(res.values, np.hypot(a, b) + 2.0)
    shift = main.SHIFT
    closure = sweep(lambda a, b: a * b + shift, GRID, n_workers=2)
    assert closure.status == "ok", closure.message
    np.testing.assert_array_equal(closure.values, a * b + 2.0)


def test_a_script_without_a_main_guard_runs_its_sweep_once(tmp_path):
    out = _run(
        """
        import numpy as np
        from presliding import sweep

        print("script body ran", flush=True)

        def f(a, b):
            return a + 10 * b

        res = sweep(f, {"a": [1.0, 2.0, 3.0], "b": [0.0, 1.0]}, n_workers=2, chunk_size=1)
        print(res.status, res.values.ravel().tolist(), flush=True)
        """,
        tmp_path,
    )
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.count("script body ran") == 1  # the workers did not re-run it
    assert "ok [1.0, 11.0, 2.0, 12.0, 3.0, 13.0]" in out.stdout
    assert "Traceback" not in out.stderr


def _dies(a, b):
    if np.any(a > 0.7):
        os.kill(os.getpid(), signal.SIGKILL)
    return a + b


def test_a_dead_worker_is_named_with_its_cause_and_nothing_is_spilled(capfd):
    res = sweep(_dies, GRID, n_workers=2, chunk_size=3)
    assert res.status == "failed" and res.failed.any()
    assert "a worker process died (SIGKILL: killed by the system" in res.message
    assert "memory" in res.message
    assert "Traceback" not in capfd.readouterr().err


def test_ctrl_c_stops_a_sweep_on_two_workers_promptly(tmp_path):
    script = tmp_path / "slow.py"
    script.write_text(
        textwrap.dedent(
            """
            import sys, time
            import numpy as np
            from presliding import sweep

            def slow(a):
                time.sleep(1.5)
                return a

            print("started", flush=True)
            try:
                sweep(slow, {"a": np.arange(40.0)}, n_workers=2, chunk_size=1)
            except KeyboardInterrupt:
                print("interrupted", flush=True)
                sys.exit(130)
            """
        )
    )
    env = {**os.environ, "PYTHONPATH": SRC + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)  # fmt: skip
    try:
        assert proc.stdout is not None and proc.stdout.readline().strip() == "started"
        time.sleep(6.0)  # the pool is up and working (40 chunks of 1.5 s on 2 workers: 30 s)
        t0 = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=20)
        took = time.perf_counter() - t0
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130 and "interrupted" in out, err[-2000:]
    assert took < 8.0, f"Ctrl-C took {took:.1f} s"
    assert "Traceback" not in err, err[-2000:]


def test_a_function_holding_what_cannot_be_sent_is_refused_before_any_work():
    import threading

    lock = threading.Lock()
    with pytest.raises(TypeError, match=r"`fn` must be picklable by cloudpickle .* lock"):
        sweep(lambda a, b: (lock, a)[1], GRID, n_workers=2)
