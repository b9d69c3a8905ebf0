"""``presliding sweep``: a quantity of the free motion over a grid of parameters.

A specification file (TOML, or JSON with the same tables) holds a base model, its free
motion and the grid to sweep; the quantity is evaluated on every grid point (local worker
processes, or a Dask cluster) and written as a table, a figure and a report.

Files
-----
sweep.py       ``presliding sweep``: the grid evaluated, sweep.csv, sweep.png and the report
sweep_spec.py  sweep specifications: reading and validation (`SCHEMA`, `load_spec`)

May import: the command line's shared modules (`common`, `report`); every layer below the
command line and the root's shared modules.
"""
