"""The progress helper: a bar on a terminal, plain lines elsewhere, silence when quiet,
and "compiling (first run only)" exactly when numba compiles presliding's kernels."""

from __future__ import annotations

import io
import os
import subprocess
import sys

from presliding._progress import COMPILING, Progress


def _plain(**kwargs):
    stream = io.StringIO()
    return stream, Progress("presliding cmd", stream=stream, interactive=False, **kwargs)


def test_plain_lines_per_part_and_note():
    stream, bar = _plain(total=3, unit="part", compile_note=False)
    with bar:
        bar.part("first")
        bar.note("a remark")
        bar.note("a remark")  # said once per part
        bar.update()
        bar.part("second")
        bar.note("a remark")
        bar.update(2)
    assert stream.getvalue().splitlines() == [
        "presliding cmd: [1/3] first",
        "presliding cmd: a remark",
        "presliding cmd: [2/3] second",
        "presliding cmd: a remark",
    ]
    assert bar.n == 3


def test_counted_work_prints_a_line_per_tenth():
    stream, bar = _plain(total=40, unit="chunk", compile_note=False)
    with bar:
        for _ in range(40):
            bar.update()
    lines = stream.getvalue().splitlines()
    assert len(lines) == 10
    assert lines[0] == "presliding cmd: 4/40 chunks (10 %)"
    assert lines[-1] == "presliding cmd: 40/40 chunks (100 %)"


def test_quiet_and_delay_print_nothing():
    for kwargs in ({"quiet": True}, {"delay": 60.0}):
        stream, bar = _plain(total=2, **kwargs)
        with bar:
            bar.part("a part")
            bar.note("a note")
            bar.update(2)
        assert stream.getvalue() == ""


def test_a_terminal_gets_a_bar_with_the_part_and_the_note():
    stream = io.StringIO()
    with Progress("presliding cmd", total=2, unit="part", stream=stream, interactive=True,
                  compile_note=False) as bar:  # fmt: skip
        bar.part("loops")
        bar.note(COMPILING)
        bar.update()
    text = stream.getvalue()
    assert "presliding cmd: loops" in text and COMPILING in text and "/2 [" in text
    assert "\r" in text  # redrawn in place, not one line per update


def test_compiling_is_said_on_a_cold_cache_only(tmp_path):
    """A fresh numba cache folder: the first process compiles (and says so), the next loads."""
    code = (
        "import sys, presliding as ps\n"
        "from presliding._progress import Progress\n"
        "with Progress('probe', total=1, stream=sys.stdout, interactive=False) as bar:\n"
        "    bar.part('force')\n"
        "    ps.PIFriction(0.5, [500.0, 10.0], [1.0, 1.0]).force([0.0, 0.3, -0.2])\n"
        "    bar.update()\n"
        "print(bar.n_compiled)\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    runs = [
        subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                       timeout=600)
        for _ in range(2)
    ]  # fmt: skip
    for run in runs:
        assert run.returncode == 0, run.stderr
    first, second = (run.stdout.splitlines() for run in runs)
    assert first[:2] == ["probe: [1/1] force", f"probe: {COMPILING}"] and int(first[-1]) > 0
    assert second == ["probe: [1/1] force", "0"]


def test_a_delayed_part_line_comes_first_once_the_delay_has_passed():
    import time

    stream, bar = _plain(total=2, delay=0.05, compile_note=False)
    with bar:
        bar.part("reading")  # before the delay: held back
        bar.part("fitting")  # replaces it
        time.sleep(0.06)
        bar.note("a note after the delay")
        bar.part("writing")
    assert stream.getvalue().splitlines() == [
        "presliding cmd: [2/2] fitting",
        "presliding cmd: a note after the delay",
        "presliding cmd: [3/2] writing",
    ]


def test_a_delayed_bar_draws_nothing_before_the_delay_and_notes_after_it():
    import time

    stream = io.StringIO()
    with Progress("presliding cmd", total=2, stream=stream, interactive=True,
                  compile_note=False, delay=0.2) as bar:  # fmt: skip
        bar.part("reading")
        bar.note("early note")
        assert stream.getvalue() == ""  # a quick command shows nothing
        time.sleep(0.25)
        bar.note("late note")
        assert "presliding cmd: reading" in stream.getvalue()
        assert "late note" in stream.getvalue()


