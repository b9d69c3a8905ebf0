"""Chunked parameter sweeps: serial, local processes and a Dask LocalCluster agree."""

import os
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
    lock = __import__("threading").Lock()
    with pytest.raises(TypeError, match=r"`fn` must be picklable by cloudpickle .*lock"):
        sweep(lambda ratio, velocity: (lock, ratio)[1], GRID, n_workers=2)
    with pytest.raises(ValueError, match="`retries` must be nonnegative; got -1"):
        sweep(surface, GRID, retries=-1)
    with pytest.raises(TypeError, match="`scheduler` must be None, a scheduler address"):
        sweep(surface, GRID, scheduler=3)


def test_malformed_address_is_refused_before_connecting():
    pytest.importorskip("distributed")
    rule = r"^`scheduler` must be a scheduler address .* got 'nonsense'"
    with pytest.raises(ValueError, match=rule):
        sweep(surface, GRID, scheduler="nonsense")


def test_missing_dask_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(ImportError, match=r"pip install \"presliding\[dask\]\""):
        sweep(surface, GRID, scheduler="tcp://127.0.0.1:1")


def test_to_pandas_and_to_xarray_of_a_product_grid():
    pd = pytest.importorskip("pandas")
    xr = pytest.importorskip("xarray")
    res = sweep(surface, GRID, n_workers=1, chunk_size=10)
    frame = res.to_pandas()
    assert list(frame.index.names) == ["ratio", "velocity"] and list(frame) == ["value", "failed"]
    assert frame.shape == (77, 2) and frame.attrs["status"] == "ok"
    table = frame["value"].unstack()  # the 2-D map back
    np.testing.assert_array_equal(table.to_numpy(), res.values)
    np.testing.assert_array_equal(table.index.to_numpy(), GRID["ratio"])
    np.testing.assert_array_equal(table.columns.to_numpy(), GRID["velocity"])
    assert frame.loc[(GRID["ratio"][2], GRID["velocity"][5]), "value"] == res.values[2, 5]
    data = res.to_xarray()
    assert isinstance(data, xr.Dataset) and data["value"].dims == ("ratio", "velocity")
    np.testing.assert_array_equal(data["value"].values, res.values)
    np.testing.assert_array_equal(data["ratio"].values, GRID["ratio"])
    assert not data["failed"].values.any() and data.attrs["backend"] == "serial"
    point = data["value"].sel(ratio=GRID["ratio"][2], velocity=GRID["velocity"][5])
    assert float(point) == res.values[2, 5]
    assert isinstance(frame, pd.DataFrame)


def test_to_pandas_and_to_xarray_of_rows_and_tables():
    pytest.importorskip("pandas")
    pytest.importorskip("xarray")
    rows = sweep(two_outputs, GRID, n_workers=1)
    frame = rows.to_pandas(names=["sum", "product"])
    assert list(frame) == ["sum", "product", "failed"]
    np.testing.assert_array_equal(frame["product"].to_numpy(), rows.values[..., 1].ravel())
    assert list(rows.to_pandas()) == ["value_0", "value_1", "failed"]
    data = rows.to_xarray(names=["sum", "product"])
    np.testing.assert_array_equal(data["sum"].values, rows.values[..., 0])
    table = np.zeros(4, dtype=[("ratio", float), ("velocity", float)])
    table["ratio"], table["velocity"] = [0.1, 0.2, 0.3, 0.4], [1.0, -1.0, 2.0, 0.0]
    res = sweep(nan_where_negative, table, n_workers=1)
    frame = res.to_pandas()
    assert list(frame) == ["ratio", "velocity", "value", "failed"]
    np.testing.assert_array_equal(frame["velocity"].to_numpy(), table["velocity"])
    assert frame["failed"].tolist() == [False, True, False, False]
    data = res.to_xarray()
    assert data["value"].dims == ("point",) and data["ratio"].dims == ("point",)
    np.testing.assert_array_equal(data["failed"].values, [False, True, False, False])
    assert data.attrs["status"] == "failed"
    with pytest.raises(ValueError, match="`names` must be 2 distinct non-empty strings"):
        rows.to_pandas(names=["sum"])
    with pytest.raises(ValueError, match="must not repeat a grid name or 'failed'"):
        rows.to_xarray(names=["ratio", "x"])


def test_pandas_and_xarray_are_optional(monkeypatch):
    res = sweep(surface, GRID, n_workers=1)
    monkeypatch.setitem(sys.modules, "pandas", None)
    monkeypatch.setitem(sys.modules, "xarray", None)
    with pytest.raises(ImportError, match=r"pip install \"presliding\[pandas\]\""):
        res.to_pandas()
    with pytest.raises(ImportError, match=r"pip install \"presliding\[xarray\]\""):
        res.to_xarray()


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


def flaky_once(marker_dir, ratio, velocity):
    """Raises the first time each chunk runs (a marker file per chunk), then succeeds."""
    import pathlib

    marker = pathlib.Path(marker_dir) / f"{ratio[0]!r}-{velocity[0]!r}"
    if not marker.exists():
        marker.write_text("seen")
        raise OSError("a transient failure")
    return surface(ratio, velocity)


def slow_surface(ratio, velocity):
    import time

    time.sleep(0.25)
    return surface(ratio, velocity)


def _kill_a_worker_mid_sweep(client, run):
    """Run `run()` in a thread and kill a worker process while it runs a chunk."""
    import contextlib
    import threading
    import time

    out = {}
    thread = threading.Thread(target=lambda: out.update(result=run()))
    thread.start()
    deadline = time.monotonic() + 60
    victim = None
    while victim is None and time.monotonic() < deadline:
        victim = next((w for w, keys in client.processing().items() if keys), None)
        time.sleep(0.02)
    assert victim is not None, "no chunk started"
    with contextlib.suppress(Exception):  # the connection drops as the worker exits
        client.run(os._exit, 1, workers=[victim])
    thread.join(timeout=120)
    assert not thread.is_alive()
    return out["result"]


