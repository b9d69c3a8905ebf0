"""The judge: the one status table of every fit.

What status a fit ends with (`_status.judge`, its rules tabled with the command line's
exit codes) and the noise floor of the data the residual is measured against.

Files
-----
_noise_floor.py  the noise floor of the data: quantum and high-frequency noise
_status.py       the one status judge of every fit (its rules tabled), exit codes, hints

May import: the layers below identification and the root's shared modules.
"""
