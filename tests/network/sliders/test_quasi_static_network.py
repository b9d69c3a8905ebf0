"""Quasi-static slider networks: the exact event-driven solution of the sweeping process."""

import matplotlib
import numpy as np
import pytest

from presliding import PIFriction
from presliding.network import GROUND, SliderNetwork, quasi_static_network

matplotlib.use("Agg")

TWO = SliderNetwork(2, springs=[(0, 1, 50.0)], sliders=[(1, GROUND, 1.0)],
                    stops=[(0, GROUND, 100.0, 0.5)])  # fmt: skip


def test_one_stop_is_the_elasto_plastic_element():
    net = SliderNetwork(1, stops=[(0, GROUND, 100.0, 1.0)])
    u = np.array([0.005, 0.02, 0.0, -0.004, 0.01])
    res = quasi_static_network(net, displacement={0: u})
    expected, _ = PIFriction(0.0, [100.0], breakaway=[1.0]).force(np.concatenate([[0.0], u]))
    np.testing.assert_allclose(res.forces[:, 0], expected[1:], rtol=1e-14, atol=1e-15)
    assert res.success and res.positions.shape == (5, 1)


def test_breakpoints_are_exact():
    res = quasi_static_network(TWO, displacement={0: [0.05]})
    x0 = res.breakpoint_positions[:, 0]
    np.testing.assert_allclose(x0, [0.0, 0.005, 0.02, 0.05], rtol=1e-15)
    np.testing.assert_allclose(res.breakpoint_forces[:, 0], [0.0, 0.75, 1.5, 1.5], rtol=1e-14)
    assert res.breakpoints[-1] == 0.0 and res.breakpoints[0] == -1.0
    # node 1 starts to move when its slider slips, at u = 0.02
    np.testing.assert_allclose(res.breakpoint_positions[:, 1], [0.0, 0.0, 0.0, 0.03], atol=1e-16)


def test_equilibrium_and_slider_bounds_at_every_sample():
    rng = np.random.default_rng(3)
    n = 5
    springs = [(i, i + 1, rng.uniform(10, 100)) for i in range(n - 1)] + [(0, 3, 30.0)]
    sliders = [(i, GROUND, rng.uniform(0.2, 1.0)) for i in range(1, n)]
    net = SliderNetwork(n, springs, sliders)
    u = 0.1 * np.sin(np.linspace(0, 9, 40)) * np.linspace(1, 0.2, 40)
    res = quasi_static_network(net, displacement={0: u})
    c = np.array([s[2] for s in sliders])
    assert np.all(np.abs(res.slider_forces) <= c * (1 + 1e-14))
    for x, f, fs in zip(res.positions, res.forces[:, 0], res.slider_forces, strict=True):
        internal = np.zeros(n)
        for a, b, k in springs:
            internal[a] += k * (x[a] - x[b])
            internal[b] -= k * (x[a] - x[b])
        for (a, _, _), fi in zip(sliders, fs, strict=True):
            internal[a] += fi
        np.testing.assert_allclose(internal[1:], 0.0, atol=1e-12 * np.max(c))
        assert internal[0] == pytest.approx(f, rel=1e-12, abs=1e-12)


def test_force_driven_node_on_a_spring_and_slider():
    # a spring k to the ground in parallel with a slider c: x = 0 until p = c, then (p − c)/k
    net = SliderNetwork(1, springs=[(0, GROUND, 200.0)], sliders=[(0, GROUND, 2.0)])
    p = np.array([1.0, 5.0, 3.0, -4.0])
    res = quasi_static_network(net, force={0: p})
    x = res.positions[:, 0]
    assert x[0] == 0.0
    assert x[1] == pytest.approx(3.0 / 200.0, rel=1e-14)
    assert x[2] == pytest.approx(3.0 / 200.0, rel=1e-14)  # unloading by 2 < 2c: sticks
    assert x[3] == pytest.approx((-4.0 + 2.0) / 200.0, rel=1e-14)
    assert res.forces.shape == (4, 0)


def test_mixed_drives_on_one_network():
    net = SliderNetwork(3, springs=[(0, 1, 40.0), (1, 2, 60.0)],
                        sliders=[(1, GROUND, 0.5)], stops=[(2, GROUND, 30.0, 0.4)])  # fmt: skip
    u = np.array([0.01, 0.03, -0.02])
    p = np.array([0.0, 0.3, -0.2])
    res = quasi_static_network(net, displacement={0: u}, force={2: p})
    np.testing.assert_allclose(res.positions[:, 0], u, rtol=1e-15)
    assert res.displacement_nodes.tolist() == [0] and res.force_nodes.tolist() == [2]


