"""Model files: round trip, schema errors naming file and field, no overwriting."""

import json

import numpy as np
import pytest

from presliding import PIFriction
from presliding.hysteresis.densities import Exponential, PiecewiseConstant, Uniform
from presliding.model_io import (
    MeasurementTerms,
    MotionSettings,
    load_model,
    model_to_toml,
    save_model,
)


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_round_trip_toml(tmp_path):
    model = PIFriction(0.5, [500.0, 10.0, 4.0], [1.0, 0.75, 1.25])
    motion = MotionSettings(mass=2.0, initial_velocity=-1.5, t_end=3.0, samples=11)
    path = tmp_path / "m.toml"
    save_model(path, model, motion)
    loaded = load_model(path)
    assert loaded.model == model
    assert loaded.motion == motion


def test_threshold_form_and_json(tmp_path):
    data = {"friction": {"coulomb": 1.0, "stiffness": [10.0, 4.0], "threshold": [0.1, 0.25]}}
    path = _write(tmp_path, "m.json", json.dumps(data))
    model = load_model(path).model
    np.testing.assert_allclose(model.breakaway, [1.0, 1.0])
    assert load_model(path).motion == MotionSettings()


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[friction]\ncoulomb = 1.0\nstifness = [1.0]\n", "friction.stifness"),
        ("[motion]\nmass = 1.0\n", "missing table `friction`"),
        ("[friction]\nstiffness = [1.0]\nbreakaway = [1.0]\n", "friction.coulomb"),
        ("[friction]\ncoulomb = 1.0\nstiffness = [-1.0]\nbreakaway = [1.0]\n", "`stiffness`"),
        ("[friction]\ncoulomb = 1.0\n[motion]\nmass = -2.0\n", "motion.mass"),
        ("[friction]\ncoulomb = 1.0\n[motion]\nmass = 'heavy'\n", "motion.mass"),
        ("[friction]\ncoulomb = 1.0\n[motion]\nsamples = 2.5\n", "motion.samples"),
        ("[friction]\ncoulomb = 1.0\n[motion]\ninitial_state = 'tired'\n", "initial_state"),
        ("[friction]\ncoulomb = 1.0\n[extra]\n", "unknown table `extra`"),
        ("[friction\ncoulomb = 1.0\n", "not valid TOML"),
        ("[friction]\ncoulomb = 1.0\n[motion]\nt_end = inf\n", "`motion.t_end` must be finite"),
        (
            "[friction]\ncoulomb = 1.0\n[motion]\ninitial_velocity = nan\n",
            "must be finite; got nan",
        ),
        ("[friction]\ncoulomb = 1.0\n[motion]\nmass = inf\n", "`motion.mass` must be finite"),
        ("[friction]\ncoulomb = 1.0\n[motion]\nsamples = 1e12\n", "at most 10,000,000"),
        ("[friction]\ncoulomb = 1.0\n[measurement]\nforce_offset = nan\n", "force_offset"),
        ("[friction]\ncoulomb = 1.0\n[measurement]\noffset = 1.0\n", "measurement.offset"),
    ],
)
def test_schema_errors_name_file_and_field(tmp_path, text, needle):
    path = _write(tmp_path, "bad.toml", text)
    with pytest.raises(ValueError, match=r"bad\.toml") as info:
        load_model(path)
    assert needle in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(ValueError, match="no such file"):
        load_model(tmp_path / "absent.toml")


def test_save_never_overwrites_by_default(tmp_path):
    path = _write(tmp_path, "keep.toml", "original")
    model = PIFriction(1.0)
    with pytest.raises(FileExistsError, match=r"keep\.toml"):
        save_model(path, model)
    assert path.read_text() == "original"
    save_model(path, model, overwrite=True)
    assert load_model(path).model == model


def test_toml_text_states_units():
    text = model_to_toml(PIFriction(0.5, [10.0], [1.0]))
    assert "[N/m]" in text and "c1 [N]" in text


