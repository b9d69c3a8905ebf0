"""Every public result follows one convention.

A result has named arrays, ``success`` (bool), ``status`` (a str from the set its
class documents), ``message`` (str), ``plot(ax=None)`` returning the axes,
``report()`` returning a str, ``to_dict()`` and ``to_pandas()``. Each public
class of ``presliding.__all__`` is either built here (cheaply) and checked, or
listed as not a result, so a new result type that breaks the convention fails.
The integer status of motions and loops stays reachable for one release, with a
DeprecationWarning.
"""

from __future__ import annotations

import functools
import inspect
import pickle
import warnings
from html.parser import HTMLParser

import matplotlib
import numpy as np
import pytest

import presliding as ps

matplotlib.use("Agg")

#: public classes that are not results: models, memory states, densities, data
NOT_RESULTS = {
    "PID", "DiscreteController", "FrictionNonlinearity", "PIFriction", "CoulombFriction",
    "DahlFriction", "DahlState", "LuGreFriction", "LuGreState", "Density", "Discrete",
    "GMSFriction", "GMSState", "CreepingFriction",
    "Exponential", "Uniform", "PiecewiseConstant", "Tabulated", "GeneralPIOperator",
    "MemoryState", "PIOperator", "PIState", "PIInverse", "PIBatch", "PIBatchState",
    "Measurement", "SegalmanIwan", "MindlinContact", "MicroslipBar", "SliderNetwork",
    "Segments",  # the pieces of a Measurement (with table, report and plot), not a result
    "MotionEnergy",  # a part of MotionResult (its `energy`), with its own to_dict
    "NetworkStructure", "NetworkState", "JointedStructure", "CompiledStructure",
    "NetworkEnergy",  # a part of NetworkResult (its `energy`), with its own to_dict
}  # fmt: skip

MODEL = ps.PIFriction(0.3, [100.0, 40.0], breakaway=[0.32, 0.34])
UNDAMPED = ps.PIFriction(coulomb=0.0, stiffness=[100.0], breakaway=[10.0])
_JENKINS_1DOF = ps.JointedStructure(
    1.0, 1.0, [[1.0]], [ps.PIFriction(0.0, [3.0], breakaway=[0.5])], damping=0.1
)
PATH = ps.signals.piecewise_linear([0.0, 0.01, -0.008, 0.006], 2e-4)


def _fit():
    return ps.fit_presliding(PATH, MODEL.force(PATH)[0], 2)


def _measurement():
    t = np.arange(400) * 1e-3
    res = ps.simulate(MODEL, 1.0, initial_velocity=0.05, t_eval=t)
    return ps.Measurement(t, position=res.position, velocity=res.velocity,
                          applied_force=np.zeros_like(t))  # fmt: skip


def _loop(**kw):
    pid = ps.PID(300.0, 1000.0, 10.0, dt=1e-3)
    return ps.simulate_loop(MODEL, 1.0, pid, 1e-3, t_end=0.2, **kw)


def _cycles():
    pytest.importorskip("control")
    import control

    s = control.tf("s")
    return ps.predict_limit_cycles(2.0, ps.PIFriction(0.3), 800.0 + 2e4 / s + 10.0 * s)


@functools.cache
def _cross_validation():
    return ps.cross_validate([_measurement(), _measurement()], fit="response")


def _sweep():
    return ps.sweep(lambda a, b: a * b, {"a": [1.0, 2.0], "b": [3.0, 4.0, 5.0]}, n_workers=1)


