"""FitResult carries the names lmfit and scipy users look for, with lmfit's definitions."""

from __future__ import annotations

import numpy as np
import pytest

import presliding as ps
from presliding.signals import piecewise_linear


def test_lmfit_and_scipy_names():
    y = piecewise_linear([0.0, 0.8, -0.8, 0.4, -0.2, 0.6, -0.6], 1e-3) * 1e-3
    model = ps.PIFriction(0.2, [5e5, 5e4], [1.0, 1.0])
    f = model.force(y)[0] + np.random.default_rng(2).normal(0.0, 0.01, y.shape)
    res = ps.fit_presliding(y, f, 2, fixed={"coulomb": 0.2})
    assert res.var_names == ("stiffness_1", "stiffness_2", "threshold_1", "threshold_2")
    assert res.nvarys == 4 and res.ndata == y.shape[0] and res.nfree == res.ndata - 4
    np.testing.assert_array_equal(res.x, [res.parameters[n] for n in res.var_names])
    assert res.chisqr == pytest.approx(float(np.sum(res.residual**2)), rel=1e-9)
    n, k = res.ndata, res.nvarys
    assert res.redchi == pytest.approx(res.chisqr / (n - k))
    assert res.aic == pytest.approx(n * np.log(res.chisqr / n) + 2 * k)
    assert res.bic == pytest.approx(n * np.log(res.chisqr / n) + np.log(n) * k)
    assert res.nfev == res.n_evaluations > 0
    d = res.to_dict()
    for key in ("aic", "bic", "redchi", "chisqr", "ndata", "nvarys", "interval_method"):
        assert key in d
    assert set(res.interval_method) == set(res.var_names)
    assert "aic" in ps.FitResult.__doc__ and "redchi" in ps.FitResult.__doc__
