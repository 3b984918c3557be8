"""``python -m armik.tools.cli``: the ``armik`` command."""

from armik.tools.cli.main import main

raise SystemExit(main())
