"""The module paths of network from before its rooms keep resolving (imports, attributes)."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

import presliding
import presliding.network as network

OLD = {
    "exact": ("events", ["simulate_network", "compile_now", "compile_main"]),
    "moreau": ("stepping", ["simulate_network_moreau"]),
    "slider_network": ("sliders", ["SliderNetwork", "GROUND"]),
    "quasi_static": ("sliders", ["quasi_static_network", "QuasiStaticNetworkResult"]),
    "compile": ("reduction", ["compile_network", "network_virgin_curve"]),
    "compile_joints": ("reduction", ["compile_structure", "CompiledStructure"]),
    "structure": (None, ["NetworkStructure", "chain_structure", "square_matrix"]),
    "results": (None, ["NetworkResult", "NetworkEnergy", "NetworkState"]),
}


@pytest.mark.parametrize("old", sorted(OLD))
def test_old_module_paths_are_the_moved_modules(old):
    room, names = OLD[old]
    module = importlib.import_module(f"presliding.network.{old}")
    if room is not None:
        assert module is importlib.import_module(f"presliding.network.{room}.{old}")
    assert getattr(network, old) is module
    for name in names:
        assert hasattr(module, name), f"presliding.network.{old}.{name}"
        if name in network.__all__:
            assert getattr(module, name) is getattr(network, name)
        if name in presliding.__all__:
            assert getattr(module, name) is getattr(presliding, name)


def test_an_old_path_imports_first_in_a_fresh_interpreter():
    """``import presliding.network.exact`` before anything else of the package (a script,
    an unpickled object) finds the moved module."""
    code = (
        "import presliding.network.compile_joints as c, presliding.network.exact as e; "
        "print(e.__name__, c.__name__)"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == [
        "presliding.network.events.exact",
        "presliding.network.reduction.compile_joints",
    ]
