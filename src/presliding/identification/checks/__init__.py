"""Checks of a found optimum: refinements the fits ask for before the judge.

Relabelling interchangeable elements, the rigid corner, coalesced elements, parameters
on their bounds, F_c equal to the model's, and a split of neighbouring elements that no
record makes slide.

Files
-----
_response_checks.py  after a pooled fit: rigid corner, coalesced elements, relabelling, bounds
_split_check.py      a split of neighbouring elements the records do not determine (a plateau)

May import: the rooms `search`, `solve` of identification; the layers below identification and
the root's shared modules.
"""
