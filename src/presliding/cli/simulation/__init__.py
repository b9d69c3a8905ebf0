"""Commands that run a model: ``simulate``, ``analyze``, ``loop``, ``network``.

A model file's motion, its key quantities and stop analysis, a PID loop with PI
friction and its limit cycles, and a structure with friction contacts: each written as
CSV tables, figures and (``loop``, ``network``) a report.

Files
-----
analyze.py   ``presliding analyze``: key quantities and the stop analysis of a model file
loop.py      ``presliding loop``: a PID loop, its exact response and limit cycles
network.py   ``presliding network``: a structure with friction contacts, report, figures
simulate.py  ``presliding simulate``: a model file's motion to CSV and PNG

May import: the command line's shared modules (`common`, `report`); every layer below the
command line and the root's shared modules.
"""
