"""The parsers of the commands on files, the compiler, the exporter, the viewer and the servo.

Parsing only: the command functions are named by ``later`` and imported when the command
runs, so that ``armik --help`` and parsing import none of the library.
"""

from __future__ import annotations

import argparse
import importlib
from collections.abc import Callable

from armik.tools.cli.flags import add_arm_arguments, add_solve_options

# ``armik.precompile.PARTS``' names, for ``armik compile --help`` without importing the
# library (tests/tools/test_cli.py checks them against PARTS)
PART_NAMES = (
    "dls",
    "qp",
    "clik",
    "planar2r",
    "spherical",
    "three_parallel",
    "spherical_general",
    "three_parallel_general",
    "spherical_shoulder",
    "search_1d",
    "swept",
    "srs",
    "general_6r",
    "elimination_6r",
    "hold",
    "batch",
    "path",
    "fk_batch",
    "tasks",
    "collisions",
    "servo",
)


def later(where: str) -> Callable[[argparse.Namespace], int]:
    """The command function ``"module:name"`` of ``armik.tools.cli``, imported when it runs."""
    module, name = where.split(":")

    def run(args: argparse.Namespace) -> int:
        return getattr(importlib.import_module(f"armik.tools.cli.{module}"), name)(args)

    return run


def seed_number(text: str) -> int:
    """A ``--seed`` (a sampling seed): a whole number in [0, 2**32 - 1], as numpy seeds."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value < 2**32:
        raise argparse.ArgumentTypeError(
            f"expected a whole number in [0, 4294967295] (a sampling seed), got {text!r}"
        )
    return value


def add_many_commands(command) -> None:
    c = command(
        "batch",
        "solve IK for many targets read from a file, on every core or on a Dask cluster; "
        "exit 0 once the results are written, whatever their success",
        "armik batch panda targets.npy -o out.npz --workers 2",
        later("many:cmd_batch"),
    )
    add_arm_arguments(c)
    c.add_argument(
        "targets",
        help="targets file: .npy or .npz (the array 'targets', or np.savez's one 'arr_0'; an "
        "array 'q0' gives seeds) or .csv; rows x y z (positions), x y z qx qy qz qw, 16 numbers of "
        "a 4x4 transform, or an (N, 4, 4) array",
    )
    c.add_argument("-o", "--output", required=True, help="results file (.npz)")
    c.add_argument("--solver", default="auto", help="solver name or 'auto' (default)")
    c.add_argument("--workers", type=int, help="threads (default: one per core)")
    c.add_argument(
        "--cluster",
        metavar="ADDRESS",
        help="run on a Dask cluster: tcp://host:8786, or local:N for N local processes "
        "(needs armik[cluster])",
    )
    c.add_argument(
        "--q0",
        nargs="+",
        type=float,
        help="one seed for every target (rad, m), in place of the file's 'q0'",
    )
    c.add_argument("--tol", type=float, help="success tolerance, m and rad")
    add_solve_options(c)
    c.add_argument("--chunk-size", type=int, help="targets per task")

    c = command(
        "path",
        "solve waypoints read from a file in order, never with a silent jump: followed from "
        "the previous answer, or planned over every branch (--plan global); exit 0 once the "
        "results are written, whatever their success",
        "armik path ur5 seam.npy -o path.npz --plan global --max-joint-step 0.3",
        later("many:cmd_path"),
    )
    add_arm_arguments(c)
    c.add_argument(
        "targets",
        help="waypoints file, as for batch; an .npz's array 'q0' (one configuration) is the start",
    )
    c.add_argument("-o", "--output", required=True, help="results file (.npz)")
    c.add_argument(
        "--q0",
        nargs="+",
        type=float,
        help="the configuration the arm starts from (rad, m), in place of the file's 'q0'; "
        "default: the file's 'q0', else none, the first waypoint free (followed: solved "
        "from the middle of the limits; global: any branch)",
    )
    c.add_argument(
        "--plan",
        choices=["follow", "global"],
        default="follow",
        help="follow: each waypoint from the previous answer (default); global: every branch "
        "at every waypoint, the least total joint motion (closed-form arms)",
    )
    c.add_argument(
        "--max-joint-step",
        type=float,
        help="largest move of any joint between consecutive answers (rad or m; 0.5)",
    )
    c.add_argument("--solver", default="auto", help="solver name or 'auto' (default)")
    c.add_argument("--tol", type=float, help="success tolerance, m and rad")
    add_solve_options(c)

    c = command(
        "reach",
        "reachability map: per voxel, the fraction of tool orientations the arm reaches "
        "(an arm of fewer than 6 joints: whether it reaches the point)",
        "armik reach panda --resolution 0.1 --orientations 16 -o reach.npz --plot reach.png",
        later("many:cmd_reach"),
    )
    add_arm_arguments(c)
    c.add_argument("--resolution", type=float, default=0.1, help="voxel side, m (0.1)")
    c.add_argument(
        "--orientations",
        type=int,
        default=16,
        help="per voxel (16; unused by an arm of fewer than 6 joints: positions only)",
    )
    c.add_argument("--timeout", type=float, default=0.005, help="budget per solve, s (0.005)")
    c.add_argument("--solver", default="auto", help="solver name or 'auto' (default)")
    c.add_argument("--workers", type=int, help="threads (default: one per core)")
    c.add_argument("--cluster", metavar="ADDRESS", help="run on a Dask cluster (see batch)")
    c.add_argument("--seed", type=seed_number, default=0, help="orientation sample seed (0)")
    c.add_argument("-o", "--output", default="reach.npz", help="map file (reach.npz)")
    c.add_argument(
        "--plot", metavar="PNG", help="also draw slices into this PNG (needs armik[plot])"
    )


def add_compile_command(command) -> None:
    c = command(
        "compile",
        "compile armik's kernels for this machine into numba's cache, once (a first call "
        "then loads them in milliseconds)",
        "armik compile --all",
        later("compile:cmd_compile"),
    )
    c.add_argument("names", nargs="*", metavar="PART", help=f"parts: {', '.join(PART_NAMES)}")
    c.add_argument("--all", action="store_true", help="every part (the default)")
    c.add_argument(
        "--jobs", type=int, default=None, help="processes compiling at once (default: one per core)"
    )


def add_export_command(command) -> None:
    c = command(
        "export",
        "write an arm's closed form as plain C99 (N_ik.h, N_ik.c; --ikfast: N_ikfast.cpp, "
        "IKFast 61's interface for MoveIt)",
        "armik export ur5 --name ur5 --out ur5_ik --ikfast",
        later("export:cmd_export"),
    )
    add_arm_arguments(
        c,
        base="base frame (default: URDF root)",
        tip="tip frame (default: as armik info chooses it)",
    )
    c.add_argument("--name", required=True, help="the solver's name N, a C identifier")
    c.add_argument("--out", required=True, help="directory to write the files into")
    c.add_argument("--ikfast", action="store_true", help="also write N_ikfast.cpp")
    c.add_argument(
        "--tol-position", type=float, help="how far a solution may miss its target (m, 1e-6)"
    )
    c.add_argument("--tol-orientation", type=float, help="... and its orientation (rad, 1e-6)")


def add_view_command(command) -> None:
    c = command(
        "view",
        "show an arm in the browser: drag the target and the arm follows (needs armik[view])",
        "armik view panda --port 8080 --solver dls",
        later("view:cmd_view"),
    )
    add_arm_arguments(
        c,
        tip="tip frame; repeat it for several tips of one robot (as info and solve take "
        "them): the whole robot, a gizmo per tip",
        repeat_tip=True,
        tips=True,
    )
    c.add_argument("--port", type=int, default=8080, help="port to serve on (8080; 0: any free)")
    c.add_argument(
        "--host", default="127.0.0.1", help="address to serve on (127.0.0.1; 0.0.0.0: all)"
    )
    c.add_argument("--solver", default="auto", help="solver name or 'auto' (default)")
    c.add_argument("--timeout", type=float, help="time budget of numeric solvers (s)")
    c.add_argument(
        "--obstacles",
        metavar="FILE",
        help='JSON list of boxes and spheres, e.g. [{"type": "sphere", "radius": 0.1, '
        '"center": [0.4, 0, 0.3]}]: drawn and avoided (every solve, --path and --servo keep '
        "clear of them)",
    )
    c.add_argument(
        "--path",
        metavar="FILE",
        help="waypoints file, as for armik path: solved with each --plan and shown side by "
        "side, a slider stepping through the waypoints",
    )
    c.add_argument(
        "--plan",
        nargs="+",
        choices=["follow", "global"],
        default=["follow", "global"],
        help="the plans of --path to show (default: both)",
    )
    c.add_argument(
        "--max-joint-step",
        type=float,
        help="largest move of any joint between consecutive answers of --path (rad or m; 0.5)",
    )
    c.add_argument(
        "--q0",
        nargs="+",
        type=float,
        help="the configuration --path starts from (rad, m), in place of the file's 'q0'; "
        "default: the file's 'q0', else none, the first waypoint free (followed: solved "
        "from the middle of the limits; global: any branch), as armik path",
    )
    c.add_argument(
        "--servo",
        action="store_true",
        help="drags are followed by the servo within every limit, not solved (the panel's box)",
    )
    c.add_argument("--no-browser", action="store_true", help="do not open a browser tab")


def add_servo_command(command) -> None:
    c = command(
        "servo",
        "stream a demo trajectory through the servo (one tick a target): a circle about the "
        "tip, then a jump; print the tracking error, the limits hit and the time a tick",
        "armik servo panda --circle 0.1 --hz 0.5 --seconds 2\n"
        "         armik servo ur5 --circle 0.05 --seconds 1 --jump 0 0.25 0 --dt 0.004",
        later("servo:cmd_servo"),
    )
    add_arm_arguments(c)
    c.add_argument(
        "--q0",
        nargs="+",
        type=float,
        metavar="Q",
        help="start joint values (rad, m), within the limits (default: a bundled arm's "
        "start with room around the tip, else the best-conditioned of the middle of the "
        "limits and 64 seeded configurations within the middle half of each joint's range)",
    )
    c.add_argument(
        "--circle",
        type=float,
        default=0.1,
        metavar="R",
        help="radius (m) of the circle in the base's y-z plane through the tip, the "
        "orientation held (0.1); a planar arm's in its own plane, and an arm of fewer than "
        "6 joints', as positions",
    )
    c.add_argument("--hz", type=float, default=0.5, help="turns of the circle a second (0.5)")
    c.add_argument("--seconds", type=float, default=2.0, help="length of the circle, s (2)")
    c.add_argument(
        "--jump",
        nargs=3,
        type=float,
        metavar=("DX", "DY", "DZ"),
        help="then a target this far (m, base frame) from where the circle ends, held 1.5 s",
    )
    c.add_argument("--dt", type=float, default=0.002, help="tick period, s (0.002: 500 Hz)")
    c.add_argument(
        "--acceleration-limit",
        type=float,
        default=None,
        metavar="A",
        help="rad/s^2 on every joint, m/s^2 on a prismatic one (default: the servo's, 20)",
    )
    c.add_argument(
        "--velocity-limit",
        type=float,
        default=None,
        metavar="V",
        help="rad/s on every joint, m/s on a prismatic one (default: the URDF's)",
    )
