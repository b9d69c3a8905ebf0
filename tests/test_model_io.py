"""Model files: round trip, schema errors naming file and field, no overwriting."""

import json

import numpy as np
import pytest

from presliding import PIFriction
from presliding.model_io import MotionSettings, load_model, model_to_toml, save_model


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
