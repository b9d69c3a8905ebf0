"""The package's layout: layers, contracts, no import cycles, old module paths."""

from __future__ import annotations

import ast
import importlib
import pickle
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import presliding

PACKAGE = Path(presliding.__file__).resolve().parent
ROOT = Path(__file__).resolve().parents[1]  # the checkout (or unpacked sdist) of the tests
LAYERS = (
    "hysteresis",
    "friction",
    "motion",
    "analysis",
    "network",
    "measurement",
    "identification",
    "control",
    "sweep",
    "structural",
    "cli",
)

# Pickles written before the package was split into layers (module paths
# ``presliding.operators`` and ``presliding.general_pi``, protocol 2).
OLD_PISTATE = (
    b"\x80\x02cpresliding.operators\nPIState\nq\x00)\x81q\x01}q\x02(X\n\x00\x00\x00last_inputq"
    b"\x03G?\xd0\x00\x00\x00\x00\x00\x00X\x04\x00\x00\x00playq\x04cnumpy._core.multiarray\n"
    b"_reconstruct\nq\x05cnumpy\nndarray\nq\x06K\x00\x85q\x07c_codecs\nencode\nq\x08X\x01\x00"
    b"\x00\x00bq\tX\x06\x00\x00\x00latin1q\n\x86q\x0bRq\x0c\x87q\rRq\x0e(K\x01K\x02\x85q\x0f"
    b"cnumpy\ndtype\nq\x10X\x02\x00\x00\x00f8q\x11\x89\x88\x87q\x12Rq\x13(K\x03X\x01\x00\x00"
    b"\x00<q\x14NNNJ\xff\xff\xff\xffJ\xff\xff\xff\xffK\x00tq\x15b\x89h\x08X\x1f\x00\x00\x00"
    b"\xc2\x9a\xc2\x99\xc2\x99\xc2\x99\xc2\x99\xc2\x99\xc2\xb9?\xc2\x9a\xc2\x99\xc2\x99\xc2"
    b"\x99\xc2\x99\xc2\x99\xc3\x89\xc2\xbfq\x16h\n\x86q\x17Rq\x18tq\x19bX\t\x00\x00\x00"
    b"directionq\x1aG?\xf0\x00\x00\x00\x00\x00\x00ub."
)
OLD_MEMORYSTATE = (
    b"\x80\x02cpresliding.general_pi\nMemoryState\nq\x00)\x81q\x01}q\x02(X\n\x00\x00\x00"
    b"last_inputq\x03G\xbf\xb9\x99\x99\x99\x99\x99\x9aX\x07\x00\x00\x00turningq\x04c"
    b"numpy._core.multiarray\n_reconstruct\nq\x05cnumpy\nndarray\nq\x06K\x00\x85q\x07c_codecs"
    b"\nencode\nq\x08X\x01\x00\x00\x00bq\tX\x06\x00\x00\x00latin1q\n\x86q\x0bRq\x0c\x87q\rRq"
    b"\x0e(K\x01K\x01\x85q\x0fcnumpy\ndtype\nq\x10X\x02\x00\x00\x00f8q\x11\x89\x88\x87q\x12Rq"
    b"\x13(K\x03X\x01\x00\x00\x00<q\x14NNNJ\xff\xff\xff\xffJ\xff\xff\xff\xffK\x00tq\x15b\x89h"
    b"\x08X\t\x00\x00\x00333333\xc3\x93?q\x16h\n\x86q\x17Rq\x18tq\x19bX\x04\x00\x00\x00baseq"
    b"\x1aG\x00\x00\x00\x00\x00\x00\x00\x00X\t\x00\x00\x00directionq\x1bG\xbf\xf0\x00\x00\x00"
    b"\x00\x00\x00ub."
)


def _modules() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def test_layer_contracts_hold():
    """import-linter's contracts of pyproject.toml (layers, shared ground) are kept."""
    exe = shutil.which("lint-imports") or str(Path(sys.executable).with_name("lint-imports"))
    if not Path(exe).exists():
        pytest.skip("import-linter is not installed (the test extra has it)")
    run = subprocess.run(
        [exe, "--no-cache", "--config", str(ROOT / "pyproject.toml")],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "0 broken" in run.stdout


def _imports_of(path: Path) -> set[str]:
    """Modules of presliding that a file imports (at any depth, TYPE_CHECKING included)."""
    module = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([base] if base else []))
            found.add(base)
            found.update(f"{base}.{a.name}" for a in node.names)
    names = {m.removesuffix(".__init__") for m in _all_module_names()}
    return {m for m in found if m in names and m != module.removesuffix(".__init__")}


def _all_module_names() -> list[str]:
    return [".".join(p.relative_to(PACKAGE.parent).with_suffix("").parts) for p in _modules()]


