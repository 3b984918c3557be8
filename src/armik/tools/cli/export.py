"""``armik export``: an arm's closed form written as a C99 solver (``armik.export``)."""

from __future__ import annotations

import argparse

from armik.export import export
from armik.tools.cli.arms import add_arm_arguments, load_arm


def add_export_command(command) -> None:
    c = command(
        "export",
        "write an arm's closed form as plain C99 (N_ik.h, N_ik.c; --ikfast: N_ikfast.cpp, "
        "IKFast 61's interface for MoveIt)",
        "armik export ur5 --name ur5 --out ur5_ik --ikfast",
        cmd_export,
    )
    add_arm_arguments(
        c,
        base="base frame (default: URDF root)",
        tip="tip frame (default: as armik info chooses it)",
        lock=False,
    )
    c.add_argument("--name", required=True, help="the solver's name N, a C identifier")
    c.add_argument("--out", required=True, help="directory to write the files into")
    c.add_argument("--ikfast", action="store_true", help="also write N_ikfast.cpp")
    c.add_argument(
        "--tol-position", type=float, help="how far a solution may miss its target (m, 1e-6)"
    )
    c.add_argument("--tol-orientation", type=float, help="... and its orientation (rad, 1e-6)")


def cmd_export(args: argparse.Namespace) -> int:
    files = export(
        load_arm(args),
        args.name,
        args.out,
        ikfast=args.ikfast,
        tol_position=args.tol_position,
        tol_orientation=args.tol_orientation,
    )
    for name in files:
        print(f"{args.out}/{name}")
    return 0
