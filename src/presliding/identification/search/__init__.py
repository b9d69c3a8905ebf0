"""The search step: where the optimum is looked for.

Starts, the adaptive multistart and the nuisance grid of each record's own
parameters, then probes of the neighbouring valleys and along eq. 17's scale;
`fit_presliding`'s differential evolution over thresholds; the model order by BIC.

Files
-----
_block_lm.py         Levenberg–Marquardt on every record's own block at once (the grid's polish)
_flat_probe.py       a far step along the least determined split of the k_j, solved short
_global_search.py    differential evolution over thresholds for `fit_presliding`
_model_order.py      ``n_elements="auto"``: the number of elements by BIC
_nuisance_search.py  each record's own parameters searched on a grid, the shared ones held
_probe_gate.py       whether the best needs the valleys' probes (floor, starts, stationarity)
_probes.py           probes of the valleys next to the best optimum (engage, corner, split)
_rate_search.py      the search of a rate family's fit: the PI fit, a batched grid, multistart
_scale_probe.py      the probe along eq. 17's scale (mass and forces together, blocks re-searched)
_search.py           the search step: starts, alternation, the noise-floor rule, its summary
_threshold_search.py variable projection over the thresholds of a separable fit (its starts)

May import: the rooms `intervals`, `judge`, `problem`, `records`, `solve` of identification; the
layers below identification and the root's shared modules.
"""
