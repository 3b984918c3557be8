"""``python -m armik``: the ``armik`` command (``armik.tools.cli``), imported only when run."""

from armik.tools.cli.main import main

raise SystemExit(main())
