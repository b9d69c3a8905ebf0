"""Commands that fit models to measured records: ``fit``, ``predict``, ``ring-down``.

Records come from data files or ``--join`` groups (`records`, read by the room
`inputs`); ``presliding fit`` turns them into a model file, a figure and a report
(one-file kinds in `fit`, pooled kinds in `fit_pooled`); ``presliding predict`` and
``fit --hold-out`` predict records the model never saw; ``presliding ring-down`` fits a
joint model to a measured free decay.

Files
-----
fit.py          ``presliding fit``: one-file kinds, the model file, column roles as notes
fit_figure.py   the figure of a fit (fit.png)
fit_options.py  the options of ``presliding fit`` (its sub-parser), and which kinds use each
fit_pooled.py   ``presliding fit FILE ...`` for response, quasi-static and virgin fits
predict.py      ``presliding predict MODEL FILE ...`` and ``fit --hold-out``: held-out records
records.py      records from files or --join groups; --header, --decimal, --axis, --join
ring_down.py    ``presliding ring-down FILE``: a free decay's ω(A), ζ(A) and a fitted joint

May import: the room `inputs` of the command line; the command line's shared modules
(`common`, `report`); every layer below the command line and the root's shared modules.
"""
