"""Command-line outputs: a folder is locked by one run, stale temporaries of killed writes
are removed, the manifest lists only files in place, and write errors name the output."""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import textwrap

import pytest

from presliding import _io
from presliding._io import atomic_path, remove_stale_temporaries
from presliding.cli import main
from presliding.cli.common import LOCK, MANIFEST
from tests.cli.test_commands import MODEL_TOML
from tests.helpers import one_error_line


@pytest.fixture
def model_file(tmp_path):
    path = tmp_path / "model.toml"
    path.write_text(MODEL_TOML, encoding="utf-8")
    return path


def _listed(folder):
    lines = (folder / MANIFEST).read_text(encoding="utf-8").splitlines()
    return [n for n in lines if not n.startswith("#")]


def _start(code: str) -> subprocess.Popen:
    """A Python child that prints 'ready' once it holds what `code` sets up, then waits."""
    proc = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(code)],
        stdout=subprocess.PIPE,
        text=True,
        cwd=os.getcwd(),
    )
    assert proc.stdout.readline().strip() == "ready"
    return proc


# ---------------------------------------------------------------------- locking
def test_a_second_run_into_a_locked_folder_fails_with_one_line(tmp_path, model_file, capsys):
    out = tmp_path / "run"
    out.mkdir()
    holder = _start(
        f"""
        import time
        from filelock import FileLock
        lock = FileLock({str(out / LOCK)!r})
        lock.acquire()
        print("ready", flush=True)
        time.sleep(60)
        """
    )
    try:
        assert main(["simulate", str(model_file), "-o", str(out)]) == 2
        one_error_line(capsys, str(out), "another presliding run is writing into this folder")
        assert not (out / "simulation.csv").exists() and not (out / MANIFEST).exists()
        # the same for a .csv output inside the folder
        assert main(["simulate", str(model_file), "-o", str(out / "x.csv")]) == 2
        one_error_line(capsys, "another presliding run")
    finally:
        holder.kill()
        holder.wait()
    # once the other run has ended, the folder is free again; a run releases it when done
    assert main(["simulate", str(model_file), "-o", str(out), "--quiet"]) == 0
    assert main(["simulate", str(model_file), "-o", str(out), "--quiet"]) == 0
    assert _listed(out) == ["simulation.csv", "simulation.png"]


def test_two_concurrent_runs_never_mix_their_outputs(tmp_path, model_file):
    out = tmp_path / "run"
    out.mkdir()
    cmd = [sys.executable, "-m", "presliding", "simulate", str(model_file), "-o", str(out)]
    cmd.append("--quiet")
    procs = [subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    results = [(p.wait(), p.stderr.read()) for p in procs]
    for p in procs:
        p.stderr.close()
    assert {code for code, _ in results} <= {0, 2} and any(code == 0 for code, _ in results)
    for code, err in results:
        if code == 2:  # the loser ran while the folder was locked: one line, naming it
            assert len(err.strip().splitlines()) == 1 and "another presliding run" in err
    assert _listed(out) == ["simulation.csv", "simulation.png"]
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]


# ---------------------------------------------------------------------- paths
def test_an_existing_folder_named_like_a_csv_is_reported_as_a_folder(tmp_path, model_file, capsys):
    folder = tmp_path / "existing.csv"
    folder.mkdir()
    for extra in ([], ["--overwrite"]):
        assert main(["simulate", str(model_file), "-o", str(folder), *extra]) == 2
        line = one_error_line(capsys, str(folder), "is a folder")
        assert "not written by presliding" not in line and "Errno" not in line
    assert list(folder.iterdir()) == []


# ---------------------------------------------------------------------- killed writes
def test_temporaries_of_a_killed_write_are_removed_by_the_next_run(tmp_path, model_file):
    out = tmp_path / "run"
    child = _start(
        f"""
        import time
        from presliding._io import atomic_path
        with atomic_path({str(out / "simulation.csv")!r}) as tmp:
            tmp.write_bytes(b"x" * 100000)
            print("ready", flush=True)
            time.sleep(60)
        """
    )
    child.send_signal(signal.SIGKILL)
    child.wait()
    stale = [p for p in out.iterdir() if p.name.endswith(".tmp")]
    assert len(stale) == 1 and f".{child.pid}@" in stale[0].name
    # a temporary of a live writer (this process) and one of another host are kept
    with atomic_path(out / "other.txt") as live:
        live.write_text("in progress")
        foreign = out / ".y.csv.1@elsewhere.abcd1234.tmp"
        foreign.write_text("")
        assert main(["simulate", str(model_file), "-o", str(out), "--quiet"]) == 0
        assert not stale[0].exists() and live.exists() and foreign.exists()
    assert _listed(out) == ["simulation.csv", "simulation.png"]


def test_remove_stale_temporaries_only_removes_dead_writers(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    pid = int(dead.stdout)
    host = _io._host()
    gone = tmp_path / f".a.csv.{pid}@{host}.x1y2z3.tmp"
    mine = tmp_path / f".a.csv.{os.getpid()}@{host}.x1y2z3.tmp"
    user = tmp_path / ".notes.tmp"
    for p in (gone, mine, user):
        p.write_text("")
    assert remove_stale_temporaries(tmp_path) == [gone]
    assert mine.exists() and user.exists()


def test_the_manifest_lists_only_files_in_place(tmp_path, model_file, monkeypatch, capsys):
    out = tmp_path / "run"
    import presliding.plotting

    def full_disk(fig, path, *args, **kwargs):
        with atomic_path(path):
            raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(presliding.plotting, "save_figure", full_disk)
    assert main(["simulate", str(model_file), "-o", str(out)]) == 2
    line = one_error_line(capsys, "No space left on device", str(out / "simulation.png"))
    assert ".tmp" not in line
    # the CSV was written and listed; the figure was not, and is not listed
    assert _listed(out) == ["simulation.csv"]
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]
    monkeypatch.undo()
    # a listed file that is gone is dropped from the list when it is read or rewritten
    (out / "simulation.csv").unlink()
    (out / MANIFEST).write_text("# header\nsimulation.csv\nghost.png\n", encoding="utf-8")
    assert main(["simulate", str(model_file), "-o", str(out), "--quiet"]) == 0
    assert _listed(out) == ["simulation.csv", "simulation.png"]


# ---------------------------------------------------------------------- write errors
@pytest.mark.parametrize(
    "where", ["mkstemp", "replace", "write"], ids=["read-only", "rename", "full"]
)
def test_write_errors_name_the_output_not_the_temporary(tmp_path, monkeypatch, where):
    target = tmp_path / "out" / "result.csv"
    if where == "mkstemp":

        def refuse(*args, dir=None, **kwargs):
            raise PermissionError(errno.EACCES, "Permission denied", f"{dir}/.result.csv.x.tmp")

        monkeypatch.setattr(_io.tempfile, "mkstemp", refuse)
    elif where == "replace":

        def read_only(src, dst):
            raise OSError(errno.EROFS, "Read-only file system", src)

        monkeypatch.setattr(_io.os, "replace", read_only)
    with pytest.raises(OSError) as info, atomic_path(target) as tmp:
        if where == "write":
            raise OSError(errno.ENOSPC, "No space left on device")
        tmp.write_text("data")
    assert info.value.filename == str(target), info.value
    assert ".tmp" not in str(info.value) and str(target) in str(info.value)
    assert not target.exists() and not list(target.parent.glob("*.tmp"))