def test_resampling_the_input_changes_nothing():
    """Rate independence: extra samples on the same piecewise-linear input give the same path."""
    u = np.array([0.04, -0.03, 0.02])
    fine = np.concatenate([np.linspace(0, 0.04, 9)[1:], np.linspace(0.04, -0.03, 8)[1:],
                           np.linspace(-0.03, 0.02, 6)[1:]])  # fmt: skip
    a = quasi_static_network(TWO, displacement={0: u})
    b = quasi_static_network(TWO, displacement={0: fine})
    np.testing.assert_allclose(b.forces[[7, 14, 19], 0], a.forces[:, 0], rtol=1e-13, atol=1e-15)


def test_event_limit_is_reported():
    u = 0.05 * np.sin(np.linspace(0, 30, 200))
    res = quasi_static_network(TWO, displacement={0: u}, max_events=10)
    assert res.status == "event_limit" and not res.success
    assert "event limit" in res.message
    assert res.sample.shape[0] < 200


def test_result_convention():
    import matplotlib.pyplot as plt

    res = quasi_static_network(TWO, displacement={0: [0.05, -0.05]})
    assert repr(res).startswith("QuasiStaticNetworkResult(") and len(repr(res)) < 100
    frame = res.to_pandas()
    assert list(frame.columns) == ["x0", "x1", "force0"] and frame.attrs["status"] == "success"
    assert "node 0" in res.report() and "<table>" in res._repr_html_()
    ax = res.plot()
    assert "[m]" in ax.get_xlabel() and "[N]" in ax.get_ylabel()
    plt.close(ax.figure)
    ax = quasi_static_network(TWO, force={1: [0.5]}, displacement={0: [0.0]}).plot()
    plt.close(ax.figure)


@pytest.mark.parametrize(
    "build, match",
    [
        (lambda: SliderNetwork(0, sliders=[(0, -1, 1.0)]), "n_nodes"),
        (lambda: SliderNetwork(2, springs=[(0, 2, 1.0)], sliders=[(0, -1, 1.0)]), "springs"),
        (lambda: SliderNetwork(2, springs=[(0, 0, 1.0)], sliders=[(0, -1, 1.0)]), "itself"),
        (lambda: SliderNetwork(2, springs=[(0, 1, -1.0)], sliders=[(0, -1, 1.0)]), "springs"),
        (lambda: SliderNetwork(2, springs=[(0, 1, 1.0)]), "sliders"),
        (lambda: SliderNetwork(2, sliders=[(0, 1)]), "sliders"),
        (lambda: quasi_static_network(TWO), "displacement"),
        (lambda: quasi_static_network(TWO, displacement={0: [1.0, 2.0]}, force={1: [1.0]}),
         "same length"),
        (lambda: quasi_static_network(TWO, displacement={0: [1.0]}, force={0: [1.0]}), "not both"),
        (lambda: quasi_static_network(TWO, displacement={5: [1.0]}), "displacement"),
        (lambda: quasi_static_network(TWO, force={1: [1.0]}), "held by springs"),
        (lambda: quasi_static_network(
            SliderNetwork(2, springs=[(0, 1, 1.0)], sliders=[(1, -1, 1.0), (1, 0, 1.0)]),
            displacement={0: [1.0]}), "closed loop"),
        (lambda: quasi_static_network(TWO, displacement={0: [np.nan]}), "displacement"),
    ],
)  # fmt: skip
def test_bad_input_is_named(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_network_type_is_checked():
    with pytest.raises(TypeError, match="network"):
        quasi_static_network("chain", displacement={0: [1.0]})


def test_a_chain_too_large_is_refused_before_it_is_built():
    """1e8 sliders reached 5.8 GB before; now the size (and the memory a network of that
    size needs: rows, expanded form, solver) is checked first."""
    import time

    k, c = np.ones(10**7), np.ones(10**7 + 1)
    start = time.process_time()
    with pytest.raises(ValueError, match=r"`stiffness` must ask for at most .* got "
                                         r"'20,000,000 elements'.*GiB"):  # fmt: skip
        from presliding import _validation

        limit = _validation.MAX_ALLOCATION_BYTES
        _validation.MAX_ALLOCATION_BYTES = 10**9  # a machine with 1 GB to spare
        try:
            SliderNetwork.chain(k, c)
        finally:
            _validation.MAX_ALLOCATION_BYTES = limit
    assert time.process_time() - start < 0.5


def test_a_notebook_shows_a_slider_network_as_a_table():
    net = SliderNetwork(3, springs=[(0, 1, 50.0), (1, 2, 20.0)], sliders=[(2, GROUND, 1.0)],
                        stops=[(0, GROUND, 100.0, 0.5)])  # fmt: skip
    page = net._repr_html_()
    assert "<table>" in page and "stops" in page and "N/m" in page
    assert repr(net) == "SliderNetwork(n_nodes=3, springs=2, sliders=1, stops=1)"
