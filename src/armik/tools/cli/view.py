"""``armik view``: an arm (or several tips of one robot) in the browser, each target on a
gizmo that solves as it is dragged; ``--path`` shows a path's plans side by side. Ctrl-C
stops it (exit 0)."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from armik.arm import Arm
from armik.arms import Arms
from armik.constraints.shapes_file import read_shapes
from armik.errors import InputError
from armik.loading import load
from armik.tools.cli.arms import load_arm, locked_joints
from armik.tools.cli.many import path_start, read_targets_file


def cmd_view(args: argparse.Namespace) -> int:
    from armik.view.server import import_viser
    from armik.view.viewer import Viewer

    import_viser()  # without the extra, say what to install before loading and solving
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
            locked = locked_joints(args.lock)
            robot: Arm | Arms = load(args.robot, base=args.base, tips=tips, locked=locked)
        else:
            args.tip = tips or None  # --tips A alone is --tip A
            robot = load_arm(args)
        # the obstacles are drawn, and every solve (a drag, the ghosts, --path's plans) and
        # --servo's servo keeps clear of them, as armik.view(arm, obstacles=...) does
        options: dict = {} if args.timeout is None else {"timeout": args.timeout}
        if obstacles:
            options["obstacles"] = obstacles
        paths = _solve_paths(robot, args, obstacles) if args.path else {}
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
            viewer.follow(obstacles=obstacles or None)  # None: no collision rows
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


def _solve_paths(arm, args: argparse.Namespace, obstacles: list) -> dict:
    """Each ``--plan``'s ``solve_path`` over the waypoints of ``--path``, clear of
    ``obstacles``, from the start ``armik path`` takes (without one, the first waypoint
    free: a followed plan solves it from the middle of the limits, a global one on any
    branch)."""
    poses, in_file = read_targets_file(args.path)
    q0 = path_start(args.path, in_file, args.q0)  # as armik path reads the file
    clear = {"obstacles": obstacles} if obstacles else {}
    return {
        plan: arm.solve_path(
            poses,
            q0,
            max_joint_step=args.max_joint_step,
            plan=plan,
            solver=args.solver,
            **clear,
        )
        for plan in dict.fromkeys(args.plan)
    }