BUILDERS = {
    "QuasiStaticNetworkResult": lambda: ps.quasi_static_network(
        ps.SliderNetwork(1, stops=[(0, -1, 100.0, 1.0)]), displacement={0: [0.02, -0.01]}
    ),
    "AmplitudeResponse": lambda: ps.amplitude_response(MODEL, [1e-3, 1e-2]),
    "MotionResult": lambda: ps.simulate(MODEL, 1.0, initial_velocity=0.05, t_end=0.5),
    "MotionBatch": lambda: ps.simulate_batch(MODEL, 1.0, [0.02, 0.05], t_end=0.5),
    "FreeResponse": lambda: ps.free_response(1.0, 0.3, [100.0], [0.003], 0.05, 1e-3, 500),
    "QuasiStaticResponse": lambda: ps.quasi_static_response(MODEL, 0.2 * np.sin(PATH * 300)),
    "TurningPoints": lambda: ps.turning_points(MODEL, 1.0, 0.05),
    "Comparison": lambda: ps.compare([MODEL, ps.CoulombFriction(0.3)], PATH),
    "FitResult": _fit,
    "Prediction": lambda: _cross_validation().predictions[0],
    "MasingCheck": lambda: ps.masing_check(MODEL, (PATH, MODEL.force(PATH)[0])),
    "CrossValidation": _cross_validation,
    "FitComparison": lambda: ps.compare_fits(
        [_measurement(), _measurement()], {"pi": {"n_elements": 2}, "coulomb": {}}
    ),
    "LoopResult": _loop,
    "LoopBatch": lambda: ps.simulate_loop_batch(
        MODEL, 1.0, ps.PID(300.0, 1000.0, 10.0, dt=1e-3), 1e-3, kp=[200.0, 300.0], t_end=0.2
    ),
    "MeasuredCycle": lambda: _loop(initial_velocity=0.0).limit_cycle(after=0.0),
    "LimitCycles": _cycles,
    "SweepResult": _sweep,
    "NetworkResult": lambda: ps.simulate_network(
        ps.chain_structure(2, 1.0, 10.0, MODEL), 0.5, None, [0.05, 0.0]
    ),
    "PeriodicOrbit": lambda: ps.periodic_orbit(_JENKINS_1DOF, [0.4], 1.3, samples=64),
    "FrequencyResponse": lambda: ps.frequency_response(
        _JENKINS_1DOF, [0.4], (1.0, 1.4), step=0.2, max_points=6
    ),
    "StructureMotion": lambda: ps.simulate_ring_down(_JENKINS_1DOF, 0, 1.0, 5.0),
    "RingDown": lambda: ps.analyze_ring_down(
        ps.simulate_ring_down(_JENKINS_1DOF, 0, 1.0, 120.0), method="peaks"
    ),
    "ModalBackbone": lambda: ps.modal_backbone(
        ps.JointedStructure(1.0, 3.0, [[1.0]], [UNDAMPED]), 0, [0.01, 0.1, 1.0]
    ),
}

#: failures that are cheap to provoke: (type, builder, expected status)
FAILURES = {
    "MotionResult": lambda: ps.simulate(
        UNDAMPED, 1.0, initial_velocity=0.1, t_end=100.0, max_events=20
    ),
    "MotionBatch": lambda: ps.simulate_batch(UNDAMPED, 1.0, [0.1, 0.2], t_end=100.0, max_events=20),
    "FreeResponse": lambda: ps.free_response(
        1.0, 0.0, [1e10], [1.0], 1.0, 0.01, 2000, initial_state="relaxed", max_events=100
    ),
    "LoopResult": lambda: _loop(max_events=3),
    "NetworkResult": lambda: ps.simulate_network(
        ps.chain_structure(2, 1.0, 10.0, MODEL), 0.5, None, [0.05, 0.0], max_events=2
    ),
}


def test_every_public_class_is_a_checked_result_or_listed_as_not_one():
    classes = {n for n in ps.__all__ if inspect.isclass(getattr(ps, n))}
    assert classes - NOT_RESULTS - set(BUILDERS) == set(), "classify the new public class"
    assert set(BUILDERS) | NOT_RESULTS >= classes
    assert (set(BUILDERS) | NOT_RESULTS) - classes == set(), "a listed class is not public"


def _documented_statuses(cls) -> str:
    """The class docstring, where the set of statuses is documented."""
    return inspect.getdoc(cls) or ""


def _check(name, res, plt):
    cls = getattr(ps, name)
    assert isinstance(res, cls)
    assert type(res.success) is bool
    assert isinstance(res.status, str) and res.status
    doc = _documented_statuses(cls)
    assert f'"{res.status}"' in doc or f"'{res.status}'" in doc, (name, res.status)
    assert isinstance(res.message, str)
    d = res.to_dict()
    assert isinstance(d, dict)
    assert type(d["status"]) is str and d["status"] == res.status
    assert d["success"] is res.success and d["message"] == res.message
    fields = getattr(res, "__dataclass_fields__", {})
    arrays = [f for f in fields if isinstance(getattr(res, f), np.ndarray)]
    arrays += [k for k, v in d.items() if isinstance(v, np.ndarray | list)]
    assert arrays or name == "MeasuredCycle", f"{name} has no named array"
    text = res.report()
    assert isinstance(text, str) and text.strip()
    ax = res.plot()
    assert ax.__class__.__name__.endswith("Axes")
    plt.close(ax.figure)
    _, given = plt.subplots()
    assert res.plot(ax=given) is given
    plt.close(given.figure)
    pd = pytest.importorskip("pandas")
    frame = res.to_pandas()
    assert isinstance(frame, pd.DataFrame) and frame.shape[0] > 0
    assert frame.attrs.get("status", res.status) == res.status
    assert pickle.loads(pickle.dumps(res.status)) == res.status


