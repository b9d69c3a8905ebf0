"""``python -m presliding`` runs the command-line interface."""

from presliding.cli.commands import main

raise SystemExit(main())
