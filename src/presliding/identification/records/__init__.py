"""Record-pooled residuals: many measured records, one compiled call.

`fit_response` and `fit_quasi_static` pool records: each record is a measurement
with its own start (initial position, velocity, preload); the residual of every
record under many parameter sets is one compiled call, its Jacobian structured
by record. The start values come from eq. 17 (motion) or eq. 8 (quasi-static)
as a regression over every record.

Files
-----
_creep_problem.py         the pooled quasi-static residual with creep (a Kelvin–Voigt element)
_penalty.py               the hinge row that keeps a derived F_c at or above `min_coulomb_level`
_pooled_banks.py          the banks (c1, k_j, r_j) of many parameter sets as kernel arrays
_pooled_jacobian.py       the finite differences of that Jacobian, records' columns together
_pooled_kernel.py         compiled batched responses of many records and parameter sets
_pooled_problem.py        the pooled residual and its structured Jacobian
_pooled_record.py         a measurement as a pooled record; its velocity as a difference quotient
_pooled_start.py          pooled start values (eq. 17 as a regression)
_quasi_static_errors.py   the error floor of runs of equal quantised samples
_quasi_static_kernel.py   compiled quasi-static positions of many records and parameter sets
_quasi_static_problem.py  the pooled quasi-static residual
_quasi_static_start.py    quasi-static start values (eq. 8 as a regression)
_rate_kernel.py           compiled batched motions with GMS, LuGre or Dahl friction (implicit)
_rate_problem.py          the pooled residual of a rate-dependent family
_residual_blocks.py       a pooled residual as the adequacy tests read it; candidate mechanisms
_response_tools.py        a record's first direction, integrals, equal-break-away stiffnesses

May import: the rooms `intervals`, `judge`, `problem`, `solve` of identification;
identification's `prediction`, `uncertainty`; the layers below identification and the root's
shared modules.
"""