@pytest.mark.parametrize("name", sorted(BUILDERS))
def test_result_follows_the_convention(name):
    import matplotlib.pyplot as plt

    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)  # the API never uses int statuses
        res = BUILDERS[name]()
        _check(name, res, plt)


@pytest.mark.parametrize("name", sorted(FAILURES))
def test_failed_result_follows_the_convention(name):
    import matplotlib.pyplot as plt

    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        res = FAILURES[name]()
        assert res.success is False and res.status == "event_limit"
        assert "event limit" in res.message
        _check(name, res, plt)


def test_integer_status_is_deprecated_but_still_compares():
    ok = BUILDERS["MotionResult"]()
    failed = FAILURES["MotionResult"]()
    with pytest.warns(DeprecationWarning, match="`status` is a string"):
        assert ok.status == 0
    with pytest.warns(DeprecationWarning):
        assert failed.status == -1 and failed.status != 0
    with pytest.warns(DeprecationWarning, match="status codes are deprecated"):
        assert ok.status_code == 0 and failed.status_code == -1
    batch = FAILURES["MotionBatch"]()
    assert batch.member_status.tolist() == ["event_limit", "event_limit"]
    with pytest.warns(DeprecationWarning):
        np.testing.assert_array_equal(batch.status_code, [-1, -1])
    loops = BUILDERS["LoopBatch"]()
    assert loops.status == "success" and loops.member_status.tolist() == ["success"] * 2
    with pytest.warns(DeprecationWarning):
        np.testing.assert_array_equal(loops.status_code, [0, 0])
    # the string compares, hashes and pickles as a plain str
    assert ok.status == "success" and {ok.status: 1}["success"] == 1
    assert pickle.loads(pickle.dumps(failed)).status == "event_limit"
    assert type(ok.to_dict()["status"]) is str


class _Tags(HTMLParser):
    """Checks that every opened tag is closed in order, and collects the text."""

    def __init__(self):
        super().__init__()
        self.open, self.text = [], []

    def handle_starttag(self, tag, attrs):
        self.open.append(tag)

    def handle_endtag(self, tag):
        assert self.open and self.open.pop() == tag, f"</{tag}> closes nothing"

    def handle_data(self, data):
        self.text.append(data)


SHOWN = [(n, BUILDERS[n]) for n in sorted(BUILDERS)]
SHOWN += [(n, FAILURES[n]) for n in sorted(FAILURES)]  # a failed run shows its status too
SHOWN_IDS = [f"{n}-{'failed' if i >= len(BUILDERS) else 'ok'}" for i, (n, _) in enumerate(SHOWN)]


@pytest.mark.parametrize(("name", "build"), SHOWN, ids=SHOWN_IDS)
def test_result_shows_itself_in_a_notebook(name, build):
    res = build()
    text = repr(res)
    assert text.startswith(f"{name}(") and len(text) <= 1000, (len(text), text[:200])
    assert str(res.status) in text
    page = res._repr_html_()
    tags = _Tags()
    tags.feed(page)
    assert tags.open == [], "unclosed tags"
    shown = "".join(tags.text)
    assert str(res.status) in shown and res.message[:40] in shown
    assert "<table>" in page and "<th" in page
    assert ("#1a7f37" in page) is res.success  # green for success only
    if getattr(res, "model", None) is not None:
        for name_ in ("coulomb", "stiffness"):
            assert name_ in shown  # the model's parameter table
    pytest.importorskip("pandas")
    attrs = res.to_pandas().attrs
    assert attrs["status"] == str(res.status) and attrs["success"] is res.success
    assert attrs["message"] == res.message and isinstance(attrs["units"], dict)
    if getattr(res, "model", None) is not None:
        assert attrs["parameters"]["coulomb"] == pytest.approx(res.model.coulomb)


def test_a_fit_shows_its_parameter_table_with_units():
    fit = BUILDERS["FitResult"]()
    page = fit._repr_html_()
    for n, v in fit.parameters.items():
        assert f"<td>{n}</td><td>{v:.6g}</td><td>{fit.units[n]}</td>" in page
    frame = fit.to_pandas()
    assert frame.loc["stiffness_1", "unit"] == "N/m" and frame.attrs["units"]["threshold_1"] == "m"
    assert frame.attrs["parameters"]["stiffness"] == pytest.approx([100.0, 40.0])
    assert frame.attrs["kind"] == fit.kind and frame.attrs["nrmse"] == fit.nrmse


