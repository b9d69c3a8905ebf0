"""Joint identification from ω(a), ζ(a) or D(a): the engine, statuses and intervals of
every fit, with the mode's viscous (fixture) damping fitted beside the joint."""

import numpy as np
import pytest

import presliding as ps
from presliding.structural import JointedStructure
from presliding.structural._joint_model import JOINTS, predict, segalman_elements
from presliding.structural.fit_joint import fit_joint
from presliding.structural.motion import simulate_ring_down
from presliding.structural.ring_down import analyze_ring_down

TRUTH = {"stiffness": 2.0, "slip_force": 0.1, "exponent": -0.3, "mass_ratio": 0.2,
         "linear_stiffness": 10.0, "viscous": 0.01}  # fmt: skip
AMPLITUDES = np.geomspace(0.005, 0.5, 30)


def _model_data(joint, truth, definition, keys=("frequency", "damping_ratio")):
    w, z, d = predict(JOINTS[joint], truth, AMPLITUDES, definition)
    values = {"frequency": w, "damping_ratio": z, "dissipation": d}
    return {"amplitude": AMPLITUDES, **{k: values[k] for k in keys}}


@pytest.mark.parametrize("definition", ["ring_down", "steady_state", "quasi_static"])
def test_segalman_parameters_come_back_from_exact_data(definition):
    fit = fit_joint(_model_data("segalman", TRUTH, definition), definition=definition)
    assert fit.status == "converged" and isinstance(fit.model, ps.PIFriction)
    for name, value in TRUTH.items():
        assert fit.parameters[name] == pytest.approx(value, rel=1e-5), name
    assert fit.derived["natural_frequency"] == pytest.approx(np.sqrt(12.0), rel=1e-5)


@pytest.mark.parametrize(
    "joint, truth",
    [("mindlin", {"slip_force": 0.2, "slip_displacement": 0.05}),
     ("jenkins", {"stiffness": 2.0, "slip_force": 0.1})],
)  # fmt: skip
def test_mindlin_and_jenkins_joints_come_back(joint, truth):
    full = {**truth, "linear_stiffness": 10.0, "viscous": 0.02}
    fit = fit_joint(_model_data(joint, full, "ring_down"), joint)
    assert fit.status == "converged"
    for name, value in full.items():
        assert fit.parameters[name] == pytest.approx(value, rel=1e-5), name


def test_dissipation_alone_fits_the_joint_with_the_mode_held():
    data = _model_data("segalman", TRUTH, "ring_down", keys=("dissipation",))
    fit = fit_joint(data, fixed={"linear_stiffness": 10.0, "viscous": 0.0})
    assert fit.status == "converged"
    for name in ("stiffness", "slip_force", "exponent", "mass_ratio"):
        assert fit.parameters[name] == pytest.approx(TRUTH[name], rel=1e-5), name


def test_a_noisy_ring_down_gives_the_segalman_joint_within_its_intervals():
    """The issue's check, one seed (40 seeds: benchmarks/study_joint_coverage.py): the
    joint as 40 cells and its point mass for the exact ring-down, noise added, the decay
    read by peak tracking, the density fitted with the fixture's damping; the four
    Segalman parameters within their 99 % intervals (one seed; the 95 % coverage over 40
    seeds is what benchmarks/study_joint_coverage.py measures)."""
    seg = ps.SegalmanIwan(TRUTH["stiffness"], TRUTH["slip_force"], TRUTH["exponent"],
                          TRUTH["mass_ratio"])  # fmt: skip
    joint = segalman_elements(seg, 40)
    st = JointedStructure(1.0, TRUTH["linear_stiffness"], [[1.0]], [joint],
                          damping=TRUTH["viscous"])  # fmt: skip
    motion = simulate_ring_down(st, 0, 0.4, 100.0, samples_per_period=32)
    rng = np.random.default_rng(0)
    x = motion.position[:, 0] + 1e-4 * rng.normal(size=motion.time.shape[0])
    rd = analyze_ring_down((motion.time, x), method="peaks")
    fit = fit_joint(rd, level=0.99)
    assert fit.status == "converged", fit.message
    for name in ("stiffness", "slip_force", "exponent", "mass_ratio"):
        lo, hi = fit.confidence_interval[name]
        assert lo <= TRUTH[name] <= hi, (name, lo, TRUTH[name], hi)
    assert fit.parameters["viscous"] == pytest.approx(TRUTH["viscous"], rel=0.3)
    assert fit.parameters["linear_stiffness"] == pytest.approx(10.0, rel=0.01)


def test_bad_inputs_are_refused():
    data = _model_data("segalman", TRUTH, "ring_down")
    with pytest.raises(ValueError, match="`joint` must be one of"):
        fit_joint(data, "coulomb")
    with pytest.raises(ValueError, match="`definition` must be one of"):
        fit_joint(data, definition="hilbert")
    with pytest.raises(ValueError, match="must name only"):
        fit_joint({**data, "phase": data["frequency"]})
    with pytest.raises(ValueError, match="one value per amplitude"):
        fit_joint({**data, "frequency": data["frequency"][:-1]})
    with pytest.raises(ValueError, match="more values than free parameters"):
        fit_joint({"amplitude": AMPLITUDES[:3], "dissipation": [1.0, 2.0, 3.0]})
    with pytest.raises(TypeError, match="`data` must be a RingDown or a mapping"):
        fit_joint([1, 2, 3])