def test_dask_local_cluster_equals_local_run(tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    import functools

    import cloudpickle

    serial = sweep(surface, GRID, n_workers=1, chunk_size=10)
    r, v = np.meshgrid(GRID["ratio"], GRID["velocity"], indexing="ij")
    sent = []
    original_map = distributed.Client.map

    def spy_map(self, func, *iterables, **kwargs):  # what each task carries, as Dask sends it
        sent.extend(len(cloudpickle.dumps(args)) for args in zip(*iterables, strict=True))
        return original_map(self, func, *iterables, **kwargs)

    monkeypatch.setattr(distributed.Client, "map", spy_map)
    big = {"ratio": np.linspace(0.1, 0.9, 1000), "velocity": np.linspace(-2.0, 3.0, 1000)}
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
        # cloudpickle: a lambda runs on Dask (local processes refuse it, see test_input_validation)
        with_lambda = sweep(lambda ratio, velocity: ratio * velocity, GRID, client)
        sent.clear()
        million = sweep(surface, big, client)  # chunks from the cluster's 2 threads: 8
        million_sent = list(sent)
        flaky = functools.partial(flaky_once, str(tmp_path))
        retried = sweep(flaky, GRID, client, chunk_size=20, retries=1)
        (tmp_path / "second").mkdir()
        not_retried = sweep(functools.partial(flaky_once, str(tmp_path / "second")), GRID,
                            client, chunk_size=20)  # fmt: skip
        # a table: each chunk's rows are scattered once; rows lost with a killed worker are
        # scattered again (LocalCluster's nanny starts a new worker process)
        scattered = []
        original_scatter = distributed.Client.scatter

        def spy_scatter(self, data, *args, **kwargs):
            scattered.append(len(data) if isinstance(data, list) else 0)
            return original_scatter(self, data, *args, **kwargs)

        monkeypatch.setattr(distributed.Client, "scatter", spy_scatter)
        table = np.zeros(77, dtype=[("ratio", float), ("velocity", float)])
        table["ratio"], table["velocity"] = r.ravel(), v.ravel()
        killed = _kill_a_worker_mid_sweep(
            client, lambda: sweep(slow_surface, table, client, chunk_size=7)
        )
        assert client.status == "running"  # a given Client is left open
    for res in (on_client, on_address):
        assert res.backend == "dask" and res.n_workers == 2 and res.status == "ok"
        np.testing.assert_array_equal(res.values, serial.values)
    assert "on 2 Dask workers" in on_client.report()
    assert failing.status == "failed" and failing.failed[:, 0].tolist() == [False, True]
    assert "ValueError: velocity too large" in failing.message
    np.testing.assert_array_equal(with_lambda.values, r * v)
    # a million points: each task carries two futures and an index range, a few hundred bytes
    assert million.n_chunks == 8 and million.success and len(million_sent) == 8
    assert max(million_sent) < 1000, million_sent
    rb, vb = np.meshgrid(big["ratio"], big["velocity"], indexing="ij")
    np.testing.assert_array_equal(million.values, surface(rb, vb))
    assert retried.success and retried.n_chunks == 4
    np.testing.assert_array_equal(retried.values, serial.values)
    assert not_retried.status == "failed" and not_retried.failed.all()
    assert "OSError: a transient failure" in not_retried.message
    assert killed.kind == "table" and killed.success and killed.n_chunks == 11, killed.message
    np.testing.assert_array_equal(killed.values, serial.values.ravel())
    lists = [n for n in scattered if n]
    assert lists[0] == 11 and len(lists) >= 2 and sum(lists[1:]) < 11, scattered


def test_a_cheap_default_sweep_runs_in_this_process(monkeypatch):
    """A trivial function on a default sweep started a pool of worker processes (27 s of
    wall time on a loaded machine); the first chunk is timed and the rest run here."""
    from presliding.sweep import runner

    def no_pool(*args, **kwargs):
        raise AssertionError("a pool was started")

    monkeypatch.setattr(runner, "on_local_pool", no_pool)
    monkeypatch.setattr(runner.os, "cpu_count", lambda: 4)
    res = sweep(surface, GRID)
    assert res.backend == "serial" and res.n_workers == 1 and res.n_chunks == 16
    np.testing.assert_array_equal(res.values, sweep(surface, GRID, n_workers=1).values)


def test_a_costly_default_sweep_runs_its_remaining_chunks_on_a_pool(monkeypatch):
    """Chunks that would take longer than IN_PROCESS_SECONDS in all go to worker processes,
    the first (timed here) excepted; a function that cannot be sent is refused either way."""
    import threading

    from presliding.sweep import runner

    pooled = []

    def pool(fn, points, n_chunks, workers, bar, first=0):
        pooled.append((first, workers))
        return runner._execute(fn, points, n_chunks, "serial", 1, None, bar, 0, start=first)

    monkeypatch.setattr(runner, "on_local_pool", pool)
    monkeypatch.setattr(runner.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(runner, "IN_PROCESS_SECONDS", 0.0)  # every chunk counts as costly
    res = sweep(surface, GRID)
    assert pooled == [(1, 2)] and res.backend == "processes" and res.n_workers == 2
    np.testing.assert_array_equal(res.values, sweep(surface, GRID, n_workers=1).values)
    lock = threading.Lock()
    with pytest.raises(TypeError, match="must be picklable"):  # whatever the timing decides
        sweep(lambda ratio, velocity: (lock, ratio)[1], GRID)
