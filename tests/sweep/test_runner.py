"""Chunked parameter sweeps: serial, local processes and a Dask LocalCluster agree."""

import sys

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from presliding.sweep import SweepResult, sweep

GRID = {"ratio": np.linspace(0.1, 0.9, 7), "velocity": np.linspace(-2.0, 3.0, 11)}


def surface(ratio, velocity):
    """An elementwise test function (module level: picklable by reference)."""
    return np.sin(3 * ratio) * np.exp(-0.1 * velocity**2) + ratio * velocity


def chunk_length(ratio, velocity):
    return np.full(ratio.shape, ratio.shape[0])


def two_outputs(ratio, velocity):
    return np.column_stack([ratio + velocity, ratio * velocity])


def fails_on_large(ratio, velocity):
    if np.any(velocity > 2.5):
        raise ValueError("velocity too large")
    return ratio + velocity


def wrong_length(ratio, velocity):
    return ratio[:-1]


def nan_where_negative(ratio, velocity):
    return np.where(velocity < 0, np.nan, np.where(velocity > 2.5, np.inf, ratio + velocity))


def test_product_grid_serial_values_and_shape():
    res = sweep(surface, GRID, n_workers=1, chunk_size=10)
    assert isinstance(res, SweepResult) and res.status == "ok" and res.success
    assert res.shape == (7, 11) and res.values.shape == (7, 11)
    r, v = np.meshgrid(GRID["ratio"], GRID["velocity"], indexing="ij")
    np.testing.assert_array_equal(res.values, surface(r, v))
    assert res.n_chunks == 8 and res.backend == "serial" and res.n_workers == 1
    assert not res.failed.any()
    text = res.report()
    assert "77 points (product) in 8 chunks in this process" in text
    assert "ratio: 7 values in [0.1, 0.9]" in text


def test_chunks_are_cut_as_asked():
    res = sweep(chunk_length, GRID, n_workers=1, chunk_size=30)
    np.testing.assert_array_equal(np.unique(res.values.ravel()), [25, 26])  # 77 = 26 + 26 + 25
    assert res.n_chunks == 3
    flat = res.values.ravel()
    np.testing.assert_array_equal(flat[:3], [26, 26, 25])  # point i is in chunk i mod 3


def test_local_processes_equal_serial():
    serial = sweep(surface, GRID, n_workers=1)
    local = sweep(surface, GRID, n_workers=2, chunk_size=9)
    assert local.backend == "processes" and local.n_workers == 2 and local.status == "ok"
    np.testing.assert_array_equal(local.values, serial.values)


def test_given_executor_is_used_and_left_open():
    from concurrent.futures import ThreadPoolExecutor

    serial = sweep(surface, GRID, n_workers=1)
    with ThreadPoolExecutor(max_workers=3) as pool:
        first = sweep(surface, GRID, pool, chunk_size=5)
        second = sweep(two_outputs, GRID, pool)
    assert first.backend == "executor" and first.n_workers == 3 and first.n_chunks == 16
    np.testing.assert_array_equal(first.values, serial.values)
    assert second.values.shape == (7, 11, 2) and "given executor" in first.report()


def test_table_grid_and_row_outputs():
    table = np.zeros(5, dtype=[("ratio", float), ("velocity", float)])
    table["ratio"] = [0.1, 0.2, 0.3, 0.4, 0.5]
    table["velocity"] = [1.0, -1.0, 2.0, 0.0, 5.0]
    res = sweep(two_outputs, table, n_workers=1, chunk_size=2)
    assert res.kind == "table" and res.shape == (5,) and res.values.shape == (5, 2)
    np.testing.assert_array_equal(res.values[:, 0], table["ratio"] + table["velocity"])
    np.testing.assert_array_equal(res.values[:, 1], table["ratio"] * table["velocity"])
    with pytest.raises(ValueError, match="needs a 1-D or 2-D product grid"):
        res.plot()


def test_failed_chunk_is_reported_not_raised():
    grid = {"velocity": [0.0, 1.0, 3.0], "ratio": [0.5]}
    res = sweep(fails_on_large, grid, n_workers=1, chunk_size=1)
    assert res.status == "failed" and not res.success
    assert res.message == (
        "1 of 3 chunks failed; chunk 2 (first point velocity=3.0, ratio=0.5) raised "
        "ValueError: velocity too large"
    )
    np.testing.assert_array_equal(res.failed[:, 0], [False, False, True])
    np.testing.assert_array_equal(res.values[:2, 0], [0.5, 1.5])
    assert np.isnan(res.values[2, 0])
    assert "failed" in res.report()


def test_non_finite_values_are_failed_points():
    res = sweep(lambda a: a * np.nan, {"a": [1.0, 2.0]}, n_workers=1)
    assert res.status == "failed" and not res.success
    assert res.message == (
        "2 of 2 points got no finite value from `fn`; the first at a=1.0 (index 0)"
    )
    assert res.failed.all() and np.isnan(res.values).all()
    # a product grid: NaN and inf points are flagged, the rest kept; index in the grid's shape
    res = sweep(nan_where_negative, GRID, n_workers=1, chunk_size=10)
    r, v = np.meshgrid(GRID["ratio"], GRID["velocity"], indexing="ij")
    bad = (v < 0) | (v > 2.5)
    np.testing.assert_array_equal(res.failed, bad)
    assert np.isnan(res.values[bad]).all()
    np.testing.assert_array_equal(res.values[~bad], (r + v)[~bad])
    assert res.status == "failed"
    assert res.message == (
        f"{bad.sum()} of 77 points got no finite value from `fn`; the first at ratio=0.1, "
        "velocity=-2.0 (index (0, 0))"
    )
    assert "failed" in res.report()


