"""``armik``'s entry point and its argument parser: one sub-command per job."""

from __future__ import annotations

import argparse
import os
import re
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import NoReturn

from armik import __version__
from armik.errors import ArmikError, ArmikWarning
from armik.tools.cli.commands import (
    add_compile_command,
    add_export_command,
    add_many_commands,
    add_servo_command,
    add_view_command,
    later,
    seed_number,
)
from armik.tools.cli.flags import add_arm_arguments, add_solve_options, for_cli


def main(argv: Sequence[str] | None = None) -> int:
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # named with the command's own help, where the command was given
        getattr(args, "command_parser", parser).error(f"unrecognized arguments: {' '.join(extra)}")
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", category=DeprecationWarning)
            warnings.showwarning = _one_line_warning
            return int(args.func(args) or 0)
    except ArmikError as exc:
        print(f"armik: error: {for_cli(str(exc))}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C: one line, the shell's code for SIGINT (armik view: 0)
        print("armik: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader went away (armik info panda | head -1): stop quietly. Point stdout at
        # devnull so that the interpreter's final flush does not raise again.
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError):  # stdout without a file descriptor (captured)
            pass
        return 1
    except OSError as exc:  # a file armik was told to write or read (--plot DIR, ...)
        print(f"armik: error: {exc}", file=sys.stderr)
        return 2


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:
    kind = "" if issubclass(category, ArmikWarning) else f"{category.__name__}: "
    where = "" if issubclass(category, ArmikWarning) else f" ({Path(filename).name}:{lineno})"
    print(f"armik: warning: {kind}{message}{where}", file=sys.stderr)


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        # "-1e-3" is a number, not an option: argparse's own pattern misses exponents.
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")

    def error(self, message: str) -> NoReturn:  # one line, exit code 2
        if message == "argument --xyz: expected 3 arguments":
            message += " (a planar arm's two coordinates across its plane: --xy A B)"
        print(f"armik: error: {message} (see '{self.prog} --help')", file=sys.stderr)
        raise SystemExit(2)


def _info(args: argparse.Namespace) -> int:
    args.tip = [*(args.tip or ()), *(args.tips or ())] or None  # --tips A B: --tip A --tip B
    return later("tips:cmd_info_tips" if len(args.tip or ()) > 1 else "arms:cmd_info")(args)


def _solve(args: argparse.Namespace) -> int:
    return later("tips:cmd_solve_tips" if len(args.tip or ()) > 1 else "arms:cmd_solve")(args)


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {value}")
    return value


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="armik", description="Inverse kinematics for URDF robot arms.")
    p.add_argument("--version", action="version", version=f"armik {__version__}")
    sub = p.add_subparsers(title="commands", parser_class=_Parser)

    def command(name: str, helptext: str, example: str, func) -> argparse.ArgumentParser:
        c = sub.add_parser(
            name,
            help=helptext,
            description=helptext,
            epilog=f"example: {example}",
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        c.set_defaults(func=func, command_parser=c)
        return c

    command(
        "robots",
        "list the bundled arms with their DOF and tip",
        "armik robots",
        later("arms:cmd_robots"),
    )

    c = command(
        "info",
        "show an arm's chain and which solvers apply",
        "armik info panda\n"
        "         armik info talos_reduced.urdf --tip gripper_left_base_link "
        "--tip gripper_right_base_link",
        _info,
    )
    add_arm_arguments(
        c,
        base="base frame (default: URDF root)",
        tip="tip frame (default: catalogue tip, tool0, or the end of the longest chain); "
        "repeat it for several tips of one robot: each chain and the joints they share",
        repeat_tip=True,
        tips=True,
    )
    c.add_argument("--frames", action="store_true", help="print the URDF's frames as a tree")

    c = command(
        "solve",
        "solve IK for a target pose",
        "armik solve ur5 --xyz 0.4 0.2 0.3 --rpy 3.1416 0 0 --solver dls\n"
        "         armik solve ur5 --xyz 0.4 0.2 0.3 --axis 0 0 1 --toward 0 0 -1 --within 0.05\n"
        "         armik solve ur5 --xyz 0.4 0.2 0.3 --axis 0 0 1 --look-at 0.6 0.2 0\n"
        "         armik solve ROBOT --tip A --xyz 0.4 0.3 0.3 --rpy 0 0 0 "
        "--tip B --xyz 0.4 -0.3 0.3 --rpy 0 0 0",
        _solve,
    )
    # the target flags are repeatable: the n-th of each goes with the n-th --tip
    add_arm_arguments(
        c,
        tip="tip frame; repeat it, each followed by its target, for several tips of one robot",
        repeat_tip=True,
    )
    where = c.add_mutually_exclusive_group(required=True)
    where.add_argument(
        "--xyz",
        nargs=3,
        type=float,
        action="append",
        metavar=("X", "Y", "Z"),
        help="target position in the base frame (m); once per --tip",
    )
    where.add_argument(
        "--xy",
        nargs=2,
        type=float,
        action="append",
        dest="xyz",  # in --xyz's place: the n-th position, 2 numbers
        metavar=("A", "B"),
        help="instead of --xyz on a planar arm: a position on its plane by the base's two "
        "axes across it, (x, y), (x, z) or (y, z) (m)",
    )
    rot = c.add_mutually_exclusive_group()
    rot.add_argument(
        "--rpy",
        nargs=3,
        type=float,
        action="append",
        metavar=("R", "P", "Y"),
        help="target roll, pitch, yaw (rad); omit both for a position target",
    )
    rot.add_argument(
        "--quat",
        nargs=4,
        type=float,
        action="append",
        metavar=("X", "Y", "Z", "W"),
        help="target quaternion, (x, y, z, w) order",
    )
    c.add_argument(
        "--axis",
        nargs=3,
        type=float,
        action="append",
        metavar=("AX", "AY", "AZ"),
        help="instead of --rpy/--quat: this axis of the tip (its own frame) points along "
        "--toward (or at the point --look-at), within --within; its spin about it is free",
    )
    c.add_argument(
        "--toward",
        nargs=3,
        type=float,
        action="append",
        metavar=("DX", "DY", "DZ"),
        help="the direction --axis points along, in the base frame",
    )
    c.add_argument(
        "--look-at",
        nargs=3,
        type=float,
        action="append",
        metavar=("PX", "PY", "PZ"),
        help="instead of --toward: the point --axis points at, in the base frame (m)",
    )
    c.add_argument(
        "--within",
        type=float,
        action="append",
        metavar="ANGLE",
        help="how far --axis may lie from --toward or --look-at (rad, 0 by default)",
    )
    c.add_argument("--solver", default="auto", help="solver name or 'auto' (default)")
    c.add_argument("--all", action="store_true", help="print every solution found")
    c.add_argument("--q0", nargs="+", type=float, help="seed joint values (rad, m)")
    c.add_argument("--tol", type=float, help="success tolerance, m and rad (1e-6)")
    add_solve_options(c, axis=True)
    c.add_argument("--json", action="store_true", help="machine-readable output")

    command(
        "demo",
        "solve a target on the 2-link arm and on the Panda",
        "armik demo",
        later("arms:cmd_demo"),
    )
    add_many_commands(command)  # batch, reach
    add_compile_command(command)
    add_export_command(command)
    add_view_command(command)
    add_servo_command(command)

    c = command(
        "bench",
        "benchmark the numeric solvers (TRAC-IK's protocol)",
        "armik bench --arms panda ur5 -n 2000 --peers rtb eaik",
        later("studies:cmd_bench"),
    )
    c.add_argument("--arms", nargs="+", help="arms to run (default: every bundled spatial arm)")
    c.add_argument("--solvers", nargs="+", help="solvers to run (default: dls qp clik)")
    c.add_argument("-n", type=int, default=2000, help="targets per arm (2000)")
    c.add_argument("--budget", type=float, default=0.005, help="seconds per solve (0.005)")
    c.add_argument("--seed", type=seed_number, default=42, help="sampling seed (42)")
    c.add_argument("--tol", type=float, default=1e-5, help="success tolerance, m and rad")
    c.add_argument(
        "--repeats", type=int, default=1, help="passes over the targets, other solver seeds (1)"
    )
    c.add_argument(
        "--peers",
        nargs="+",
        default=[],
        help="other IK libraries timed on the same targets: rtb (Robotics Toolbox ik_LM), eaik "
        "(needs armik[peers])",
    )
    c.add_argument("--tip", help="the tip frame of the arms given (a URDF with several ends)")
    c.add_argument("--json", action="store_true", help="print JSON rows")

    c = command(
        "compare",
        "compare the analytic and numeric solvers, optionally with plots",
        "armik compare -n 500 --plot out/",
        later("studies:cmd_compare"),
    )
    c.add_argument("-n", type=_positive_int, default=500, help="targets per experiment (500)")
    c.add_argument("--seed", type=seed_number, default=7, help="sampling seed (7)")
    c.add_argument("--plot", metavar="DIR", help="write PNG figures to DIR (needs armik[plot])")
    c.add_argument("--json", action="store_true", help="print JSON")
    c.add_argument(
        "--speed",
        action="store_true",
        help="only time the closed forms' solve and solve_all against EAIK, interleaved",
    )
    return p
