"""``armik view``: an arm in the browser, its target on a gizmo that solves as it is dragged;
Ctrl-C stops it (exit 0)."""

from __future__ import annotations

import argparse
import sys

from armik.constraints.shapes_file import read_shapes
from armik.tools.cli.arms import load_arm


def add_view_command(command) -> None:
    c = command(
        "view",
        "show an arm in the browser: drag the target and the arm follows (needs armik[view])",
        "armik view panda --port 8080 --solver dls",
        cmd_view,
    )
    c.add_argument("robot", help="bundled robot name or path to a URDF file")
    c.add_argument("--base", help="base frame")
    c.add_argument("--tip", help="tip frame")
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
    c.add_argument("--no-browser", action="store_true", help="do not open a browser tab")


def cmd_view(args: argparse.Namespace) -> int:
    from armik.view.viewer import Viewer

    viewer = None
    try:
        obstacles = read_shapes(args.obstacles) if args.obstacles else []
        arm = load_arm(args)
        options = {} if args.timeout is None else {"timeout": args.timeout}
        viewer = Viewer(
            arm,
            port=args.port,
            host=args.host,
            open_browser=not args.no_browser,
            solver=args.solver,
            **options,
        )
        if obstacles:
            viewer.add_obstacles(obstacles)
        print(f"armik: {arm.name} at {viewer.url} (Ctrl-C to stop)", flush=True)
        viewer.wait()
    except KeyboardInterrupt:  # before the viewer was up: loading, compiling
        pass
    finally:
        if viewer is not None:
            viewer.close()
    print("armik: viewer stopped", file=sys.stderr)
    return 0
