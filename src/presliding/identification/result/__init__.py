"""How a fit shows itself: the parts of `FitResult` that are not its numbers.

The report, notebook table, pandas frame and figure; lmfit's and scipy's names for the
same quantities; what a fit shows while it runs.

Files
-----
_fit_names.py     lmfit's and scipy's names on `FitResult` (aic, bic, redchi, x, to_lmfit)
_fit_progress.py  what a fit shows while it runs (`progress=`): stages, evaluations, generations
_fit_report.py    how a `FitResult` shows itself: report, notebook table, pandas, figure

May import: the rooms `problem` of identification; the layers below identification and the
root's shared modules.
"""
