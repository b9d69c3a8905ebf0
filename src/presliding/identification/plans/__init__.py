"""Each pooled fit's own parts of the pipeline (`_fit_engine.FitPlan`).

`fit_response` and `fit_quasi_static` check their arguments into a request, build their
problem, start values and bounds, name their searches, checks and refit (pruning), and
assemble their result; `_predictors` says how every fit predicts another record.

Files
-----
_asymmetric_plan.py    ``asymmetric=True``: the symmetric fit, then the asymmetric one from it
_predictors.py         how each fit predicts another record
_quasi_static_plan.py  `fit_quasi_static` as a problem and its search, checks, refit
_quasi_static_result.py the public result of a quasi-static fit (model, preloads, predictor)
_rate_plan.py          `fit_response(family=...)`: GMS, LuGre, Dahl as a problem, search, result
_response_box.py       a pooled response fit's start values and bounds (regression, records, user)
_response_plan.py      `fit_response` as a problem and its search, checks, refit, result
_response_request.py   `fit_response`'s arguments checked into one request
_response_result.py    the public result of a pooled response fit (model, derived values, units)
_response_setup.py     the pooled fit's entry checks, bounds, pruning and record bootstrap
_virgin_sides.py       `fit_virgin_curve(asymmetric=True)`: both branches from the symmetric fit

May import: the rooms `checks`, `intervals`, `judge`, `problem`, `records`, `search`, `solve` of
identification; identification's `_fit_engine`, `fit_result`, `masing`, `prediction`; the layers
below identification and the root's shared modules.
"""
