"""Fit a friction model to measured records: CSV files in, model, report and prediction out
=========================================================================================

The workflow with data from a rig: read the records (here CSV files with units in the
headers, written first from a simulation so the script runs anywhere), fit mass and PI
friction to three of them together (`fit_response`, output error on the position, each
record with its own initial velocity and preload), read the report, and predict a fourth
record the fit never saw. The figure shows the pooled fit, one colour per file, and the
prediction of the held-out file.

Run: python examples/fit_csv_records.py [output.png]
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import presliding as ps
from presliding.plotting import save_figure

TRUTH = ps.PIFriction(coulomb=0.3, stiffness=[4000.0, 1000.0], breakaway=[0.35, 0.35])
MASS = 2.0


def write_record(path: Path, v0: float, seed: int) -> None:
    """A stop after a push, as a rig logs it: time [s], position [mm], force [N]."""
    t = np.arange(600) * 1e-3
    d = np.sign(v0)
    u = np.where(t < 0.05, -0.3 * d, 0.0)
    memory = ps.preloaded_state(TRUTH, 0.5 * d, direction=d)
    res = ps.simulate(TRUTH, MASS, applied_force=(t, u), initial_velocity=v0,
                      initial_state=memory, t_eval=t)  # fmt: skip
    y_mm = 1e-4 * np.round(res.position * 1e3 / 1e-4)  # an encoder of 0.1 µm
    noise = 1e-3 * np.random.default_rng(seed).standard_normal(t.size)
    table = np.column_stack([t, y_mm, u + noise])
    np.savetxt(path, table, delimiter=",", header="Time [s],Position [mm],Force [N]",
               comments="", fmt="%.9g")  # fmt: skip


def main(path: str = "fit_csv_records.png") -> None:
    folder = Path(tempfile.mkdtemp(prefix="presliding-example-"))
    files = []
    for i, v0 in enumerate((0.03, -0.045, 0.06, -0.05)):
        files.append(folder / f"stop_{i + 1}.csv")
        write_record(files[-1], v0, seed=i)

    # read: columns by name, units from the headers (mm -> m)
    records = [ps.Measurement.from_csv(f, "Time [s]", position="Position [mm]",
                                       applied_force="Force [N]") for f in files]  # fmt: skip
    fit = ps.fit_response(records[:3], n_elements=2, signal="position", initial_state="preload")
    print(fit.report())
    prediction = fit.predict(records[3])  # the held-out file
    print(prediction.report())
    assert fit.success and abs(fit.parameters["mass"] - MASS) < 0.05

    fig = plt.figure(figsize=(12.0, 4.8), layout="constrained")
    left, right = fig.subfigures(1, 2)
    fit.plot(ax=left.subplots(), labels=[f.name for f in files[:3]])
    prediction.plot(ax=right.subplots())
    right.suptitle(f"held out: {files[3].name}")
    save_figure(fig, path)
    plt.close(fig)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