def test_a_long_result_is_summarised_not_printed():
    t = np.linspace(0.0, 200.0, 400_001)
    res = ps.simulate(MODEL, 1.0, initial_velocity=0.05, t_eval=t)
    text = repr(res)
    assert len(text) <= 1000 and "<array 400001 float64" in text
    assert "status='success'" in text


def test_units_follow_the_names():
    from presliding._display import summarise, unit_of

    assert [unit_of(n) for n in ("stop_time", "rest_position", "elastic_forces",
                                 "final_velocity", "n_reversals", "energy_viscous",
                                 "nrmse")] == ["s", "m", "N", "m/s", "", "J", ""]  # fmt: skip
    assert summarise(np.array([1.0, np.nan, 3.0, 4.0, 5.0])) == "<array 5 float64, 1 … 5>"
    assert summarise(np.arange(3)) == "[0, 1, 2]"
    assert summarise({f"k{i}": float(i) for i in range(10)}).endswith("… 2 more}")


def test_a_models_density_is_shown_as_its_fields_with_units_not_as_a_raw_repr():
    """The model table of a result showed ``'Discrete(stiffness=array([500.,  10., …``."""
    discrete = ps.simulate(MODEL, 1.0, initial_velocity=0.05, t_end=0.05)
    uniform = ps.PIFriction(0.1, density=ps.Uniform(height=3.5e7, max_threshold=2e-4))
    smooth = ps.simulate(uniform, 1.0, initial_velocity=0.01, t_end=0.01, method="implicit",
                         step=1e-4)  # fmt: skip
    for res, cell in (
        (discrete, "<td>density</td><td>Discrete: stiffness = [100, 40] N/m, threshold = ["),
        (smooth, "<td>density</td><td>Uniform: height = 3.5e+07 N/m², max_threshold = 0.0002 m"),
    ):
        page = res._repr_html_()
        assert cell in page and "array(" not in page
    pytest.importorskip("pandas")
    attrs = smooth.to_pandas().attrs["parameters"]
    assert attrs["density"] == "Uniform: height = 3.5e+07 N/m², max_threshold = 0.0002 m"


@pytest.mark.parametrize(
    "model",
    [
        MODEL,
        ps.PIFriction(0.1, density=ps.Exponential(height=7e7, length=1e-4)),
        ps.PIFriction(0.5, [500.0], [1.0], coulomb_negative=0.3),
    ],
    ids=["elements", "density", "asymmetric"],
)
def test_a_friction_model_shows_its_levels_and_parameters_in_a_notebook(model):
    page = model._repr_html_()
    tags = _Tags()
    tags.feed(page)
    assert tags.open == [] and page.count("<table>") == 2
    shown = "".join(tags.text)
    assert "Coulomb level" in shown and "N/m" in shown and "coulomb" in shown
    if model.is_symmetric:
        assert f"{model.coulomb_level:.6g}" in shown and f"{model.initial_stiffness:.6g}" in shown
    else:
        assert "F_c⁺, F_c⁻" in shown and "coulomb_negative" in shown


def test_a_measurement_shows_its_samples_span_and_signals_in_a_notebook():
    t = np.linspace(0.0, 2.0, 201)
    m = ps.Measurement(t, position=0.3 * np.sin(t), applied_force=np.cos(t), axis="rotary")
    page = m._repr_html_()
    tags = _Tags()
    tags.feed(page)
    assert tags.open == []
    for cell in ("<td>samples</td><td>201</td>", "<td>sampling step</td><td>0.01</td><td>s</td>",
                 "<td>position</td><td>0 … 0.3</td><td>rad</td>",
                 "<td>applied_force</td><td>-0.416147 … 1</td><td>N m</td>"):  # fmt: skip
        assert cell in page


@pytest.mark.parametrize(("name", "build"), sorted(BUILDERS.items()))
def test_to_pandas_without_pandas_names_the_extra(name, build, monkeypatch):
    """Without pandas, every `to_pandas` raises the one ImportError naming the extra (it was
    a bare ModuleNotFoundError for most results)."""
    import sys

    res = build()
    monkeypatch.setitem(sys.modules, "pandas", None)  # an import of pandas now fails
    expected = (r"^`\S*to_pandas\(\)` needs the optional package `pandas`; install it with "
                r'`pip install "presliding\[pandas\]"`\.$')  # fmt: skip
    with pytest.raises(ImportError, match=expected):
        res.to_pandas()
