"""The [data] table of a model file: how the records were read, written and read back."""

from __future__ import annotations

import pytest

import presliding as ps
from presliding.model_io import DataSettings, ModelFileError, load_model, save_model

MODEL = ps.PIFriction(0.3, [4000.0], breakaway=[0.35])


def test_the_data_table_round_trips(tmp_path):
    data = DataSettings(
        columns={"time": "Time [s]", "position": 1, "applied_force": "Force [N]"},
        units={"position": "mm"}, scale={"applied_force": -1.0, "position": "gtau"},
        sample_rate=1000.0, decimal=",", header=False, axis="rotary",
        segments={"kind": "stops", "lead_in": 0.02, "min_samples": 20},
    )  # fmt: skip
    path = tmp_path / "model.toml"
    save_model(path, MODEL, data=data)
    text = path.read_text()
    assert 'columns = { time = "Time [s]", position = 1, applied_force = "Force [N]" }' in text
    assert load_model(path).data == data
    assert not data.empty and DataSettings().empty


def test_a_model_file_without_data_states_nothing(tmp_path):
    path = tmp_path / "model.toml"
    save_model(path, MODEL, data=DataSettings())
    assert "[data]" not in path.read_text()
    assert load_model(path).data.empty


@pytest.mark.parametrize(
    ("table", "needle"),
    [
        ("colums = { time = 't' }", "unknown key `data.colums`"),
        ("columns = { speed = 't' }", "`data.columns.speed` must be a signal"),
        ("columns = { time = true }", "`data.columns.time` must be a string or a number"),
        ("sample_rate = -5.0", "`data.sample_rate` must be a positive number"),
        ("decimal = ';'", "`data.decimal` must be '.' or ','"),
        ("header = 1", "`data.header` must be true or false"),
        ("axis = 'polar'", "`data.axis` must be 'linear' or 'rotary'"),
        ("segments = { kind = 'cycles' }", "`data.segments` must be a table with kind"),
        ("segments = { kind = 'stops', lead = 0.1 }", "`data.segments.lead` must be one of"),
        ("segments = { kind = 'stops', lead_in = 'x' }", "`data.segments.lead_in` must be a "
         "finite number"),
    ],
)  # fmt: skip
def test_a_bad_data_table_is_named(tmp_path, table, needle):
    path = tmp_path / "model.toml"
    path.write_text(f"[friction]\ncoulomb = 0.3\n\n[data]\n{table}\n")
    with pytest.raises(ModelFileError, match=needle.replace("(", r"\(")):
        load_model(path)


def test_save_model_checks_its_data_argument(tmp_path):
    with pytest.raises(TypeError, match="`data` must be a DataSettings"):
        save_model(tmp_path / "m.toml", MODEL, data={"columns": {}})
