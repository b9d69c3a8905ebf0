"""The second process that compiles a later part's kernels on a cold cache (`_precompile`)."""

from __future__ import annotations

import subprocess

import pytest

from presliding.cli import _precompile


@pytest.fixture(autouse=True)
def _no_leftovers():
    yield
    _precompile.stop_all()
    assert not _precompile._running


def test_a_warm_cache_starts_nothing_and_wait_returns_at_once(monkeypatch):
    monkeypatch.setattr(_precompile, "_cores", lambda: 2)
    monkeypatch.setattr(_precompile, "_cache_is_cold", lambda task: False)
    assert _precompile.start("demo-later") is False
    _precompile.wait("demo-later")  # nothing to wait for


def test_disabled_jit_or_an_unknown_sentinel_count_as_warm(monkeypatch):
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "1")
    assert _precompile._cache_is_cold("demo-later") is False
    monkeypatch.delenv("NUMBA_DISABLE_JIT")
    monkeypatch.setitem(_precompile._SENTINELS, "missing", "presliding.nowhere:kernel")
    assert _precompile._cache_is_cold("missing") is False


def test_one_core_starts_nothing(monkeypatch):
    monkeypatch.setattr(_precompile, "_cores", lambda: 1)
    monkeypatch.setattr(_precompile, "_cache_is_cold", lambda task: True)
    assert _precompile.start("demo-later") is False


def test_a_started_process_is_waited_for_and_reaped(monkeypatch):
    monkeypatch.setattr(_precompile, "_cores", lambda: 2)
    monkeypatch.setattr(_precompile, "_cache_is_cold", lambda task: True)
    # an unknown task makes the second process exit at once with an error: the
    # command then compiles for itself, as without a second process
    assert _precompile.start("no-such-task") is True
    assert _precompile.start("no-such-task") is False  # one process per task
    proc = _precompile._running["no-such-task"]
    _precompile.wait("no-such-task")
    assert proc.returncode not in (None, 0)
    assert "no-such-task" not in _precompile._running


def test_stop_all_ends_a_process_that_is_still_running(monkeypatch):
    proc = subprocess.Popen(["sleep", "30"])
    monkeypatch.setitem(_precompile._running, "slow", proc)
    _precompile.stop_all()
    assert proc.poll() is not None


def test_the_tasks_name_functions_that_exist():
    import importlib

    def kernel(target):
        module, name = target.split(":")
        return getattr(importlib.import_module(module), name)

    for task, steps in _precompile.TASKS.items():
        for needs, target in steps:
            assert callable(kernel(target)), task
            assert needs is None or hasattr(kernel(needs), "_cache"), task
        assert hasattr(kernel(_precompile._SENTINELS[task]), "_cache")


def test_a_step_waits_for_the_kernels_it_needs_but_not_for_ever(monkeypatch):
    """The second process polls the cache for a kernel the command compiles, and gives up."""
    looks = iter([False, False, True])
    monkeypatch.setattr(_precompile, "_POLL", 0.0)
    monkeypatch.setattr(_precompile, "_is_cached", lambda kernel: next(looks))
    assert _precompile._await_cached("a:b") is True
    monkeypatch.setattr(_precompile, "_is_cached", lambda kernel: False)
    assert _precompile._await_cached("a:b", limit=0.05) is False
    monkeypatch.setattr(_precompile, "_is_cached", lambda kernel: None)  # cannot tell
    assert _precompile._await_cached("a:b") is False


def test_the_second_process_runs_the_steps_in_order_after_their_kernels(monkeypatch):
    log: list[str] = []
    monkeypatch.setattr(_precompile, "_await_cached", lambda kernel: log.append(f"await {kernel}"))
    monkeypatch.setitem(
        _precompile.TASKS,
        "t",
        ((None, "os:getpid"), ("presliding.nowhere:kernel", "os:getcwd")),
    )
    assert _precompile.main(["t"]) == 0
    assert log == ["await presliding.nowhere:kernel"]


def test_the_precompile_command_runs_the_demo_into_nothing_but_the_cache(
    monkeypatch, tmp_path, capsys
):
    """``presliding precompile`` (documented in --help): the demo's work and both network
    paths, no files left."""
    from presliding.cli import demo, main, precompile

    ran = []
    monkeypatch.setattr(demo, "run_demo", lambda out, quiet: ran.append((out, quiet)) or [])
    monkeypatch.setattr(precompile, "network_kernels", lambda: ran.append("network"))
    monkeypatch.chdir(tmp_path)
    assert main(["precompile"]) == 0
    assert len(ran) == 2 and ran[0][1] is False and not ran[0][0].exists()
    assert ran[1] == "network"
    assert "kernels are cached" in capsys.readouterr().out
    assert list(tmp_path.iterdir()) == []
    assert main(["--help"]) == 0
    assert "presliding precompile" in capsys.readouterr().out


def test_the_demo_starts_its_task_early_and_waits_before_its_part(monkeypatch, tmp_path):
    """One second process from the start; the demo compiles its closed loop itself and
    waits for the second process before the identification round trip."""
    from presliding.cli import demo, demo_hunting, demo_sections

    log: list[str] = []
    monkeypatch.setattr(_precompile, "start", lambda task: log.append(f"start {task}") or True)
    monkeypatch.setattr(_precompile, "wait", lambda task: log.append(f"wait {task}"))
    free_stop = demo.free_stop
    monkeypatch.setattr(demo, "free_stop", lambda: log.append("free stop") or free_stop())

    class Done(Exception):
        pass

    hunting_part = demo_hunting.hunting_part
    monkeypatch.setattr(
        demo_hunting, "hunting_part", lambda: log.append("hunting") or hunting_part()
    )

    def identification():
        log.append("identification")
        raise Done

    monkeypatch.setattr(demo_sections, "identification", identification)
    with pytest.raises(Done):
        demo.run_demo(tmp_path)
    assert log == ["start demo-later", "free stop", "hunting", "wait demo-later", "identification"]
    # the second process compiles the parts that run after the wait
    targets = [target for _, target in _precompile.TASKS["demo-later"]]
    assert targets == [
        "presliding.cli.demo_sections:density_part",
        "presliding.cli.demo_sections:identification",
    ]


def test_the_network_kernels_run_both_paths_of_a_small_chain(monkeypatch):
    """What ``presliding precompile`` adds to the demo: one exact run (its compiled loop),
    and Moreau–Jean runs of a dense and a sparse chain (both of its loops)."""
    import presliding.network as network
    import presliding.network.exact as exact
    from presliding.cli.precompile import network_kernels

    calls = []
    for module, name in ((exact, "simulate_network"), (network, "simulate_network_moreau")):
        real = getattr(module, name)
        monkeypatch.setattr(
            module, name, lambda *a, _f=real, _n=name, **k: calls.append((_n, _f(*a, **k)))
        )
    network_kernels()
    assert [n for n, _ in calls] == ["simulate_network"] + ["simulate_network_moreau"] * 2
    assert all(r.success for _, r in calls)
