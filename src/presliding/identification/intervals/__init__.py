"""Intervals: how sure each fitted value is.

The HAC covariance of a fit, profile-likelihood intervals (each end walked by
continuation), a parameter whose column vanishes on its bound, and other local optima
within the profile's threshold that widen the intervals.

Files
-----
_alternatives.py   other local optima within the profile's threshold: widened intervals
_covariance.py     a fit's covariance: the HAC sandwich of leverage-adjusted residuals
_profile.py        profile-likelihood intervals on the least-squares core
_profile_bound.py  a column vanishing on its bound: profiled inward, its partners' ranges
_profile_inner.py  a profile point's inner optimisation (LM with per-record steps)
_profile_walk.py   the walk to one end of a profile interval (continuation, regula falsi)

May import: the rooms `solve` of identification; identification's `uncertainty`; the layers
below identification and the root's shared modules.
"""
