"""One least-squares solve and its statistics.

scipy's trust region for small problems, Levenberg–Marquardt on structured normal
equations for large pooled ones; the `Solution` they return; JᵀJ and its scaled
pseudo-inverse.

Files
-----
_deferred.py          a solve whose covariance is deferred until the search keeps it
_least_squares.py     the solver around scipy.optimize.least_squares (bounds, ties, statistics)
_normal_equations.py  JᵀJ and its scaled pseudo-inverse (profile, probes, alternatives)
_solution.py          `Solution`: the outcome of one least-squares solve
_structured_lm.py     Levenberg–Marquardt on structured normal equations (large pooled fits)

May import: the rooms `intervals`, `judge`, `problem` of identification; identification's
`uncertainty`; the layers below identification and the root's shared modules.
"""
