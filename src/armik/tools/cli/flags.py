"""The flags the commands share: the arm a command works on and the options of a solve.

Parsing only: this module imports nothing of the library, so that ``armik --help`` and the
parsing of any command import none of it (the command's own module is imported when it
runs, ``commands.later``).
"""

from __future__ import annotations

import argparse
import re


def add_solve_options(c: argparse.ArgumentParser, axis: bool = False) -> None:
    """The options of a solve as flags (``solve``, ``batch`` and ``path``; ``axis``: the
    command takes ``--axis``, which ``--bounds`` reads in its own way)."""
    c.add_argument(
        "--tip-offset",
        nargs=3,
        type=float,
        metavar=("X", "Y", "Z"),
        help="tool point in the tip frame (m)",
    )
    c.add_argument(
        "--weights",
        nargs=6,
        type=float,
        metavar=("X", "Y", "Z", "RX", "RY", "RZ"),
        help="weights of the error in the tip frame; 0 frees an axis",
    )
    c.add_argument(
        "--bounds",
        nargs=6,
        type=float,
        metavar=("BX", "BY", "BZ", "BRX", "BRY", "BRZ"),
        help="a region around the target: each component of the error in the target frame "
        "within +- its bound (m, rad); inf frees it (TRAC-IK's bounds)"
        + ("; with --axis, the position's box (base frame) and 0 0 0 for the rotation" * axis),
    )
    c.add_argument("--position-only", action="store_true", help="ignore the target's orientation")
    c.add_argument(
        "--prefer",
        choices=["nearest", "manipulability", "limits"],
        help="the best verified answer by this score, over every branch (docs/preferences.md)",
    )
    c.add_argument("--timeout", type=float, help="time budget of numeric solvers (s)")
    c.add_argument(
        "--iterations",
        type=int,
        metavar="N",
        help="a deterministic budget instead of --timeout: at most N iterations, restarts included",
    )
    c.add_argument("--seed", type=int, help="seed of the random restarts (0)")
    c.add_argument(
        "--hold",
        action="append",
        type=hold_pair,
        metavar="NAME[=VALUE]",
        help="hold a joint at a value (rad or m), or at q0's without one, during this solve; "
        "repeatable",
    )
    c.add_argument(
        "--swivel",
        type=float,
        metavar="PSI",
        help="an SRS arm's elbow swivel angle (rad): every branch at it (the KUKA iiwa)",
    )
    c.add_argument(
        "--obstacles",
        metavar="FILE",
        help="obstacles to keep clear of, in the base frame: a JSON (or YAML) list such as "
        '[{"type": "box", "size": [0.2, 0.2, 0.4], "position": [0.5, 0, 0.2]}, '
        '{"type": "halfspace", "normal": [0, 0, 1], "offset": 0}] (see docs/collisions.md)',
    )
    c.add_argument(
        "--self-collision", action="store_true", help="keep the arm's links clear of each other"
    )
    c.add_argument(
        "--margin",
        type=float,
        metavar="M",
        help="distance every checked pair must keep (m, 0); needs --obstacles or --self-collision",
    )


def hold_pair(text: str) -> tuple[str, float | None]:
    """``NAME`` (held at q0's value) or ``NAME=VALUE`` (rad or m) as (name, value)."""
    if "=" not in text and text.strip():
        return text.strip(), None
    return lock_pair(text)


def lock_pair(text: str) -> tuple[str, float]:
    """``NAME=VALUE`` (rad or m) as (name, value); argparse reports a bad one in one line."""
    name, sep, value = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise argparse.ArgumentTypeError(
            f"expected NAME=VALUE (a joint name and its value in rad or m), got {text!r}"
        )
    try:
        number = float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"the value of {name!r} must be a number (rad or m), got {value.strip()!r}"
        ) from None
    return name, number


def add_arm_arguments(
    c: argparse.ArgumentParser,
    *,
    base: str = "base frame",
    tip: str = "tip frame",
    repeat_tip: bool = False,
    tips: bool = False,
) -> None:
    """The arm a command works on: ``robot``, ``--base`` and ``--tip`` (their help texts
    ``base`` and ``tip``; ``repeat_tip``: ``--tip`` repeatable, for several tips of one
    robot; ``tips``: ``--tips A B`` as well), and ``--lock``."""
    c.add_argument("robot", help="bundled robot name or path to a URDF file")
    c.add_argument("--base", help=base)
    c.add_argument("--tip", action="append" if repeat_tip else _OneTip, help=tip)
    if tips:
        c.add_argument(
            "--tips",
            nargs="+",
            metavar="TIP",
            help="several tips at once: --tips A B is --tip A --tip B",
        )
    add_lock_option(c)


