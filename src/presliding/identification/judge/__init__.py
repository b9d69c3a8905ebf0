"""The judge: the one status table of every fit.

What status a fit ends with (`_status.judge`, its rules tabled with the command line's
exit codes), the noise floor of the data the residual is measured against, and whether
the data support an asymmetric model over the symmetric one (`_asymmetry`).

Files
-----
_asymmetry.py    is an asymmetry supported? the nested symmetric and asymmetric fits tested
_noise_floor.py  the noise floor of the data: quantum and high-frequency noise
_status.py       the one status judge of every fit (its rules tabled), exit codes, hints

May import: the layers below identification and the root's shared modules.
"""