def test_a_delayed_bar_appears_when_the_delay_ends_without_an_update():
    import time

    stream = io.StringIO()
    with Progress("presliding cmd", total=2, stream=stream, interactive=True,
                  compile_note=False, delay=0.1) as bar:  # fmt: skip
        bar.part("fitting")
        time.sleep(0.4)  # a long step with no update or note: the timer draws the bar
        assert "presliding cmd: fitting" in stream.getvalue()


def test_plain_output_beats_while_kernels_compile(monkeypatch):
    """A piped run is never silent for long while numba compiles: a line every HEARTBEAT s."""
    import time

    monkeypatch.setattr(Progress, "HEARTBEAT", 0.2)
    stream, bar = _plain(total=1, compile_note=False)
    with bar:
        bar.part("loops")
        bar._on_compile("kernel_a")  # what numba's start event calls
        time.sleep(0.75)
        bar._on_compiled("kernel_a")  # done: the heartbeat stops
        said = len(stream.getvalue().splitlines())
        time.sleep(0.5)
    lines = stream.getvalue().splitlines()
    assert lines[:2] == ["presliding cmd: [1/1] loops", f"presliding cmd: {COMPILING}"]
    beats = [ln for ln in lines if "so far" in ln]
    assert 2 <= len(beats) <= 4 and beats[0].startswith(f"presliding cmd: {COMPILING}: 1 kernel")
    assert len(lines) == said  # nothing after the compilation ended


def test_the_bar_keeps_ticking_and_leads_with_the_note_while_compiling(monkeypatch):
    import time

    monkeypatch.setattr(Progress, "TICK", 0.05)
    stream = io.StringIO()
    with Progress("presliding demo", total=6, unit="part", stream=stream, interactive=True,
                  compile_note=False) as bar:  # fmt: skip
        bar.part("the paper's Figure 3 loops")
        bar._on_compile("kernel_a")
        before = stream.getvalue().count("\r")
        time.sleep(0.4)  # no update from the work: the ticker redraws the clock
        redraws = stream.getvalue().count("\r") - before
        last = stream.getvalue().split("\r")[-1]
        bar._on_compiled("kernel_a")
        after = stream.getvalue().split("\r")[-1]
    assert redraws >= 3
    # the note comes first, so it stays visible when a terminal of 80 columns cuts the line
    assert last.startswith(f"presliding demo: {COMPILING}")
    assert len(f"presliding demo: {COMPILING}") < 60
    assert "Figure 3 loops; 1 kernel" in last
    assert after.startswith("presliding demo: the paper's Figure 3 loops")


def test_a_terminal_that_reports_no_size_still_gets_the_bar(monkeypatch):
    """A pseudo-terminal nobody sized (0 × 0: some consoles, containers, session recorders)
    showed nothing at all for a whole cold demo; it gets an 80-column bar now."""
    import pty
    import select

    monkeypatch.delenv("COLUMNS", raising=False)
    monkeypatch.delenv("LINES", raising=False)
    main, child = pty.openpty()
    assert os.get_terminal_size(child) == (0, 0)
    stream = os.fdopen(child, "w")
    with stream, Progress("presliding demo", total=2, unit="part", stream=stream,
                          compile_note=False) as bar:  # fmt: skip
        assert bar.interactive
        bar.part("the paper's Figure 3 loops")
        bar._on_compile("kernel_a")
        stream.flush()
        text = ""
        while select.select([main], [], [], 0.5)[0]:  # whatever was drawn, no waiting
            text += os.read(main, 65536).decode()
        bar._on_compiled("kernel_a")
    os.close(main)
    assert f"presliding demo: {COMPILING}" in text and "0/2 [" in text


def test_a_notebook_is_told_from_a_terminal_ipython(monkeypatch):
    """IPython's shell in a Jupyter kernel has a kernel; the terminal's has none."""
    import sys
    import types

    from presliding import _progress

    monkeypatch.delitem(sys.modules, "IPython", raising=False)
    assert not _progress.in_notebook()
    for shell, notebook in ((None, False), (types.SimpleNamespace(), False),
                            (types.SimpleNamespace(kernel=object()), True)):  # fmt: skip
        fake = types.SimpleNamespace(get_ipython=lambda shell=shell: shell)
        monkeypatch.setitem(sys.modules, "IPython", fake)
        assert _progress.in_notebook() is notebook
        assert _progress.progress_enabled() is notebook  # stderr is no terminal here
        with Progress("probe", compile_note=False, quiet=True) as bar:
            assert bar.interactive is notebook and bar.quiet