class _OneTip(argparse.Action):
    """``--tip`` of a command that works on one tip: a second, other one is refused (exit 2),
    not silently taken in place of the first."""

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        before = getattr(namespace, self.dest, None)
        if before is not None and before != values:
            parser.error(
                f"--tip given twice ({before!r}, then {values!r}): '{parser.prog}' works on "
                "one tip; give --tip once (several tips of one robot: 'armik solve' and "
                "'armik info' take --tip A --tip B; in Python, armik.load(robot, tips=[A, B]))"
            )
        setattr(namespace, self.dest, values)


def add_lock_option(c: argparse.ArgumentParser) -> None:
    c.add_argument(
        "--lock",
        action="append",
        type=lock_pair,
        metavar="NAME=VALUE",
        help="hold a joint at a value (rad or m), on or off the chain; repeatable",
    )


# options a refusal starts with, and the flag that gives each on the command line
_LEADING_OPTIONS = {
    "max_joint_step": "--max-joint-step",
    "chunk_size": "--chunk-size",
    "tip_offset": "--tip-offset",
    "dt": "--dt",
    "acceleration_limits": "--acceleration-limit",
    "velocity_limits": "--velocity-limit",
    "timeout": "--timeout",
    "seed": "--seed",
    "margin": "--margin",
}


def for_cli(message: str) -> str:
    """An error's words for the command line: Python's ``tip=``, ``base=``, ``obstacles=``
    and ``self_collision=`` are the flags ``--tip``, ``--base``, ``--obstacles`` and
    ``--self-collision`` here, a 2-vector ``--xy``, ``package_dirs=`` the variable
    ``ROS_PACKAGE_PATH``, ``plan=`` ``--plan``, ``iteration_budget`` ``--iterations``, and
    the fixes ``arm.with_locked`` and ``hold=`` the flags ``--lock`` and ``--hold``, a
    ``LookAt`` at a ``Position``'s point ``--look-at`` at the ``--xyz`` point, and a
    refusal that starts with an option (``max_joint_step must ...``) starts with its flag. A
    target
    read from a file (``target 3: ...``: batch, path) came from no flag: its words stay."""
    for keyword, flag in _LEADING_OPTIONS.items():  # "max_joint_step must be ...": its flag
        if message.startswith(keyword + " "):
            message = flag + message[len(keyword) :]
    message = message.replace("e.g. dt=0.002", "e.g. --dt 0.002")
    if not re.match(r"target \d+: ", message):
        message = message.replace(
            "a 2-vector target needs a planar arm", "--xy needs a planar arm"
        ).replace(
            "give a position (x, y, z) or a full pose",
            "give --xyz X Y Z (with --rpy or --quat for a pose)",
        )
    return (
        message.replace("pass tip=", "pass --tip")
        .replace("pass base=", "pass --base")
        .replace(
            "give obstacles=[...] or self_collision=True", "give --obstacles or --self-collision"
        )
        .replace(
            "solve without obstacles= and self_collision=",
            "leave out --obstacles and --self-collision",
        )
        .replace(  # Pinocchio reads the variable; the command line has no package_dirs=
            "with armik.load(..., package_dirs=[...])",
            "in the environment variable ROS_PACKAGE_PATH=DIR[:DIR...]",
        )
        .replace("plan='global'", "--plan global")
        .replace("plan='follow'", "--plan follow")
        .replace("arm.with_locked({name: value})", "--lock NAME=VALUE")
        .replace("hold={joint: value}", "--hold NAME=VALUE")
        .replace("iteration_budget", "--iterations")
        .replace("LookAt point ", "--look-at ")  # --look-at at the --xyz point
        .replace("is where Position puts the frame itself", "is where --xyz puts the tip")
        .replace(
            "frame's position a box (bounds=)", "tip's position a box (--bounds BX BY BZ 0 0 0)"
        )
    )
