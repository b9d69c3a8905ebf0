"""``import presliding`` works on a read-only install with no writable home.

The package is copied to a folder that is then made read-only (a read-only bind
mount in a private mount namespace where ``unshare`` allows it, else
``chmod -R a-w`` for a user other than root), HOME points to a read-only folder
and XDG_CACHE_HOME is unset, so neither of numba's own cache folders can be
written. A fresh interpreter imports that copy and runs a compiled kernel.
"""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

import presliding
from presliding import _numba_cache

PACKAGE = Path(presliding.__file__).resolve().parent

# Runs in the read-only sandbox: imports the copy, counts kernels compiled, runs one.
PROBE = """
import sys
import presliding as ps
from presliding import _numba_cache as cache
compiled = []
with cache.compiling(compiled.append):
    model = ps.PIFriction(0.5, [500.0, 10.0, 4.0], [1.0, 1.0, 1.0])
    force, _ = model.force(ps.signals.piecewise_linear([0.0, 0.3, -0.3, 0.1], step=1e-3))
print(ps.__file__)
print(cache.LOCATION)
print(cache.FOLDER)
print(len(compiled))
print(repr(float(force.sum())))
"""


def _copy_package(site: Path) -> None:
    shutil.copytree(
        PACKAGE, site / "presliding", ignore=shutil.ignore_patterns("__pycache__", "*.nb[ic]")
    )


def _make_read_only(*folders: Path) -> None:
    for folder in folders:
        for path in [folder, *folder.rglob("*")]:
            mode = path.stat().st_mode
            path.chmod(mode & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))


def _make_writable(*folders: Path) -> None:
    for folder in folders:
        for path in [folder, *folder.rglob("*")]:
            path.chmod(path.stat().st_mode | stat.S_IWUSR)


def _namespace_prefix() -> list[str] | None:
    """A command prefix giving a private mount namespace, or None where unshare cannot."""
    exe = shutil.which("unshare")
    if exe is None or not sys.platform.startswith("linux"):
        return None
    prefix = [exe, "--mount", "--propagation", "private"]
    if os.geteuid() != 0:
        prefix[1:1] = ["--user", "--map-root-user"]
    probe = subprocess.run([*prefix, "true"], capture_output=True, timeout=60)
    return prefix if probe.returncode == 0 else None


def _run_read_only(
    site: Path, home: Path, tmpdir: Path, *, temporary_too: bool = False
) -> subprocess.CompletedProcess[str]:
    """Run PROBE with `site` and `home` read-only (and /tmp and `tmpdir` too if asked)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "XDG_"))}
    env.update(
        HOME=str(home), PYTHONPATH=str(site), TMPDIR=str(tmpdir), MPLBACKEND="Agg",
        MPLCONFIGDIR=str(home / "mpl"), PYTHONDONTWRITEBYTECODE="1",
    )  # fmt: skip
    python = [sys.executable, "-c", PROBE]
    prefix = _namespace_prefix()
    if prefix is not None:
        folders = [site, home]
        if temporary_too:
            folders += [tmpdir, *(Path(p) for p in ("/tmp", "/var/tmp", "/usr/tmp"))]
        # a bind mount, then read-only (also for a root mapped into a user namespace)
        mounts = " && ".join(
            f"mount --bind '{f}' '{f}' && mount -o remount,bind,ro '{f}'"
            for f in folders
            if f.is_dir()
        )
        cmd = [*prefix, "sh", "-c", f'{mounts} && exec "$@"', "sh", *python]
    elif os.geteuid() != 0 and not temporary_too:
        _make_read_only(site, home)
        cmd = python
    else:
        pytest.skip(
            "no way to make a folder read-only here (unshare not permitted, running as root)"
        )
    try:
        return subprocess.run(
            cmd, env=env, cwd=site, capture_output=True, text=True, timeout=600
        )  # fmt: skip
    finally:
        if prefix is None:
            _make_writable(site, home)


def _expected_sum() -> float:
    model = presliding.PIFriction(0.5, [500.0, 10.0, 4.0], [1.0, 1.0, 1.0])
    y = presliding.signals.piecewise_linear([0.0, 0.3, -0.3, 0.1], step=1e-3)
    return float(model.force(y)[0].sum())


@pytest.fixture
def sandbox(tmp_path):
    site, home, tmpdir = tmp_path / "site", tmp_path / "home", tmp_path / "tmp"
    for folder in (site, home, tmpdir):
        folder.mkdir()
    _copy_package(site)
    return site, home, tmpdir


def test_read_only_install_caches_in_a_private_temporary_folder(sandbox):
    site, home, tmpdir = sandbox
    runs = [_run_read_only(site, home, tmpdir) for _ in range(2)]
    for run in runs:
        assert run.returncode == 0, run.stderr
        assert "cannot cache" not in run.stderr and "no writable folder" not in run.stderr
    first, second = (run.stdout.split("\n") for run in runs)
    assert Path(first[0]).resolve() == (site / "presliding" / "__init__.py").resolve()
    assert first[1] == "temporary"
    folder = Path(first[2])
    assert folder.parent == tmpdir and folder.name.startswith("presliding-numba-cache-")
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert list(folder.rglob("*.nbi")) and list(folder.rglob("*.nbc"))
    assert not list((site / "presliding").rglob("*.nbi")) and not list(home.iterdir())
    assert int(first[3]) > 0  # a cold cache: the kernels were compiled ...
    assert second[1] == "temporary" and int(second[3]) == 0  # ... and loaded the next time
    assert float(first[4]) == float(second[4]) == _expected_sum()


def test_nothing_writable_runs_uncached_with_one_line(sandbox):
    site, home, tmpdir = sandbox
    run = _run_read_only(site, home, tmpdir, temporary_too=True)
    assert run.returncode == 0, run.stderr
    out = run.stdout.split("\n")
    assert out[1] == "uncached" and int(out[3]) > 0
    notes = [ln for ln in run.stderr.splitlines() if ln.startswith("presliding:")]
    assert notes == [
        "presliding: no writable folder for numba's cache (package, NUMBA_CACHE_DIR, user "
        "cache, temporary directory); kernels are compiled anew in every process."
    ]
    assert float(out[4]) == _expected_sum()


def test_an_unsafe_temporary_folder_is_not_used(tmp_path, monkeypatch):
    """A folder of that name writable by others (or not a folder) is never loaded from."""
    if not hasattr(os, "getuid"):
        pytest.skip("POSIX ownership checks")
    monkeypatch.setattr("tempfile.tempdir", str(tmp_path))
    folder = tmp_path / f"presliding-numba-cache-{os.getuid()}"
    folder.mkdir(mode=0o777)
    folder.chmod(0o777)
    assert _numba_cache._private_temporary_folder() is None
    folder.rmdir()
    folder.symlink_to(tmp_path)
    assert _numba_cache._private_temporary_folder() is None
    folder.unlink()
    made = _numba_cache._private_temporary_folder()
    assert made == folder and stat.S_IMODE(folder.stat().st_mode) == 0o700


def test_this_install_has_a_cache_location():
    assert _numba_cache.LOCATION in {"NUMBA_CACHE_DIR", "in-tree", "user", "temporary"}
    assert _numba_cache.configure() == _numba_cache.LOCATION  # a second call keeps the choice
