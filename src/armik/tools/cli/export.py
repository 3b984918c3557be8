"""``armik export``: an arm's closed form written as a C99 solver (``armik.export``)."""

from __future__ import annotations

import argparse
from pathlib import Path

from armik.errors import OptionError
from armik.export import export
from armik.tools.cli.arms import load_arm

# ``armik.export``'s arguments and the flags that give them here
FLAGS = {
    "name": "--name",
    "out": "--out",
    "tol_position": "--tol-position",
    "tol_orientation": "--tol-orientation",
}


def cmd_export(args: argparse.Namespace) -> int:
    try:
        files = export(
            load_arm(args),
            args.name,
            args.out,
            ikfast=args.ikfast,
            tol_position=args.tol_position,
            tol_orientation=args.tol_orientation,
        )
    except OptionError as exc:  # "tol_position must be > 0": the flag that gave it
        flag, text = FLAGS.get(exc.option), str(exc)
        if flag is None or not text.startswith(exc.option):
            raise
        rest = text[len(exc.option) :]
        rest = " " + rest[1:] if rest.startswith("=") else rest  # out='x' -> --out 'x'
        raise OptionError(flag + rest, option=exc.option, value=exc.value) from None
    for name in files:  # the paths written to ("" is the current folder, "sub/" is "sub")
        print(Path(args.out) / name)
    return 0