def test_rows_with_a_finite_entry_are_kept_and_both_failures_are_reported():
    def flagged(velocity):  # a value and a validity flag, as the command-line sweep returns
        return np.column_stack([np.where(velocity > 0, velocity, np.nan), velocity > 0])

    res = sweep(flagged, {"velocity": [-1.0, 1.0]}, n_workers=1)
    assert res.status == "ok" and not res.failed.any()
    assert np.isnan(res.values[0, 0]) and res.values[1].tolist() == [1.0, 1.0]
    grid = {"velocity": [0.0, -1.0, 3.0], "ratio": [0.5]}

    def both(velocity, ratio):
        return fails_on_large(ratio, velocity) / (velocity >= 0)

    with np.errstate(divide="ignore"):
        res = sweep(both, grid, n_workers=1, chunk_size=1)
    assert res.message == (
        "1 of 3 chunks failed; chunk 2 (first point velocity=3.0, ratio=0.5) raised "
        "ValueError: velocity too large; 1 of 3 points got no finite value from `fn`; the "
        "first at velocity=-1.0, ratio=0.5 (index (1, 0))"
    )
    np.testing.assert_array_equal(res.failed[:, 0], [False, True, True])


def test_wrong_output_length_fails_the_chunk():
    res = sweep(wrong_length, GRID, n_workers=1)
    assert res.status == "failed"
    assert "`fn` must return one value per point" in res.message


def test_input_validation():
    with pytest.raises(TypeError, match="`grid` must be a non-empty dict"):
        sweep(surface, [1.0, 2.0])
    with pytest.raises(ValueError, match=r"`grid\['ratio'\]` must be one-dimensional"):
        sweep(surface, {"ratio": np.zeros((2, 2)), "velocity": [1.0]})
    with pytest.raises(ValueError, match=r"`grid\['ratio'\]` must be finite"):
        sweep(surface, {"ratio": [np.nan], "velocity": [1.0]})
    with pytest.raises(ValueError, match="`chunk_size` must be a positive integer; got 0"):
        sweep(surface, GRID, chunk_size=0)
    with pytest.raises(ValueError, match="`n_workers` must be a positive integer; got 0"):
        sweep(surface, GRID, n_workers=0)
    with pytest.raises(TypeError, match="`fn` must be callable"):
        sweep(3.0, GRID)
    with pytest.raises(TypeError, match="`fn` must be picklable"):
        sweep(lambda ratio, velocity: ratio, GRID, n_workers=2)
    with pytest.raises(TypeError, match="`scheduler` must be None, a scheduler address"):
        sweep(surface, GRID, scheduler=3)


def test_malformed_address_is_refused_before_connecting():
    pytest.importorskip("distributed")
    rule = r"^`scheduler` must be a scheduler address .* got 'nonsense'"
    with pytest.raises(ValueError, match=rule):
        sweep(surface, GRID, scheduler="nonsense")


def test_missing_dask_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(ImportError, match=r"pip install presliding\[dask\]"):
        sweep(surface, GRID, scheduler="tcp://127.0.0.1:1")


def test_plot_maps_and_curves():
    res = sweep(surface, GRID, n_workers=1)
    ax = res.plot()
    mesh = ax.collections[0]
    np.testing.assert_array_equal(np.asarray(mesh.get_array()).reshape(11, 7), res.values.T)
    assert ax.get_xlabel() == "ratio" and ax.get_ylabel() == "velocity"
    plt.close(ax.figure)
    line = sweep(surface, {"ratio": GRID["ratio"], "velocity": [1.0]}, n_workers=1)
    with pytest.raises(ValueError, match="one value per point"):
        sweep(two_outputs, GRID, n_workers=1).plot()
    one = sweep(surface, {"ratio": GRID["ratio"]} | {"velocity": [1.0]}, n_workers=1)
    assert one.shape == (7, 1) and line.shape == (7, 1)
    ax = sweep(chunk_length, {"ratio": GRID["ratio"]}, n_workers=1).plot()
    assert len(ax.get_lines()) == 1
    plt.close(ax.figure)


def test_dask_local_cluster_equals_local_run():
    distributed = pytest.importorskip("distributed")
    serial = sweep(surface, GRID, n_workers=1, chunk_size=10)
    with (
        distributed.LocalCluster(
            n_workers=2,
            processes=True,
            threads_per_worker=1,
            host="127.0.0.1",
            dashboard_address=None,
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        on_client = sweep(surface, GRID, client, chunk_size=10)
        on_address = sweep(surface, GRID, cluster.scheduler_address)
        failing = sweep(fails_on_large, {"velocity": [0.0, 3.0], "ratio": [0.5]}, client,
                        chunk_size=1)  # fmt: skip
        assert client.status == "running"  # a given Client is left open
    for res in (on_client, on_address):
        assert res.backend == "dask" and res.n_workers == 2 and res.status == "ok"
        np.testing.assert_array_equal(res.values, serial.values)
    assert "on 2 Dask workers" in on_client.report()
    assert failing.status == "failed" and failing.failed[:, 0].tolist() == [False, True]