# ---------------------------------------------------------------------- densities (eq. 10)
@pytest.mark.parametrize(
    "make",
    [
        lambda: Uniform(height=3.5e7, max_threshold=2e-4),
        lambda: Exponential(height=7e7, length=1e-4),
        lambda: Exponential(height=7e7, length=1e-4, max_threshold=5e-4),
        lambda: PiecewiseConstant(breaks=[0.0, 1e-4, 3e-4], heights=[2e7, 5e6]),
    ],
    ids=["uniform", "exponential", "truncated", "piecewise"],
)
def test_density_round_trip(tmp_path, make):
    dens = make()
    model = PIFriction(0.1, density=dens)
    path = tmp_path / "d.toml"
    save_model(path, model, MotionSettings(mass=2.0))
    loaded = load_model(path)
    assert loaded.model == model and not loaded.model.is_discrete
    assert loaded.model.max_elastic_force == model.max_elastic_force
    assert "[friction.density]" in path.read_text() and "[N/m^2]" in path.read_text()
    assert loaded.motion.mass == 2.0


def test_density_in_json(tmp_path):
    data = {"friction": {"coulomb": 0.2, "density": {"kind": "uniform", "height": 2.0,
                                                     "max_threshold": 0.5}}}  # fmt: skip
    model = load_model(_write(tmp_path, "d.json", json.dumps(data))).model
    assert model.max_elastic_force == pytest.approx(2.0 * 0.5**2 / 2)


@pytest.mark.parametrize(
    ("density", "needle"),
    [
        ('kind = "gauss"', "friction.density.kind"),
        ('kind = "uniform"\nheight = 1.0', "missing `friction.density.max_threshold`"),
        ('kind = "uniform"\nheight = 1.0\nmax_threshold = 1.0\nlength = 2.0',
         "friction.density.length"),
        ('kind = "uniform"\nheight = -1.0\nmax_threshold = 1.0', "[friction.density] `height`"),
        ('kind = "piecewise_constant"\nbreaks = [0.0, 1.0]\nheights = [1.0, 2.0]', "breaks"),
    ],
)  # fmt: skip
def test_density_errors_name_file_and_field(tmp_path, density, needle):
    path = _write(
        tmp_path, "bad.toml", f"[friction]\ncoulomb = 0.1\n[friction.density]\n{density}\n"
    )
    with pytest.raises(ValueError, match=r"bad\.toml") as info:
        load_model(path)
    assert needle in str(info.value)


def test_density_and_elements_exclude_each_other(tmp_path):
    text = (
        "[friction]\ncoulomb = 0.1\nstiffness = [1.0]\nbreakaway = [1.0]\n"
        '[friction.density]\nkind = "uniform"\nheight = 1.0\nmax_threshold = 1.0\n'
    )
    with pytest.raises(ValueError, match="exclude each other"):
        load_model(_write(tmp_path, "both.toml", text))


def test_tabulated_density_cannot_be_saved(tmp_path):
    from presliding.hysteresis.densities import Density

    model = PIFriction(0.1, density=Density.from_function(lambda r: 1.0 + r, 1.0))
    with pytest.raises(ValueError, match="Tabulated"):
        model_to_toml(model)


def test_measurement_terms_and_header_round_trip(tmp_path):
    model = PIFriction(0.5, [500.0, 10.0], [1.0, 0.75])
    terms = MeasurementTerms(force_offset=-3.16)
    path = tmp_path / "m.toml"
    save_model(path, model, MotionSettings(mass=95.11), measurement=terms,
               header="identified from DATA.mat\nunits: qm [m]")  # fmt: skip
    text = path.read_text()
    assert text.startswith("# identified from DATA.mat\n# units: qm [m]\n")
    assert "force_offset = -3.16  # F_0 [N]" in text
    loaded = load_model(path)
    assert loaded.model == model and loaded.measurement == terms
    assert load_model(_write(tmp_path, "n.toml", "[friction]\ncoulomb = 1.0\n")).measurement == (
        MeasurementTerms(0.0)
    )


def test_a_byte_order_mark_is_skipped(tmp_path):
    for name, text in (("m.toml", "[friction]\ncoulomb = 2.0\n"),
                       ("m.json", '{"friction": {"coulomb": 2.0}}')):  # fmt: skip
        path = tmp_path / name
        path.write_bytes(b"\xef\xbb\xbf" + text.encode())
        assert load_model(path).model.coulomb == 2.0


def test_save_model_needs_a_model(tmp_path):
    with pytest.raises(TypeError, match="`model` must be a PIFriction; got str"):
        save_model(tmp_path / "m.toml", "notamodel")
    assert not (tmp_path / "m.toml").exists()


