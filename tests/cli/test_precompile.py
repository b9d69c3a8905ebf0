"""``presliding precompile``: every compiled route once into numba's cache, under its own name."""

from __future__ import annotations

import pytest


def test_the_precompile_command_runs_the_demo_and_every_route_into_nothing_but_the_cache(
    monkeypatch, tmp_path, capsys
):
    """The demo's work and each further route, no files left, and it is documented."""
    from presliding.cli import main, precompile
    from presliding.cli.demo import command as demo

    ran = []
    monkeypatch.setattr(demo, "run_demo", lambda out, quiet, desc: ran.append((out, desc)) or [])
    routes = tuple((name, lambda name=name: ran.append(name)) for name, _ in precompile.ROUTES)
    monkeypatch.setattr(precompile, "ROUTES", routes)
    monkeypatch.chdir(tmp_path)
    assert main(["precompile", "--quiet"]) == 0
    assert not ran[0][0].exists() and ran[1:] == [name for name, _ in routes]
    assert list(tmp_path.iterdir()) == []
    assert main(["precompile"]) == 0
    assert "kernels are cached" in capsys.readouterr().out
    assert main(["--help"]) == 0
    assert "presliding precompile" in capsys.readouterr().out


def test_precompile_speaks_as_itself_not_as_the_demo(monkeypatch, tmp_path, capsys):
    """Its progress lines name ``presliding precompile`` (they said "presliding demo")."""
    from presliding import _progress
    from presliding.cli import main, precompile
    from presliding.cli.demo import command as demo

    monkeypatch.setattr(_progress, "_isatty", lambda stream: False)  # plain lines
    parts = []
    monkeypatch.setattr(demo, "figure3_loops", lambda out: parts.append("loops") or out)

    class Stop(Exception):
        pass

    def free_stop():
        raise Stop

    monkeypatch.setattr(demo, "free_stop", free_stop)
    with pytest.raises(Stop):
        demo.run_demo(tmp_path, quiet=False, desc="presliding precompile")
    err = capsys.readouterr().err
    assert "presliding precompile: [1/6] the paper's Figure 3 loops" in err
    assert "presliding demo" not in err
    monkeypatch.setattr(precompile, "ROUTES", (("networks", lambda: None),))
    monkeypatch.setattr(demo, "run_demo", lambda out, quiet, desc: parts.append(desc) or [])
    assert main(["precompile"]) == 0
    assert parts[-1].startswith("presliding precompile")
    assert "presliding precompile: [1/1] networks" in capsys.readouterr().err


@pytest.mark.parametrize("name", ["viscous and implicit motion", "closed loops"])
def test_the_routes_beyond_the_demo_run(name):
    """Two of the routes `presliding precompile` adds (the fits and the networks take longer;
    their kernels are exercised by their own layers' tests)."""
    from presliding.cli import precompile

    dict(precompile.ROUTES)[name]()


def test_the_network_kernels_run_both_paths_of_a_small_chain(monkeypatch):
    """What ``presliding precompile`` adds to the demo: one exact run (its compiled loop),
    and Moreau–Jean runs of a dense and a sparse chain (both of its loops)."""
    import presliding.network as network
    import presliding.network.events.exact as exact
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
