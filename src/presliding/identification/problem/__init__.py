"""What a fit minimises: the step every fit starts from.

A fit's verb function turns its arguments into a `FitProblem`: named parameters with
start values, bounds, fixed and tied ones, the model spec, the options every fit
shares, and the residual. The separable fits (`fit_presliding`, `fit_motion`,
`fit_virgin_curve`) are linear in all but the thresholds.

Files
-----
_family_spec.py        the rate-dependent families (GMS, LuGre, Dahl) as named parameters
_fit_options.py        the options every fit shares (level, evaluations, fixed, tied), checked
_fit_problem.py        `FitProblem`: what a fit minimises (parameters, residual, Jacobian structure)
_model_spec.py         the fitted models as named parameters (elements, densities)
_parameter_map.py      the free/fixed/tied split of named parameters
_parameters.py         initial, bounds, fixed, tied and lmfit.Parameters, checked together
_pi_regression.py      the PI bases and threshold grids of the separable fits; the fused batch loss
_separable_adequacy.py a separable fit's residual as the adequacy tests read it; candidates
_separable_problem.py  the separable fits' problem: linear in all but the thresholds
_sided_virgin.py       the two branches of an asymmetric virgin curve as one problem

May import: the rooms `judge`, `plans`, `records`, `solve` of identification; the layers below
identification and the root's shared modules.
"""