# ----------------------------------------------------------------------- the viscous term
@pytest.mark.parametrize("sigma", [0.0, 204.1234567890123, 1e-300, 3.0])
def test_viscous_round_trip_is_exact(tmp_path, sigma):
    model = PIFriction(0.5, [500.0, 10.0, 4.0], [1.0, 0.75, 1.25], viscous=sigma)
    path = tmp_path / "m.toml"
    save_model(path, model, MotionSettings(mass=2.0))
    loaded = load_model(path).model
    assert loaded == model and loaded.viscous == sigma
    text = path.read_text(encoding="utf-8")
    assert ("viscous = " in text) == (sigma != 0.0)
    if sigma:
        assert "# σ [N s/m]" in text
    dens = PIFriction(0.5, density=Uniform(2.0, 1.0), viscous=sigma)
    save_model(tmp_path / "d.toml", dens)
    assert load_model(tmp_path / "d.toml").model == dens


def test_viscous_from_toml_and_json_is_simulated(tmp_path):
    from presliding import simulate

    text = (
        "[friction]\ncoulomb = 0.3\nstiffness = [2e4, 5e3]\nbreakaway = [0.2, 0.2]\n"
        "viscous = 12.5\n[motion]\nmass = 1.0\ninitial_velocity = 0.05\n"
        'initial_state = "saturated"\nt_end = 0.2\n'
    )
    spec = load_model(_write(tmp_path, "m.toml", text))
    assert spec.model.viscous == 12.5
    data = {"friction": {"coulomb": 0.3, "stiffness": [2e4, 5e3], "breakaway": [0.2, 0.2],
                         "viscous": 12.5}}  # fmt: skip
    assert load_model(_write(tmp_path, "m.json", json.dumps(data))).model == spec.model
    res = simulate(spec.model, 1.0, initial_velocity=0.05, initial_state="saturated", t_end=0.2)
    plain = simulate(PIFriction(0.3, [2e4, 5e3], [0.2, 0.2]), 1.0, initial_velocity=0.05,
                     initial_state="saturated", t_end=0.2)  # fmt: skip
    assert res.energy.viscous[-1] > 0 and res.stop_time < plain.stop_time


def test_simulate_command_honours_viscous(tmp_path):
    from presliding.cli import main

    text = (
        "[friction]\ncoulomb = 1.0\nviscous = 2.0\n[motion]\nmass = 1.0\n"
        "initial_velocity = 3.0\nt_end = 1.0\nsamples = 5\n"
    )
    path = _write(tmp_path, "m.toml", text)
    assert main(["--quiet", "simulate", str(path), "-o", str(tmp_path / "run")]) == 0
    rows = (tmp_path / "run" / "simulation.csv").read_text(encoding="utf-8").splitlines()
    v = [float(line.split(",")[2]) for line in rows[1:]]
    # m·v̇ = −1 − 2·v: stop at ln(1 + 2·3/1)/2 = 0.973 s, v(0.25) = 3.5·e^{−0.5} − 0.5
    assert v[1] == pytest.approx(3.5 * np.exp(-0.5) - 0.5, rel=1e-12)
    assert v[-1] == 0.0


@pytest.mark.parametrize(
    ("value", "needle"),
    [("-1.0", "`viscous` must be nonnegative"), ("true", "`viscous` must be a real number"),
     ('"fast"', "`viscous` must be a real number"), ("nan", "`viscous` must be finite")],
)  # fmt: skip
def test_bad_viscous_in_a_model_file_names_file_and_field(tmp_path, value, needle):
    path = _write(tmp_path, "m.toml", f"[friction]\ncoulomb = 1.0\nviscous = {value}\n")
    with pytest.raises(ValueError, match=needle) as info:
        load_model(path)
    assert str(path) in str(info.value) and "[friction]" in str(info.value)


