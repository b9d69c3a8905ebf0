"""Records read for ``presliding fit`` and ``presliding predict``: columns, files, cuts.

Files
-----
columns.py      column roles: the column of each signal and why, why the others are not
files.py        one data file as a record (text or MATLAB; units, scales, window)
cuts.py         ``--segments``: records cut into stops, loops or ramps; stated and drawn
virgin.py       the virgin loadings and Masing returns a record holds (``--kind virgin``)

May import every layer below the command line, and `presliding.cli.common`.
"""
