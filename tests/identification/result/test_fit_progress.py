"""Progress inside the fits (``progress=``): stages, solver evaluations, search generations,
shown on a `Progress` or stderr, and never a change of the result."""

from __future__ import annotations

import io

import numpy as np
import pytest

import presliding as ps
from presliding._progress import Progress
from presliding.identification.result._fit_progress import FitProgress
from presliding.signals import piecewise_linear
from tests.helpers import stop_records

MODEL = ps.PIFriction(0.2, [400.0, 60.0, 20.0], breakaway=[0.3, 0.4, 0.3])
STOPS = ps.PIFriction(0.3, [4000.0, 1000.0], breakaway=[0.35, 0.35])


def _loops():
    y = piecewise_linear([0.0, 0.02, -0.015, 0.01, -0.02, 0.02], 4e-5)
    rng = np.random.default_rng(3)
    return y, MODEL.force(y)[0] + 2e-3 * rng.standard_normal(y.shape[0])


def _lines(every_evaluation: bool = True) -> tuple[io.StringIO, Progress, FitProgress]:
    stream = io.StringIO()
    bar = Progress("probe", stream=stream, interactive=False, compile_note=False)
    return stream, bar, FitProgress(bar, interval=0.0 if every_evaluation else None)


def _same(a: ps.FitResult, b: ps.FitResult) -> None:
    assert a.parameters == b.parameters
    assert a.standard_error == b.standard_error
    assert a.n_evaluations == b.n_evaluations and a.status == b.status
    np.testing.assert_array_equal(a.fitted, b.fitted)


def test_a_global_search_shows_its_stages_generations_and_evaluations_and_fits_the_same():
    y, f = _loops()
    options = {"search": "global", "seed": 2, "max_generations": 25}
    quiet = ps.fit_presliding(y, f, 3, **options)
    stream, bar, shown = _lines()
    with bar:
        loud = ps.fit_presliding(y, f, 3, progress=shown, **options)
    _same(quiet, loud)
    lines = stream.getvalue().splitlines()
    assert "probe: linear start on a grid of 48 thresholds" in lines
    assert "probe: global search over 3 elements (differential evolution)" in lines
    generations = [ln for ln in lines if "global search: generation" in ln]
    assert generations and generations[0].startswith("probe: global search: generation 1 of at")
    assert "probe: least squares from the global search's thresholds" in lines
    # every evaluation is reported (interval 0); the lowest cost shown is the fit's own
    costs = [
        float(ln.rsplit("cost ", 1)[1]) for ln in lines if "evaluation" in ln and ", cost " in ln
    ]
    assert len(costs) >= loud.n_evaluations
    best = float(np.sum((loud.measured - loud.fitted) ** 2))
    assert min(costs) == pytest.approx(best, rel=1e-3)  # shown to 4 significant digits


def test_throttled_notes_are_few():
    y, f = _loops()
    stream, bar, shown = _lines(every_evaluation=False)  # a line every 2 s at most
    with bar:
        ps.fit_presliding(y, f, 3, progress=shown)
    lines = stream.getvalue().splitlines()
    assert lines[0] == "probe: linear start on a grid of 48 thresholds"
    assert len(lines) <= 3  # a fit of a second or less: its stage, at most one count


def test_progress_true_shows_on_a_terminal_only_and_false_writes_nothing(capsys, monkeypatch):
    y, f = _loops()
    a = ps.fit_presliding(y, f, 2, progress=True)  # stderr is not a terminal here: silent
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(  # stderr taken for a terminal: the progress comes as plain lines
        "presliding.identification.result._fit_progress.progress_enabled", lambda quiet=False: True
    )
    b = ps.fit_presliding(y, f, 2, progress=True)
    err = capsys.readouterr().err
    assert "presliding fit_presliding: linear start on a grid of" in err
    c = ps.fit_presliding(y, f, 2, progress=False)
    assert capsys.readouterr().err == ""
    _same(a, b)
    _same(a, c)


def test_in_a_notebook_progress_true_draws_tqdms_notebook_bar(monkeypatch):
    """Jupyter's stderr is no terminal: the fit drew nothing there; now tqdm.auto's bar."""
    import sys
    import types

    import tqdm.auto

    drawn: list[str] = []

    class NotebookBar:  # what tqdm.auto gives in a notebook (a widget)
        def __init__(self, *args, desc="", **kwargs):
            drawn.append(desc)

        def __getattr__(self, name):
            return lambda *args, **kwargs: drawn.append(name)

    kernel_shell = types.SimpleNamespace(kernel=object())  # IPython's shell in a kernel
    monkeypatch.setitem(
        sys.modules, "IPython", types.SimpleNamespace(get_ipython=lambda: kernel_shell)
    )
    monkeypatch.setattr(tqdm.auto, "tqdm", NotebookBar)
    monkeypatch.setattr(sys, "stderr", io.StringIO())  # the kernel's output stream
    y, f = _loops()
    fit = ps.fit_presliding(y, f, 2, progress=True)
    assert drawn[0] == "presliding fit_presliding"
    assert "set_postfix_str" in drawn  # the notes: stages and evaluations
    _same(fit, ps.fit_presliding(y, f, 2))


def test_a_pooled_fit_with_a_bootstrap_shows_its_steps_and_fits_the_same():
    records, _ = stop_records(5, 3, STOPS, samples=300)
    options = {"n_elements": 2, "bootstrap": 3, "seed": 1}
    quiet = ps.fit_response(records, **options)
    stream, bar, shown = _lines()
    with bar:
        loud = ps.fit_response(records, progress=shown, **options)
    _same(quiet, loud)
    assert quiet.bootstrap == loud.bootstrap
    text = stream.getvalue()
    assert "probe: least squares: 3 record(s)" in text
    assert "probe: search: the regression start, then the records that do not fit" in text
    for b in (1, 2, 3):
        assert f"probe: bootstrap: resample {b} of 3" in text
    assert "probe: bootstrap: resample 3 of 3, about " in text and " s left" in text
    assert "(run 2): 1 evaluation, cost" in text  # each solver run counts anew


def test_cross_validation_names_each_left_out_record():
    records, _ = stop_records(6, 3, STOPS, samples=300)
    stream, bar, _ = _lines()
    with bar:
        cv = ps.cross_validate(records, "response", n_elements=2, progress=bar,
                               labels=["a", "b", "c"])  # fmt: skip
    plain = ps.cross_validate(records, "response", n_elements=2, labels=["a", "b", "c"])
    _same(cv.result, plain.result)
    text = stream.getvalue()
    assert "probe: fit of all 3 records" in text
    for i, name in enumerate("abc"):
        assert f"probe: cross-validation: {name} left out ({i + 1} of 3)" in text


def test_quasi_static_virgin_and_motion_fits_take_progress():
    u = 0.5 * np.sin(np.linspace(0.0, 6 * np.pi, 400))
    y = ps.quasi_static_response(MODEL, u).position
    record = ps.Measurement(np.linspace(0.0, 4.0, 400), position=y, applied_force=u)
    for fit, args in ((ps.fit_quasi_static, ([record],)), (ps.fit_virgin_curve, (y, u))):
        stream, bar, shown = _lines()
        with bar:
            loud = fit(*args, progress=shown)
        _same(fit(*args), loud)
        assert "evaluations, cost" in stream.getvalue()


@pytest.mark.parametrize("bad", ["yes", 1.5, object()])
def test_progress_must_be_a_bool_or_a_progress(bad):
    y, f = _loops()
    with pytest.raises(TypeError, match=r"`progress` must be True, False or a presliding"):
        ps.fit_presliding(y, f, 2, progress=bad)
