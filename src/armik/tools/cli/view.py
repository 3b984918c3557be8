"""``armik view``: an arm (or several tips of one robot) in the browser, each target on a
gizmo that solves as it is dragged; ``--path`` shows a path's plans side by side. Ctrl-C
stops it (exit 0)."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from armik.arm import Arm, load
from armik.arms import Arms
from armik.constraints.shapes_file import read_shapes
from armik.errors import InputError
from armik.tools.cli.arms import add_arm_arguments, load_arm
from armik.tools.cli.many import read_targets_file


def add_view_command(command) -> None:
    c = command(
        "view",
        "show an arm in the browser: drag the target and the arm follows (needs armik[view])",
        "armik view panda --port 8080 --solver dls",
        cmd_view,
    )
    add_arm_arguments(
        c,
        tip="tip frame; repeat it for several tips of one robot (as info and solve take "
        "them): the whole robot, a gizmo per tip",
        repeat_tip=True,
        tips=True,
        lock=False,
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
        help='JSON list of boxes and spheres to draw, e.g. [{"type": "sphere", "radius": 0.1, '
        '"center": [0.4, 0, 0.3]}] (drawn only: the solvers do not avoid them yet)',
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
        help="the configuration --path starts from (rad, m); default: the middle of the "
        "limits, or for the global plan any branch",
    )
    c.add_argument(
        "--servo",
        action="store_true",
        help="drags are followed by the servo within every limit, not solved (the panel's box)",
    )
    c.add_argument("--no-browser", action="store_true", help="do not open a browser tab")


def cmd_view(args: argparse.Namespace) -> int:
    from armik.view.viewer import Viewer

    viewer = None
    try:
        obstacles = read_shapes(args.obstacles) if args.obstacles else []
        tips = [*(args.tip or ()), *(args.tips or ())]
        if len(tips) > 1:
            if args.path:
                raise InputError(
                    f"--path takes the waypoints of one tip, got {len(tips)} tips {tips}: "
                    "give one --tip (or none)"
                )
            robot: Arm | Arms = load(args.robot, base=args.base, tips=tips)
        else:
            args.tip = tips or None  # --tips A alone is --tip A
            robot = load_arm(args)
        paths = _solve_paths(robot, args) if args.path else {}
        options = {} if args.timeout is None else {"timeout": args.timeout}
        viewer = Viewer(
            robot,
            port=args.port,
            host=args.host,
            open_browser=not args.no_browser,
            solver=args.solver,
            **options,
        )
        if obstacles:
            viewer.add_obstacles(obstacles)
        if args.servo:
            viewer.follow()
        for plan, batch in paths.items():
            bad = np.flatnonzero(~batch.success)
            where = f", failed at {bad[:10].tolist()}" if len(bad) else ""
            print(f"armik: {plan}: {int(batch.success.sum())}/{len(batch)} waypoints{where}")
        if paths:
            viewer.play_paths(paths)
        print(f"armik: {viewer.robot.name} at {viewer.url} (Ctrl-C to stop)", flush=True)
        viewer.wait()
    except KeyboardInterrupt:  # before the viewer was up: loading, compiling
        pass
    finally:
        if viewer is not None:
            viewer.close()
    print("armik: viewer stopped", file=sys.stderr)
    return 0


def _solve_paths(arm, args: argparse.Namespace) -> dict:
    """Each ``--plan``'s ``solve_path`` over the waypoints of ``--path``."""
    poses, _ = read_targets_file(args.path)
    q0 = None if args.q0 is None else np.array(args.q0)
    return {
        plan: arm.solve_path(
            poses,
            arm.middle if q0 is None and plan == "follow" else q0,
            max_joint_step=args.max_joint_step,
            plan=plan,
            solver=args.solver,
        )
        for plan in dict.fromkeys(args.plan)
    }
