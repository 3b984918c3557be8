"""``armik export``: an arm's closed form written as a C99 solver (``armik.export``)."""

from __future__ import annotations

import argparse
from pathlib import Path

from armik.export import export
from armik.tools.cli.arms import load_arm


def cmd_export(args: argparse.Namespace) -> int:
    files = export(
        load_arm(args),
        args.name,
        args.out,
        ikfast=args.ikfast,
        tol_position=args.tol_position,
        tol_orientation=args.tol_orientation,
    )
    for name in files:  # the paths written to ("" is the current folder, "sub/" is "sub")
        print(Path(args.out) / name)
    return 0
