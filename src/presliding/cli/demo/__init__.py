"""``presliding demo``: the built-in main job, its parts, figures and report.

Six parts, each a figure and a report section: the paper's Figure 3 loops, a free
stop, a reversal sweep, a continuous density, an identification round trip and a PI
loop's hunting (``presliding precompile`` runs the same computations into the cache).

Files
-----
_common.py   constants and figure helpers shared by the demo's parts
command.py   the main job: `run_demo`, its parts in order, `DEMO_OUTPUTS`, the report
hunting.py   the hunting part: a limit cycle predicted against the simulated one
sections.py  parts 4 and 5: a continuous density and an identification round trip

May import: the command line's shared modules (`common`, `report`); every layer below the
command line and the root's shared modules.
"""