def test_long_element_arrays_are_read_exactly_and_by_the_scanner(tmp_path, monkeypatch):
    """Long arrays are read by the compiled scanner, bit for bit what tomllib gives (tomllib
    sees the rest of the file only); an odd form still gets tomllib's error."""
    import presliding.model_io as model_io

    rng = np.random.default_rng(3)
    k, c = rng.uniform(1.0, 1e4, 20_000), rng.uniform(0.01, 1.0, 20_000)
    path = tmp_path / "big.toml"
    model_io.save_model(path, PIFriction(0.3, k, c))
    spec = model_io.load_model(path)
    np.testing.assert_array_equal(spec.model.stiffness, k)
    np.testing.assert_array_equal(spec.model.breakaway, c)
    text = path.read_text(encoding="utf-8")
    parsed = []  # the text tomllib sees: the long arrays are cut out of it
    original = model_io.tomllib.loads
    monkeypatch.setattr(model_io.tomllib, "loads", lambda t: parsed.append(t) or original(t))
    multi = text.replace("stiffness = [", "stiffness = [\n  ").replace("]  # k_j", ",\n]  # k_j")
    assert multi != text
    for variant in (text, multi):
        path.write_text(variant, encoding="utf-8")
        got = model_io.load_model(path).model
        np.testing.assert_array_equal(got.stiffness, k)
        np.testing.assert_array_equal(got.breakaway, c)
    assert len(parsed) == 2 and all(len(t) < 1000 for t in parsed)
    # an empty item is still TOML's error, naming the file
    path.write_text(text.replace(", ", ", , ", 1), encoding="utf-8")
    with pytest.raises(model_io.ModelFileError, match="not valid TOML"):
        model_io.load_model(path)


def test_asymmetric_round_trip(tmp_path):
    model = PIFriction(0.5, [500.0, 10.0], [1.0, 0.75], viscous=2.0, coulomb_negative=0.3,
                       breakaway_negative=[0.5, 1.5], viscous_negative=4.0)  # fmt: skip
    text = model_to_toml(model)
    assert "coulomb_negative = 0.3" in text and "viscous_negative = 4.0" in text
    path = tmp_path / "m.toml"
    save_model(path, model)
    assert load_model(path).model == model
    by_threshold = _write(tmp_path, "t.toml", "[friction]\ncoulomb = 0.5\nstiffness = [100.0]\n"
                          "breakaway = [1.0]\nthreshold_negative = [0.002]\n")  # fmt: skip
    loaded = load_model(by_threshold).model
    assert loaded.coulomb_levels == pytest.approx((1.5, 0.7))
    symmetric = PIFriction(0.5, [500.0, 10.0], [1.0, 0.75])
    assert "negative" not in model_to_toml(symmetric)


def test_fitted_asymmetric_models_round_trip(tmp_path):
    """The models the asymmetric fits return (c1⁻ of fit_presliding; F_c⁻ as a share of every
    level with σ⁻ of the pooled fits) are written and read back unchanged."""
    from presliding import fit_presliding
    from presliding.identification.problem._model_spec import ModelSpec
    from presliding.signals import piecewise_linear

    truth = PIFriction(0.3, [100.0, 40.0], breakaway=[0.32, 0.34], coulomb_negative=0.2)
    path = piecewise_linear([0.0, 0.01, -0.008, 0.006], 2e-4)
    fitted = fit_presliding(path, truth.force(path)[0], 2, asymmetric=True).model
    spec = ModelSpec(2, True, None, 32, asymmetric=True)
    pooled = spec.model({"coulomb": 0.3, "coulomb_level": 1.0, "stiffness_1": 4e3,
                         "stiffness_2": 1e3, "coulomb_level_negative": 0.8, "viscous": 2.0,
                         "viscous_negative": 3.0})  # fmt: skip
    assert not fitted.is_symmetric and not pooled.is_symmetric
    for i, model in enumerate((fitted, pooled)):
        path_i = tmp_path / f"model{i}.toml"
        save_model(path_i, model)
        back = load_model(path_i).model
        assert back.coulomb_levels == model.coulomb_levels
        for name in ("coulomb", "coulomb_negative", "viscous", "viscous_negative"):
            assert getattr(back, name) == getattr(model, name), name
        for name in ("stiffness", "threshold", "threshold_negative"):
            np.testing.assert_array_equal(getattr(back, name), getattr(model, name))


@pytest.mark.parametrize("name", ["model.json", "model.txt"])
def test_a_model_file_is_written_only_under_a_toml_name(tmp_path, name):
    """Before: save_model wrote TOML to model.json, which load_model then read as JSON and
    rejected; now the path is refused before anything is written."""
    with pytest.raises(ValueError, match=r"`path` must name a TOML file .*" + name):
        save_model(tmp_path / name, PIFriction(0.1, [100.0], [0.5]))
    assert not (tmp_path / name).exists()
