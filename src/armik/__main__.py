"""``python -m armik``: the ``armik`` command (``armik.tools.cli``), imported only when run."""

if __name__ == "__main__":  # imported (a walk over armik's modules): nothing runs
    from armik.tools.cli.main import main

    raise SystemExit(main())