def test_no_import_cycles():
    """No module reaches itself through the imports of presliding (functions included).

    A package's ``__init__`` re-exporting its own modules is not a cycle.
    """
    graph = {}
    for path in _modules():
        name = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        graph[name.removesuffix(".__init__")] = _imports_of(path)

    def is_parent(a: str, b: str) -> bool:
        return b.startswith(a + ".")

    edges = {
        m: {t for t in ts if not is_parent(m, t) and not is_parent(t, m)} for m, ts in graph.items()
    }
    # Tarjan's strongly connected components, iteratively.
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []
    counter = 0
    for root in edges:
        if root in index:
            continue
        work = [(root, iter(sorted(edges[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            advanced = False
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(edges.get(child, ())))))
                    advanced = True
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                comp = []
                while True:
                    top = stack.pop()
                    on_stack.discard(top)
                    comp.append(top)
                    if top == node:
                        break
                if len(comp) > 1:
                    cycles.append(sorted(comp))
    assert cycles == []


def test_modules_stay_small_and_the_root_stays_shared_ground():
    """Modules of about 400 lines at most; the root holds shared ground only (the numba
    cache, progress, validation, optional packages and units, file input and output, ...),
    each module kept below every layer by an import contract; one folder a layer."""
    lengths = {
        str(p.relative_to(PACKAGE)): len(p.read_text(encoding="utf-8").splitlines())
        for p in _modules()
    }
    assert {name: n for name, n in lengths.items() if n > 420} == {}
    root = sorted(p.name for p in PACKAGE.glob("*.py"))
    # every root module is shared ground: named in the import contract that keeps it below
    # every layer (plotting and model_io have a contract of their own)
    config = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    shared = {p[:-3] for p in root} - {"__init__", "__main__", "plotting", "model_io"}
    assert {m for m in shared if f'"presliding.{m}"' not in config} == set(), root
    assert sorted(p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()) == sorted(
        LAYERS
    )


@pytest.mark.parametrize("layer", LAYERS)
def test_each_layer_opens_with_its_map(layer):
    """Each subpackage's docstring names what it is for, its files and what it may import."""
    module = importlib.import_module(f"presliding.{layer}")
    doc = module.__doc__ or ""
    assert "May import" in doc
    files = sorted(p.name for p in (PACKAGE / layer).glob("*.py") if p.name != "__init__.py")
    missing = [f for f in files if f not in doc]
    assert missing == []
    for name in getattr(module, "__all__", []):
        assert getattr(module, name) is getattr(presliding, name, getattr(module, name))


def _rooms() -> list[str]:
    """Every sub-package below a layer (identification's rooms, ...), as a dotted path."""
    return sorted(
        ".".join(p.parent.relative_to(PACKAGE).parts)
        for p in PACKAGE.glob("*/*/__init__.py")
        if "__pycache__" not in p.parts
    )


@pytest.mark.parametrize("room", _rooms())
def test_each_room_opens_with_its_map(room):
    """A layer's sub-package (a room: identification's pipeline steps) lists its files and
    what it may import, as a layer does."""
    module = importlib.import_module(f"presliding.{room}")
    doc = module.__doc__ or ""
    assert "May import" in doc
    folder = PACKAGE.joinpath(*room.split("."))
    files = sorted(p.name for p in folder.glob("*.py") if p.name != "__init__.py")
    assert [f for f in files if f not in doc] == []
    parent = importlib.import_module(f"presliding.{room.rsplit('.', 1)[0]}")
    assert f"{room.rsplit('.', 1)[1]}/" in (parent.__doc__ or "")


MAX_MODULES_IN_A_FOLDER = 20


def _module_counts(top: Path) -> dict[str, int]:
    """The number of .py modules of each package folder below `top` (``__init__.py`` left out)."""
    return {
        init.parent.relative_to(top.parent).as_posix(): sum(
            1 for p in init.parent.glob("*.py") if p.name != "__init__.py"
        )
        for init in top.rglob("__init__.py")
        if "__pycache__" not in init.parts
    }


def test_no_folder_holds_several_steps(tmp_path):
    """No package folder under ``src/presliding`` holds more than 20 modules: a folder over
    about 20 holds several steps and is split into rooms (identification's, the command
    line's). Counted: the folder's own ``*.py`` files, ``__init__.py`` left out (it is the
    folder's map, not a step), sub-packages not (they are counted as folders of their own).
    The same count over a folder of 21 modules is seen to exceed the limit."""
    counts = _module_counts(PACKAGE)
    assert counts["presliding"] > 0 and counts["presliding/cli"] > 0
    assert {f: n for f, n in counts.items() if n > MAX_MODULES_IN_A_FOLDER} == {}
    grown = tmp_path / "presliding" / "layer"
    grown.mkdir(parents=True)
    for name in ["__init__", *(f"m{i}" for i in range(MAX_MODULES_IN_A_FOLDER + 1))]:
        (grown / f"{name}.py").write_text("", encoding="utf-8")
    (grown.parent / "__init__.py").write_text("", encoding="utf-8")
    too_many = _module_counts(grown.parent)
    assert too_many == {"presliding": 0, "presliding/layer": MAX_MODULES_IN_A_FOLDER + 1}
    assert {f for f, n in too_many.items() if n > MAX_MODULES_IN_A_FOLDER} == {"presliding/layer"}


OLD_PATHS = {
    "operators": ["PIOperator", "PIState", "play", "stop"],
    "general_pi": ["GeneralPIOperator", "MemoryState"],
    "densities": ["Density", "Uniform", "Exponential", "PiecewiseConstant", "Tabulated"],
    "inverse": ["pi_inverse", "inverse_state", "loading_slopes"],
    "friction": ["PIFriction"],
    "baselines": ["CoulombFriction", "DahlFriction", "LuGreFriction"],
    "comparison": ["compare", "Comparison"],
    "motion": ["simulate", "simulate_batch", "free_response", "MotionResult"],
    "analysis": ["turning_points", "phi", "turning_point", "stops_at_turning_point"],
    "energy": ["total_energy", "elastic_energy", "dissipated_energy"],
    "measurement": ["Measurement"],
    "fitting": ["FitResult"],
    "fit_presliding": ["fit_presliding", "fit_virgin_curve"],
    "fit_motion": ["fit_motion", "predict_motion_force"],
    "fit_response": ["fit_response"],
    "control": ["to_iosys", "iosys_state"],
    "cli": ["main"],
}


@pytest.mark.parametrize("old", sorted(OLD_PATHS))
def test_documented_module_paths_keep_resolving(old):
    module = importlib.import_module(f"presliding.{old}")
    for name in OLD_PATHS[old]:
        assert hasattr(module, name), f"presliding.{old}.{name}"
        if name in presliding.__all__:
            assert getattr(module, name) is getattr(presliding, name)


def test_public_names_unchanged():
    expected = {
        "Comparison", "CoulombFriction", "DahlFriction", "DahlState", "Density", "Discrete",
        "Exponential", "FitResult", "FreeResponse", "GeneralPIOperator", "LuGreFriction",
        "LuGreState", "Measurement", "MemoryState", "MotionBatch", "MotionEnergy", "MotionResult",
        "PIFriction", "PIOperator", "PIState", "PiecewiseConstant", "SweepResult", "Tabulated",
        "TurningPoints", "Uniform", "__version__", "compare", "dissipated_energy",
        "elastic_energy", "fit_motion", "fit_presliding", "fit_response", "fit_virgin_curve",
        "free_response", "inverse_state", "iosys_state", "phi", "pi_inverse", "play",
        "predict_motion_force", "signals", "simulate", "simulate_batch", "stop",
        "stops_at_turning_point", "sweep", "to_iosys", "total_energy", "turning_point",
        "turning_points",
    }  # fmt: skip
    assert expected <= set(presliding.__all__)
    for name in presliding.__all__:
        assert hasattr(presliding, name), name


def test_pickles_from_before_the_move_still_load():
    state = pickle.loads(OLD_PISTATE)
    assert isinstance(state, presliding.PIState)
    assert state.last_input == 0.25 and state.direction == 1.0
    np.testing.assert_array_equal(state.play, [0.1, -0.2])
    memory = pickle.loads(OLD_MEMORYSTATE)
    assert isinstance(memory, presliding.MemoryState)
    assert memory.last_input == -0.1 and memory.direction == -1.0
    np.testing.assert_array_equal(memory.turning, [0.3])


def test_old_pickles_load_in_a_fresh_interpreter():
    """Unpickling imports ``presliding.operators`` by its old name, before anything else."""
    code = (
        "import pickle, sys; s = pickle.loads(sys.stdin.buffer.read()); print(type(s).__module__)"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], input=OLD_PISTATE, capture_output=True, timeout=120
    )
    assert run.returncode == 0, run.stderr.decode()
    assert run.stdout.decode().strip() == "presliding.hysteresis.operators"


@pytest.mark.parametrize(
    "old",
    ["measurement", "_measurement_readers", "_readers", "_mat", "_join", "_units", "_source"],
)
def test_measurement_modules_keep_their_identification_paths(old):
    moved = importlib.import_module(f"presliding.measurement.{old}")
    assert importlib.import_module(f"presliding.identification.{old}") is moved
    assert getattr(presliding.identification, old) is moved
    assert presliding.identification.Measurement is presliding.measurement.Measurement
