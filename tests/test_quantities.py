"""pint Quantities everywhere: every public entry point converts a physical argument to SI.

The public API (the functions of ``presliding.__all__``, the constructors of its
models, states and parameters, and the public methods of every class) is
enumerated from the package itself. Each argument is classified: a physical
quantity of a kind (`presliding._interop.QUANTITY_KINDS`, by the argument's name,
or `OVERRIDES` where a name means something else in one place), or no quantity
(`NOT_QUANTITIES`). A new argument that is neither fails `test_every_argument_is_
classified`; a new entry point with a physical argument and no example call in
`CALLS` fails `test_every_entry_point_with_a_quantity_has_an_example`. Then each
physical argument of each entry point is given a Quantity of another dimension
(refused, naming the argument and its kind) and, where the example passes it, the
same value as a Quantity in SI (taken, as the plain number is).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import presliding as ps
from presliding._interop import QUANTITY_KINDS, SI_UNITS

pint = pytest.importorskip("pint")
Q = pint.UnitRegistry().Quantity

#: result classes: built by the package, not by users (their methods are entry points)
RESULTS = {
    "AmplitudeResponse", "Comparison", "CrossValidation", "FitResult", "FreeResponse",
    "LimitCycles", "LoopBatch", "LoopResult", "MasingCheck", "MeasuredCycle", "MotionBatch",
    "MotionResult", "MotionEnergy", "NetworkEnergy", "NetworkResult", "Prediction",
    "QuasiStaticNetworkResult", "QuasiStaticResponse", "SweepResult", "TurningPoints",
    "FitComparison", "FrequencyResponse", "ModalBackbone", "PeriodicOrbit", "RingDown",
    "StructureMotion", "Segments", "CompiledStructure",
}  # fmt: skip

#: arguments without a unit (counts, options, flags, objects, dimensionless numbers,
#: mappings of fit parameters, column names, generic operator weights)
NOT_QUANTITIES = {
    "A", "B", "C", "D", "abscissa", "anti_windup", "asymmetric", "ax", "axis", "b",
    "bandwidth", "blocks", "bootstrap", "bounds", "burn_in", "chunk_size", "clusters",
    "contacts", "controller", "covariance", "damping_ratios", "decimal", "delimiter",
    "density", "density_cells", "derivative_on", "df", "direction", "elastic_only",
    "envelope", "equal_breakaway", "exponent", "filter_forces", "fit", "fit_initial",
    "fitted", "fixed", "fn", "forcing", "friction", "function", "grid_size", "head",
    "header", "hint", "hold", "initial", "initial_state", "inputs", "interpolate",
    "interpolation_error", "jacobian", "kind", "labels", "last_direction", "level",
    "linear", "load", "loops", "mass_ratio", "max_evaluations", "max_events",
    "max_generations", "max_reversals", "max_sweeps", "measured", "measurement", "method",
    "min_samples", "mode", "mode_shapes", "model", "models", "moments", "multistart", "n",
    "n_elements", "n_masses", "n_nodes", "n_samples", "n_workers", "name", "names",
    "network", "offset", "operator", "operators", "order", "out", "outputs", "path",
    "plant_or_loop", "points", "predicted", "progress", "prune", "purpose", "quantity",
    "records", "refine_thresholds", "residual", "result", "retries", "rotary", "rtol",
    "samples", "samples_per_swing", "scale", "scheduler", "search", "seed", "signal",
    "sliders", "sol", "source", "springs", "stack", "state", "states", "stops", "structure",
    "substeps", "system", "theta", "tied", "tolerance", "units", "value", "values_of",
    "verify", "virgin_model", "weight", "weights", "against", "backbone", "candidates",
    "coordinate", "criterion", "cycles", "data", "definition", "fitter", "floor", "harmonics",
    "hold_out", "index", "joint", "joints", "max_points", "replace", "samples_per_period",
    "scales", "tol", "stribeck_exponent", "slipping", "sparse", "creep", "family",
}  # fmt: skip

#: (entry point, argument) whose meaning differs from the argument's name elsewhere
OVERRIDES: dict[tuple[str, str], str | None] = {
    ("sweep", "grid"): None,  # a mapping of parameter names to values
    ("fit_response", "velocity"): None,  # "auto", "difference" or "measured"
    ("Measurement.from_csv", "time"): None,  # the time column's name or index
    ("Measurement.from_dataframe", "time"): None,
    ("Measurement.from_mat", "time"): None,
    ("count_reversals", "tolerance"): "position",
    ("fit_presliding", "coulomb"): None,  # fit a Coulomb element or not
    ("iosys_state", "mass"): None,  # any value: the mass system's layout
    ("modal_backbone", "amplitudes"): "modal amplitude",  # of a mass-normalised mode
    ("simulate_ring_down", "amplitude"): "modal amplitude",
    ("frequency_response", "scale"): None,  # the force's scale s, a pure number
    ("simulate_ring_down", "start"): None,  # "impulse" or "deflection"
    ("fit_motion", "viscous"): None,  # fit a viscous term or not
    ("fit_response", "viscous"): None,
    ("Measurement.segments", "tolerance"): "position",
}


def entry_points() -> dict[str, Callable[..., Any]]:
    """Every public callable: functions, constructors (results aside), public methods."""
    out: dict[str, Callable[..., Any]] = {}
    for name in ps.__all__:
        obj = getattr(ps, name)
        if inspect.isclass(obj):
            if name not in RESULTS:
                out[name] = obj
            for attr in dir(obj):
                if attr.startswith("_") or (issubclass(obj, tuple) and attr in ("count", "index")):
                    continue
                if isinstance(inspect.getattr_static(obj, attr), property):
                    continue
                member = getattr(obj, attr)
                if callable(member) and not inspect.isclass(member):
                    out[f"{name}.{attr}"] = member
        elif callable(obj) and not inspect.ismodule(obj):
            out[name] = obj
    return out


def arguments(func: Callable[..., Any]) -> list[str]:
    try:
        sig = inspect.signature(func)
    except (TypeError, ValueError):
        return []
    skip = (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD)
    return [p.name for p in sig.parameters.values() if p.kind not in skip and p.name != "self"]


def kind_of(entry: str, arg: str) -> str | None:
    return OVERRIDES[(entry, arg)] if (entry, arg) in OVERRIDES else QUANTITY_KINDS.get(arg)


ENTRIES = entry_points()
PHYSICAL = {
    entry: [a for a in arguments(f) if kind_of(entry, a) is not None]
    for entry, f in ENTRIES.items()
}
PHYSICAL = {e: args for e, args in PHYSICAL.items() if args}


def test_every_argument_is_classified():
    unknown = sorted(
        {
            f"{entry}({arg})"
            for entry, f in ENTRIES.items()
            for arg in arguments(f)
            if arg not in QUANTITY_KINDS and arg not in NOT_QUANTITIES
            and (entry, arg) not in OVERRIDES
        }
    )  # fmt: skip
    assert unknown == [], (
        "classify these arguments: a unit in presliding._interop.QUANTITY_KINDS (and convert "
        "them through presliding._validation), or none in NOT_QUANTITIES"
    )
    assert len(ENTRIES) > 250 and len(PHYSICAL) > 150


# ---------------------------------------------------------------- example calls
MODEL = ps.PIFriction(0.5, [500.0, 10.0, 4.0], [1.0, 1.0, 1.0])
Y = ps.signals.piecewise_linear([0.0, 0.3, -0.3, 0.1], step=1e-2)
T = np.linspace(0.0, 1.0, Y.shape[0])
DENSITIES = {
    "Discrete": ps.Discrete([500.0, 10.0], [2e-3, 0.1]),
    "Uniform": ps.Uniform(height=3.5e7, max_threshold=2e-4),
    "Exponential": ps.Exponential(height=7e7, length=1e-4),
    "PiecewiseConstant": ps.PiecewiseConstant([0.0, 1e-4, 2e-4], [3e7, 1e7]),
    "SegalmanIwan": ps.SegalmanIwan(1e6, 100.0, -0.5, 0.1),
    "MindlinContact": ps.MindlinContact(10.0, 1e-5),
    "MicroslipBar": ps.MicroslipBar(1e7, 1e3, 0.1),
}
DENSITIES["Tabulated"] = ps.Density.from_function(lambda r: 1e7 * (1.0 - r / 1e-3), 1e-3)


def _records() -> list[ps.Measurement]:
    truth = ps.PIFriction(coulomb=0.3, stiffness=[4000.0, 1000.0], breakaway=[0.35, 0.35])
    t = np.arange(200) * 1e-3
    res = ps.simulate(truth, 2.0, applied_force=(t, np.where(t < 0.05, -0.3, 0.0)),
                      initial_velocity=0.03, t_eval=t)  # fmt: skip
    return [ps.Measurement(t, position=res.position, applied_force=res.applied_force)]


def _calls(folder: Any) -> dict[str, tuple[Callable[..., Any], dict[str, Any]]]:
    """Entry point -> (callable, keyword arguments of a valid call); a variant of an entry
    point for arguments one call cannot take together is named ``"entry (variant)"``."""
    import pandas as pd
    import scipy.io

    csv, mat = folder / "y.csv", folder / "y.mat"
    np.savetxt(csv, Y, header="y", comments="")
    scipy.io.savemat(mat, {"y": Y})
    pid = ps.PID(400.0, 4e4, 0.0, dt=1e-3, limit=5.0)
    loop = ps.simulate_loop(MODEL, 1.0, pid, reference=1e-3, t_end=0.05)
    meas = ps.Measurement(T, position=Y, applied_force=MODEL.force(Y)[0])
    records = _records()
    lugre = ps.LuGreFriction(1.0, 1.5, 1e5, 300.0, 0.4, 0.01)
    gms = ps.GMSFriction(0.2, [1e4, 2e3], [0.3, 0.3], static_level=1.2,
                         stribeck_velocity=1e-3, lag_time=5e-3)  # fmt: skip
    creeping = ps.CreepingFriction(MODEL, 2e-6, 0.1)
    operator = ps.PIOperator([1e-3, 2e-3], [500.0, 10.0])
    gpi = ps.GeneralPIOperator(DENSITIES["Uniform"])
    batch = ps.PIBatch([[1e-3, 2e-3]], [[500.0, 10.0]])
    inverse = ps.PIInverse(operator, coulomb=0.1)
    net = ps.SliderNetwork.chain([100.0, 50.0], [0.0, 1.0, 0.5])
    jenkins = ps.PIFriction(0.0, [20.0], breakaway=[1.0])
    one = ps.JointedStructure(1.0, 3.0, [[1.0]], [jenkins], damping=0.01)
    compiled = ps.compile_structure([[3.0]], [[1.0]], [jenkins], [1.0])
    decay = ps.simulate_ring_down(one, 0, 0.1, 60.0)
    chain = ps.chain_structure(2, 1.0, 1000.0, MODEL)
    state = MODEL.relaxed_state()
    calls: dict[str, tuple[Callable[..., Any], dict[str, Any]]] = {
        "PID": (ps.PID, dict(kp=400.0, ki=4e4, kd=1.0, dt=1e-3, filter_time=1e-3, limit=5.0,
                             tracking_time=1e-2)),
        "PID.with_gains": (pid.with_gains, dict(kp=300.0, ki=3e4, kd=1.0)),
        "DiscreteController": (ps.DiscreteController, dict(A=[[1.0]], B=[[1e-3]], C=[[4e4]],
                                                           D=[[400.0]], dt=1e-3, limit=5.0)),
        "DiscreteController.from_lti": (ps.DiscreteController.from_lti,
                                        dict(system=__import__("control").ss(
                                            [[1.0]], [[1e-3]], [[4e4]], [[400.0]], 1e-3),
                                            limit=5.0)),
        "to_iosys": (ps.to_iosys, dict(model=MODEL, mass=1.0, dt=1e-3)),
        "iosys_state": (ps.iosys_state, dict(model=MODEL, mass=1.0, position=0.1, velocity=0.2)),
        "simulate_loop": (ps.simulate_loop, dict(model=MODEL, mass=1.0, controller=pid,
                                                 reference=1e-3, t_end=0.01, feedforward=0.0,
                                                 initial_position=0.0, initial_velocity=0.0,
                                                 t_start=0.0)),
        "simulate_loop_batch": (ps.simulate_loop_batch, dict(
            model=MODEL, mass=1.0, controller=pid, reference=1e-3, kp=[300.0], ki=[3e4],
            kd=[0.0], t_end=0.01, feedforward=0.0, initial_position=0.0, initial_velocity=0.0,
            settle_time=0.0, t_start=0.0)),
        "LoopResult.limit_cycle": (loop.limit_cycle, dict(after=0.01)),
        "measure_limit_cycle": (ps.measure_limit_cycle, dict(
            reversal_times=loop.reversal_times, reversal_positions=loop.reversal_positions,
            after=0.0)),
        "describing_function": (ps.describing_function, dict(model=MODEL, amplitude=0.2)),
        "FrictionNonlinearity.describing_function": (
            ps.FrictionNonlinearity(MODEL).describing_function, dict(amplitude=0.2)),
        "predict_limit_cycles": (ps.predict_limit_cycles, dict(
            plant_or_loop=__import__("control").tf([1.0], [1.0, 0.0, 0.0]), model=MODEL,
            controller=pid, amplitudes=(1e-5, 1e-2), frequencies=(1.0, 1e3), points=20)),
        "amplitude_response": (ps.amplitude_response, dict(model=MODEL, amplitudes=[0.1, 0.2])),
        "turning_points": (ps.turning_points, dict(model=MODEL, mass=1.0, initial_velocity=0.8,
                                                   initial_position=0.0)),
        "total_energy": (ps.total_energy, dict(model=MODEL, mass=1.0, velocity=0.5, state=state)),
        "phi": (ps.phi, dict(model=MODEL, displacement=0.1)),
        "dissipated_energy": (ps.dissipated_energy, dict(model=MODEL, displacement=Y)),
        "viscous_dissipation": (ps.viscous_dissipation, dict(model=MODEL, time=T, velocity=Y)),
        "compare": (ps.compare, dict(models={"pi": MODEL}, displacement=Y, time=T)),
        "count_reversals": (ps.count_reversals, dict(position=Y, tolerance=1e-3)),
        "reversal_tolerance": (ps.reversal_tolerance, dict(position=Y)),
        "preloaded_state": (ps.preloaded_state, dict(model=MODEL, elastic_force=0.5,
                                                     position=0.0)),
        "simulate": (ps.simulate, dict(model=MODEL, mass=1.0, applied_force=(T, 0.2 * T),
                                       initial_position=0.0, initial_velocity=0.1, t_end=1.0,
                                       t_eval=T, t_start=0.0)),
        "simulate_batch": (ps.simulate_batch, dict(
            coulomb=[0.5], stiffness=[[500.0]], breakaway=[[1.0]], mass=1.0,
            initial_velocity=0.1, viscous=0.0, applied_force=0.0, initial_position=0.0,
            t_end=1.0, t_eval=T, t_start=0.0)),
        "free_response": (ps.free_response, dict(
            mass=1.0, coulomb=0.5, stiffness=[500.0], threshold=[2e-3], initial_velocity=0.1,
            time_step=1e-3, n_samples=10, initial_position=0.0, applied_force=0.0,
            viscous=0.0)),
        "quasi_static_response": (ps.quasi_static_response, dict(model=MODEL,
                                                                 applied_force=0.5 * Y, time=T)),
        "fit_presliding": (ps.fit_presliding, dict(displacement=Y, force=MODEL.force(Y)[0],
                                                   n_elements=2, thresholds=None)),
        "fit_virgin_curve": (ps.fit_virgin_curve, dict(displacement=Y, force=MODEL.force(Y)[0],
                                                       n_elements=2)),
        "fit_motion": (ps.fit_motion, dict(measurement=records[0].differentiate(50.0), n_elements=1,
                                           viscous=True, min_speed=1e-3)),
        "fit_response": (ps.fit_response, dict(records=records, n_elements=1, mass=2.0,
                                               signal="position")),
        "fit_quasi_static": (ps.fit_quasi_static, dict(records=records, n_elements=1)),
        "cross_validate": (ps.cross_validate, dict(records=records * 2)),
        "masing_check": (ps.masing_check, dict(virgin_model=MODEL, loops=(Y, MODEL.force(Y)[0]))),
        "Measurement": (ps.Measurement, dict(time=T, position=Y, velocity=Y, acceleration=Y,
                                             applied_force=Y, friction_force=Y)),
        "Measurement.window": (meas.window, dict(start=0.1, end=0.9)),
        "Measurement.resample": (meas.resample, dict(step=0.01)),
        "Measurement.differentiate": (meas.differentiate, dict(cutoff=5.0)),
        "Measurement.segments": (meas.segments, dict(kind="loops", tolerance=1e-3)),
        "Measurement.segments (stops)": (records[0].segments, dict(kind="stops", lead_in=0.01,
                                                                   rest_speed=1e-3)),
        "Measurement.from_csv": (ps.Measurement.from_csv, dict(path=csv, sample_rate=1000.0,
                                                               position="y")),
        "Measurement.from_dataframe": (ps.Measurement.from_dataframe, dict(
            df=pd.DataFrame({"y": Y}), sample_rate=1000.0, position="y")),
        "Measurement.from_mat": (ps.Measurement.from_mat, dict(path=mat, sample_rate=1000.0,
                                                               position="y")),
        "PIFriction": (ps.PIFriction, dict(coulomb=0.5, stiffness=[500.0], breakaway=[1.0],
                                           viscous=0.1, coulomb_negative=0.4,
                                           breakaway_negative=[0.8], viscous_negative=0.1)),
        "PIOperator": (ps.PIOperator, dict(threshold=[1e-3], weight=[1.0])),
        "PIBatch": (ps.PIBatch, dict(threshold=[[1e-3]], weight=[[1.0]], coulomb=[0.1])),
        "PIInverse": (ps.PIInverse, dict(operator=operator, coulomb=0.1)),
        "PIInverse.apply": (inverse.apply, dict(force=[0.0, 0.2, 0.1])),
        "PIInverse.elastic_force": (inverse.elastic_force, dict(force=[0.0, 0.2, 0.1])),
        "PIInverse.relaxed_state": (inverse.relaxed_state, dict(position=0.1)),
        "PIOperator.apply": (operator.apply, dict(y=Y)),
        "play": (ps.play, dict(y=Y, threshold=[1e-3, 2e-3])),
        "stop": (ps.stop, dict(y=Y, threshold=[1e-3, 2e-3])),
        "PIOperator.relaxed_state": (operator.relaxed_state, dict(position=0.1)),
        "PIBatch.apply": (batch.apply, dict(y=Y)),
        "PIBatch.relaxed_state": (batch.relaxed_state, dict(position=0.1)),
        "PIState": (ps.PIState, dict(last_input=0.0, play=[0.0, 0.0])),
        "PIBatchState": (ps.PIBatchState, dict(last_input=0.0, play=[[0.0]])),
        "PIState.relaxed": (ps.PIState.relaxed, dict(n_elements=2, position=0.1)),
        "PIState.saturated": (ps.PIState.saturated, dict(threshold=[1e-3], position=0.1,
                                                         direction=1.0)),
        "PIState.check_against": (state.check_against, dict(threshold=MODEL.threshold)),
        "PIFriction.force": (MODEL.force, dict(displacement=Y)),
        "PIFriction.elastic_force": (MODEL.elastic_force, dict(displacement=Y)),
        "PIFriction.virgin_curve": (MODEL.virgin_curve, dict(displacement=Y)),
        "PIFriction.relaxed_state": (MODEL.relaxed_state, dict(position=0.1)),
        "PIFriction.saturated_state": (MODEL.saturated_state, dict(position=0.1,
                                                                   direction=1.0)),
        "PIFriction.steady_force": (MODEL.steady_force, dict(velocity=[0.1, -0.1])),
        "PIFriction.viscous_force": (MODEL.viscous_force, dict(velocity=[0.1, -0.1])),
        "GeneralPIOperator.apply": (gpi.apply, dict(y=Y * 1e-3)),
        "GeneralPIOperator.force_at": (gpi.force_at, dict(y=1e-4,
                                                          state=gpi.relaxed_state())),
        "GeneralPIOperator.relaxed_state": (gpi.relaxed_state, dict(position=0.1)),
        "GeneralPIOperator.saturated_state": (gpi.saturated_state, dict(position=0.1,
                                                                        direction=1.0)),
        "MemoryState": (ps.MemoryState, dict(last_input=0.0, turning=[], base=0.0)),
        "MemoryState.relaxed": (ps.MemoryState.relaxed, dict(position=0.1)),
        "MemoryState.saturated": (ps.MemoryState.saturated, dict(position=0.1, direction=1.0,
                                                                 max_threshold=1e-3)),
        "MemoryState.deformation": (ps.MemoryState.relaxed(0.0).deformation,
                                    dict(threshold=[1e-4])),
        "MemoryState.play": (ps.MemoryState.relaxed(0.0).play, dict(threshold=[1e-4])),
        "CoulombFriction": (ps.CoulombFriction, dict(coulomb=0.5)),
        "CoulombFriction.force": (ps.CoulombFriction(0.5).force, dict(displacement=Y)),
        "DahlFriction": (ps.DahlFriction, dict(coulomb=0.5, stiffness=500.0)),
        "DahlFriction.force": (ps.DahlFriction(0.5, 500.0).force, dict(displacement=Y)),
        "DahlFriction.relaxed_state": (ps.DahlFriction(0.5, 500.0).relaxed_state,
                                       dict(position=0.1)),
        "DahlState": (ps.DahlState, dict(last_input=0.0, force=0.1)),
        "LuGreFriction": (ps.LuGreFriction, dict(coulomb=1.0, static=1.5, stiffness=1e5,
                                                 damping=300.0, viscous=0.4,
                                                 stribeck_velocity=0.01)),
        "LuGreFriction.force": (lugre.force, dict(displacement=Y, time=T)),
        "LuGreFriction.relaxed_state": (lugre.relaxed_state, dict(position=0.1, time=0.0)),
        "LuGreFriction.steady_state_force": (lugre.steady_state_force, dict(velocity=0.1)),
        "LuGreFriction.stribeck": (lugre.stribeck, dict(velocity=0.1)),
        "LuGreState": (ps.LuGreState, dict(last_input=0.0, last_time=0.0, bristle=0.0,
                                           velocity=0.0)),
        "GMSFriction": (ps.GMSFriction, dict(coulomb=0.2, stiffness=[1e4, 2e3],
                                             breakaway=[0.3, 0.3], static_level=1.2,
                                             stribeck_velocity=1e-3, lag_time=5e-3,
                                             viscous=0.1)),
        "GMSFriction.force": (gms.force, dict(displacement=1e-3 * Y, time=T)),
        "GMSFriction.relaxed_state": (gms.relaxed_state, dict(position=0.1, time=0.5)),
        "GMSFriction.saturated_state": (gms.saturated_state, dict(position=0.1, time=0.5,
                                                                  direction=-1.0,
                                                                  velocity=-1e-3)),
        "GMSFriction.steady_force": (gms.steady_force, dict(velocity=[1e-3, -1e-3])),
        "GMSFriction.stribeck": (gms.stribeck, dict(velocity=[1e-3, -1e-3])),
        "GMSState": (ps.GMSState, dict(last_input=0.0, last_time=0.0, forces=[0.1, -0.3],
                                       slipping=[0.0, -1.0], velocity=-1e-3,
                                       direction=-1.0)),
        "CreepingFriction": (ps.CreepingFriction, dict(friction=MODEL, compliance=2e-6,
                                                       creep_time=0.1)),
        "quasi_static_response (creep)": (ps.quasi_static_response, dict(
            model=creeping, applied_force=0.5 * Y, time=T, initial_creep=1e-7)),
        "Tabulated": None,  # built by Tabulated.build / Density.from_function
        "Tabulated.build": (ps.Tabulated.build, dict(function=lambda r: 1e7, max_threshold=1e-3,
                                                     rtol=1e-6)),
        "SliderNetwork.chain": (ps.SliderNetwork.chain, dict(stiffness=[100.0, 50.0],
                                                             slip_force=[0.0, 1.0, 0.5])),
        "quasi_static_network": (ps.quasi_static_network, dict(
            network=net, displacement={2: [0.0, 0.1, -0.1]})),
        "quasi_static_network (force)": (ps.quasi_static_network, dict(
            network=net, displacement={0: [0.0, 0.0, 0.0]}, force={2: [0.0, 0.5, -0.5]})),
        "chain_structure": (ps.chain_structure, dict(n_masses=2, mass=1.0, spring=1000.0,
                                                     friction=MODEL, damping=0.1)),
        "multi_contact_structure": (ps.multi_contact_structure, dict(
            mass=1.0, stiffness=1000.0, friction=[MODEL, MODEL], damping=0.1)),
        "modal_structure": (ps.modal_structure, dict(frequencies=[10.0], mode_shapes=[[1.0]],
                                                     friction=MODEL)),
        "NetworkStructure": (ps.NetworkStructure, dict(mass=[[1.0]], stiffness=[[1000.0]],
                                                       contacts=[[1.0]], friction=(MODEL,),
                                                       damping=[[0.1]])),
        "NetworkStructure.force_at": (chain.force_at, dict(t=0.1)),
        "NetworkState": None,  # made by simulate_network (a result's memory)
        "simulate_network": (ps.simulate_network, dict(structure=chain, t_end=0.05,
                                                       initial_position=[0.0, 0.0],
                                                       initial_velocity=[0.3, -0.2],
                                                       t_eval=[0.0, 0.05], t_start=0.0)),
        "simulate_network_moreau": (ps.simulate_network_moreau, dict(
            structure=chain, t_end=0.01, step=1e-3, initial_position=[0.0, 0.0],
            initial_velocity=[0.3, -0.2], t_start=0.0)),
        # the structural layer: one mass on a spring with a Jenkins joint
        "JointedStructure": (ps.JointedStructure, dict(mass=1.0, stiffness=3.0, contacts=[[1.0]],
                                                       joints=[jenkins], damping=0.01)),
        "JointedStructure.modal": (ps.JointedStructure.modal, dict(
            frequencies=[2.0], mode_shapes=[[1.0]], joints=jenkins)),
        "compile_structure": (ps.compile_structure, dict(stiffness=[[3.0]], contacts=[[1.0]],
                                                         friction=[jenkins], load=[1.0])),
        "CompiledStructure.deflection": (compiled.deflection, dict(displacement=[0.01, 0.1])),
        "CompiledStructure.force": (compiled.force, dict(displacement=[0.01, 0.1])),
        "CompiledStructure.virgin_curve": (compiled.virgin_curve,
                                           dict(displacement=[0.01, 0.1])),
        "modal_backbone": (ps.modal_backbone, dict(structure=one, mode=0,
                                                   amplitudes=[0.01, 0.1])),
        "simulate_structure": (ps.simulate_structure, dict(
            structure=one, t_end=1.0, initial_position=[0.0], initial_velocity=[0.1],
            force=[0.1], frequency=2.0, plastic=[0.0], t_eval=[0.0, 1.0])),
        "simulate_ring_down": (ps.simulate_ring_down, dict(structure=one, mode=0, amplitude=0.1,
                                                           duration=2.0)),
        "analyze_ring_down": (ps.analyze_ring_down, dict(data=decay, method="peaks",
                                                         frequency=2.0, band=(1.0, 3.0),
                                                         trim=1.0)),
        "periodic_orbit": (ps.periodic_orbit, dict(structure=one, force=[0.5], frequency=2.0)),
        "frequency_response": (ps.frequency_response, dict(structure=one, force=[0.5],
                                                           frequencies=(1.9, 2.1), step=0.5,
                                                           max_points=3)),
        "force_response": (ps.force_response, dict(structure=one, force=[0.5], frequency=2.0,
                                                   scales=(1.0, 1.2), step=0.5, max_points=3)),
    }  # fmt: skip
    for name, density in [*DENSITIES.items(), ("Density", DENSITIES["Discrete"])]:
        calls[name] = {
            "Density": None,
            "Discrete": (ps.Discrete, dict(stiffness=[500.0], threshold=[1e-3])),
            "Uniform": (ps.Uniform, dict(height=3.5e7, max_threshold=2e-4)),
            "Exponential": (ps.Exponential, dict(height=7e7, length=1e-4, max_threshold=1e-3)),
            "PiecewiseConstant": (ps.PiecewiseConstant, dict(breaks=[0.0, 1e-4], heights=[3e7])),
            "SegalmanIwan": (
                ps.SegalmanIwan,
                dict(stiffness=1e6, slip_force=100.0, exponent=-0.5, mass_ratio=0.1),
            ),
            "MindlinContact": (ps.MindlinContact, dict(slip_force=10.0, slip_displacement=1e-5)),
            "MicroslipBar": (
                ps.MicroslipBar,
                dict(axial_stiffness=1e7, shear_strength=1e3, length=0.1),
            ),
            "Tabulated": None,
        }[name]
        for method in ("M0", "M1", "M2", "tail"):
            calls[f"{name}.{method}"] = (getattr(density, method), dict(r=[1e-6, 1e-5]))
        calls[f"{name}.virgin_curve"] = (density.virgin_curve, dict(displacement=[0.0, 1e-5]))
        big_r = density.max_threshold if np.isfinite(density.max_threshold) else 1e-3
        if name != "MicroslipBar":
            calls[f"{name}.discretize"] = (density.discretize, dict(n=4, max_threshold=big_r))
        calls[f"{name}.from_function"] = (
            getattr(ps, name).from_function,
            dict(function=lambda r: 1e7, max_threshold=1e-3),
        )
    calls["SegalmanIwan.loop_energy"] = (
        DENSITIES["SegalmanIwan"].loop_energy,
        dict(amplitude=1e-5),
    )
    for name in ("MindlinContact", "MicroslipBar"):
        calls[f"{name}.loop_energy_at_force"] = (
            DENSITIES[name].loop_energy_at_force,
            dict(force_amplitude=1.0),
        )
    return {k: v for k, v in calls.items() if v is not None}


#: entry points whose example call is too slow to repeat per argument (fits; their
#: arguments are still refused in another dimension, before any work)
SLOW = {"fit_presliding", "fit_virgin_curve", "fit_motion", "fit_response",
        "fit_quasi_static", "cross_validate", "simulate_network_moreau", "Tabulated.build",
        "simulate_loop_batch", "predict_limit_cycles", "periodic_orbit", "frequency_response",
        "force_response", "analyze_ring_down"}  # fmt: skip
#: a unit of another dimension for each kind
OTHER = {"position": "s", "time": "m", "frequency": "m", "angular frequency": "m"}
#: arguments given instead of another (the other one is left out of the example)
INSTEAD = {"threshold": "breakaway", "threshold_negative": "breakaway_negative"}
#: not converted yet (strict: a fix makes these fail)
GAPS: set[tuple[str, str]] = set()


@pytest.fixture(scope="module")
def calls(tmp_path_factory):
    return _calls(tmp_path_factory.mktemp("records"))


def test_every_entry_point_with_a_quantity_has_an_example(calls):
    # built by the package; the bar's μ([0, r]) is infinite for every r (no finite cells)
    exempt = {"Tabulated", "NetworkState", "MicroslipBar.discretize"}
    missing = sorted(set(PHYSICAL) - {name.split(" (")[0] for name in calls} - exempt)
    assert missing == [], "add an example call to _calls()"


def test_the_examples_run(calls):
    for name, (func, kwargs) in calls.items():
        if name.split(" (")[0] not in SLOW:
            func(**kwargs)


def _example(calls: dict, entry: str, arg: str) -> tuple[Callable[..., Any], dict[str, Any]]:
    """The example of `entry` that passes `arg` (else its first), without the argument
    `arg` replaces."""
    named = [k for k in calls if k == entry or k.startswith(f"{entry} (")]
    func, kwargs = next((calls[k] for k in named if arg in calls[k][1]), calls[named[0]])
    return func, {k: v for k, v in kwargs.items() if k != INSTEAD.get(arg)}


def _cases() -> list[Any]:
    return [
        pytest.param(entry, arg, marks=pytest.mark.xfail(strict=True, reason="network layer"))
        if (entry, arg) in GAPS else (entry, arg)
        for entry, args in sorted(PHYSICAL.items()) for arg in args
        if entry not in ("Tabulated", "NetworkState", "MicroslipBar.discretize")
    ]  # fmt: skip


@pytest.mark.parametrize(("entry", "arg"), _cases())
def test_a_quantity_of_another_dimension_is_refused_naming_the_argument(calls, entry, arg):
    func, kwargs = _example(calls, entry, arg)
    kind = kind_of(entry, arg)
    wrong = Q(1.0, OTHER.get(kind, "s"))
    given = kwargs.get(arg)
    value = {node: wrong * np.ones(3) for node in given} if isinstance(given, dict) else wrong
    # the generic wording; a Measurement reads its signals' units as it reads a file's
    message = rf"`{arg}[^`]*` must be a {kind} \(a Quantity in|of `{arg}`: the unit '.*' is not a"
    with pytest.raises(ValueError, match=message):
        func(**{**kwargs, arg: value})


@pytest.mark.parametrize(("entry", "arg"), _cases())
def test_a_quantity_in_si_is_taken_as_the_number(calls, entry, arg):
    func, kwargs = _example(calls, entry, arg)
    if entry in SLOW or kwargs.get(arg) is None or isinstance(kwargs[arg], dict):
        pytest.skip("checked by its refusal only")
    unit = SI_UNITS[kind_of(entry, arg)][0]
    value = kwargs[arg]
    if isinstance(value, tuple):  # (times, values) of a force signal
        value = (value[0], Q(np.asarray(value[1]), unit))
    else:
        value = Q(np.asarray(value, dtype=float), unit)
    func(**{**kwargs, arg: value})


def test_quantities_in_other_units_give_what_si_numbers_give():
    """The cases that refused Quantities, in units other than SI (mm, ms, g, mN)."""
    model = ps.PIFriction(coulomb=Q(0.5, "N"), stiffness=Q([0.5, 0.01, 0.004], "N/mm"),
                          breakaway=Q([1e3, 1e3, 1e3], "mN"))  # fmt: skip
    assert model == MODEL
    assert ps.PIFriction(0.5, [500.0], threshold=Q([2.0], "mm")).threshold[0] == 2e-3
    tp = ps.turning_points(MODEL, mass=Q(1000.0, "g"), initial_velocity=Q(800.0, "mm/s"))
    assert tp.positions == pytest.approx(ps.turning_points(MODEL, 1.0, 0.8).positions, 1e-14)
    pid = ps.PID(Q(0.4, "N/mm"), Q(4e4, "N/m/s"), Q(1.0, "N*s/m"), dt=Q(1.0, "ms"),
                 limit=Q(5000.0, "mN"))  # fmt: skip
    assert pid.parameters() == pytest.approx(ps.PID(400.0, 4e4, 1.0, dt=1e-3,
                                                    limit=5.0).parameters(), 1e-14)  # fmt: skip
    assert ps.to_iosys(pid).dt == pytest.approx(1e-3, 1e-15)
    assert ps.to_iosys(MODEL, mass=Q(1.0, "kg"), dt=Q(2.0, "ms")).dt == pytest.approx(2e-3)
    got = ps.amplitude_response(MODEL, Q([100.0, 200.0], "mm"))
    want = ps.amplitude_response(MODEL, [0.1, 0.2])
    assert got.dissipation == pytest.approx(want.dissipation, 1e-14)
    df = ps.describing_function(MODEL, Q(200.0, "mm"))
    assert df == pytest.approx(ps.describing_function(MODEL, 0.2), 1e-14)
    y_mm = Q(Y * 1e3, "mm")
    force = MODEL.force(Y)[0]
    fit = ps.fit_presliding(y_mm, Q(force * 1e3, "mN"), n_elements=2)
    plain = ps.fit_presliding(Y, force, n_elements=2)
    assert fit.parameters == pytest.approx(plain.parameters, rel=1e-9)


def test_the_rate_models_in_other_units_give_what_si_numbers_give():
    """GMS, creep and their states in mN, N/mm, ms, mm/s and µm/N: the SI model's numbers."""
    si = ps.GMSFriction(0.2, [1e4, 2e3], [0.3, 0.3], static_level=1.2, stribeck_velocity=1e-3,
                        lag_time=5e-3, viscous=0.1)  # fmt: skip
    gms = ps.GMSFriction(Q(200.0, "mN"), Q([10.0, 2.0], "N/mm"), Q([300.0, 300.0], "mN"),
                         static_level=Q(1200.0, "mN"), stribeck_velocity=Q(1.0, "mm/s"),
                         lag_time=Q(5.0, "ms"), viscous=Q(1e-4, "N*s/mm"))  # fmt: skip
    assert repr(gms) == repr(si)
    y, t = 1e-3 * Y, T
    want, _ = si.force(y, t)
    got, _ = gms.force(Q(y * 1e3, "mm"), Q(t * 1e3, "ms"))
    assert got == pytest.approx(want, rel=1e-12, abs=1e-15)
    assert gms.steady_force(Q([1.0, -2.0], "mm/s")) == pytest.approx(
        si.steady_force([1e-3, -2e-3]), rel=1e-14)  # fmt: skip
    state = gms.saturated_state(Q(100.0, "mm"), Q(500.0, "ms"), -1.0, Q(-1.0, "mm/s"))
    plain = si.saturated_state(0.1, 0.5, -1.0, -1e-3)
    assert (state.last_input, state.last_time, state.velocity) == pytest.approx((0.1, 0.5, -1e-3))
    assert state.forces == pytest.approx(plain.forces, rel=1e-14)
    assert ps.GMSState(Q(1.0, "mm"), Q(2.0, "ms"), Q([100.0], "mN"), [0.0]).forces[0] == 0.1
    creeping = ps.CreepingFriction(MODEL, Q(2.0, "um/N"), Q(100.0, "ms"))
    assert (creeping.compliance, creeping.creep_time) == pytest.approx((2e-6, 0.1), rel=1e-14)
    u = 0.5 * Y
    a = ps.quasi_static_response(creeping, u, time=T, initial_creep=Q(0.1, "um"))
    b = ps.quasi_static_response(ps.CreepingFriction(MODEL, 2e-6, 0.1), u, time=T,
                                 initial_creep=1e-7)  # fmt: skip
    assert a.position == pytest.approx(b.position, rel=1e-12, abs=1e-18)
    with pytest.raises(ValueError, match=r"`initial_creep` must be a position \(a Quantity"):
        ps.quasi_static_response(creeping, u, time=T, initial_creep=Q(1.0, "s"))
