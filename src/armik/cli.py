"""The ``armik`` command line.

Exit codes: 0 success, 1 no solution found (unreachable, not converged, joint limits),
2 bad input (one line on stderr, no traceback).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin

from . import bench as bench_mod
from . import structure
from .arm import Arm, load
from .errors import ArmikError, ArmikWarning
from .ik import registry
from .result import IKResult
from .robots import CATALOGUE, SPATIAL_ARMS


def main(argv: Sequence[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", category=DeprecationWarning)
            warnings.showwarning = _one_line_warning
            return int(args.func(args) or 0)
    except ArmikError as exc:
        print(f"armik: error: {exc}", file=sys.stderr)
        return 2
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

    def error(self, message: str) -> None:  # one line, exit code 2
        print(f"armik: error: {message} (see '{self.prog} --help')", file=sys.stderr)
        raise SystemExit(2)


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
    sub = p.add_subparsers(title="commands", parser_class=_Parser)

    def command(name: str, helptext: str, example: str, func) -> argparse.ArgumentParser:
        c = sub.add_parser(
            name,
            help=helptext,
            description=helptext,
            epilog=f"example: {example}",
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        c.set_defaults(func=func)
        return c

    command("robots", "list the bundled arms with their DOF and tip", "armik robots", _robots)

    c = command("info", "show an arm's chain and which solvers apply", "armik info panda", _info)
    c.add_argument("robot", help="bundled robot name or path to a URDF file")
    c.add_argument("--base", help="base frame (default: URDF root)")
    c.add_argument(
        "--tip", help="tip frame (default: catalogue tip, tool0, or the end of the longest chain)"
    )
    c.add_argument("--frames", action="store_true", help="print the URDF's frames as a tree")

    c = command(
        "solve",
        "solve IK for a target pose",
        "armik solve ur5 --xyz 0.4 0.2 0.3 --rpy 3.1416 0 0 --solver dls",
        _solve,
    )
    c.add_argument("robot", help="bundled robot name or path to a URDF file")
    c.add_argument("--base", help="base frame")
    c.add_argument("--tip", help="tip frame")
    c.add_argument(
        "--xyz",
        nargs=3,
        type=float,
        required=True,
        metavar=("X", "Y", "Z"),
        help="target position in the base frame (m)",
    )
    rot = c.add_mutually_exclusive_group()
    rot.add_argument(
        "--rpy",
        nargs=3,
        type=float,
        metavar=("R", "P", "Y"),
        help="target roll, pitch, yaw (rad); omit both for a position target",
    )
    rot.add_argument(
        "--quat",
        nargs=4,
        type=float,
        metavar=("X", "Y", "Z", "W"),
        help="target quaternion, (x, y, z, w) order",
    )
    c.add_argument("--solver", default="auto", help="solver name or 'auto' (default)")
    c.add_argument("--all", action="store_true", help="print every solution found")
    c.add_argument("--q0", nargs="+", type=float, help="seed joint values (rad, m)")
    c.add_argument("--timeout", type=float, help="time budget of numeric solvers (s)")
    c.add_argument("--json", action="store_true", help="machine-readable output")

    command("demo", "solve a target on the 2-link arm and on the Panda", "armik demo", _demo)
    _batch_commands(command)  # batch, reach

    c = command(
        "bench",
        "benchmark the numeric solvers (TRAC-IK's protocol)",
        "armik bench --arms panda ur5 -n 2000 --peers rtb eaik",
        _bench,
    )
    c.add_argument("--arms", nargs="+", default=list(SPATIAL_ARMS), help="arms to run")
    c.add_argument(
        "--solvers", nargs="+", default=list(bench_mod.DEFAULT_SOLVERS), help="dls qp clik"
    )
    c.add_argument("-n", type=int, default=2000, help="targets per arm (2000)")
    c.add_argument("--budget", type=float, default=0.005, help="seconds per solve (0.005)")
    c.add_argument("--seed", type=int, default=42, help="sampling seed (42)")
    c.add_argument("--tol", type=float, default=1e-5, help="success tolerance, m and rad")
    c.add_argument(
        "--repeats", type=int, default=1, help="passes over the targets, other solver seeds (1)"
    )
    c.add_argument(
        "--peers",
        nargs="+",
        default=[],
        help="other IK libraries timed on the same targets: rtb (Robotics Toolbox ik_LM), eaik",
    )
    c.add_argument("--json", action="store_true", help="print JSON rows")

    c = command(
        "compare",
        "compare the analytic and numeric solvers, optionally with plots",
        "armik compare -n 500 --plot out/",
        _compare,
    )
    c.add_argument("-n", type=_positive_int, default=500, help="targets per experiment (500)")
    c.add_argument("--seed", type=int, default=7)
    c.add_argument("--plot", metavar="DIR", help="write PNG figures to DIR (needs matplotlib)")
    c.add_argument("--json", action="store_true", help="print JSON")
    c.add_argument(
        "--speed",
        action="store_true",
        help="only time the closed forms' solve and solve_all against EAIK, interleaved",
    )
    return p


def _load(args: argparse.Namespace) -> Arm:
    return load(args.robot, base=getattr(args, "base", None), tip=getattr(args, "tip", None))


def _robots(args: argparse.Namespace) -> int:
    print(f"{'name':<16} {'dof':>3}  {'tip':<24} description")
    for name, spec in CATALOGUE.items():
        arm = load(name)
        print(f"{name:<16} {arm.dof:>3}  {arm.tip:<24} {spec.description}")
    return 0


def _info(args: argparse.Namespace) -> int:
    arm = _load(args)
    print(f"{arm.name}: {arm.dof} joints from {arm.base!r} to {arm.tip!r}  ({arm.source})")
    if arm.tip_reason != "given":
        print(f"  tip: {arm.tip_reason}")
    for note in arm.info.notes:
        print(f"  note: {note}")
    if args.frames:
        print("frames (link, then [joint type] joint -> child link):")
        for line in frame_tree(arm.info):
            print(f"  {line}")
    print(f"  {'joint':<24} {'type':<11} {'lower':>9} {'upper':>9}  link to next (m)")
    for i, (name, jtype) in enumerate(zip(arm.joint_names, arm.joint_types)):
        print(
            f"  {name:<24} {jtype:<11} {arm.lower[i]:>9.4f} {arm.upper[i]:>9.4f}  "
            f"{_link_lengths(arm)[i]:.4f}"
        )
    if arm.plane is not None:
        print(f"  planar: all axes along {np.round(arm.plane.normal, 6).tolist()}")
    print("structure:")
    for cls, geo in structure.classify(arm).items():
        if isinstance(geo, str):
            print(f"  {cls:<16} no: {geo}")
        else:
            text = getattr(geo, "description", "all joint axes parallel")
            print(f"  {cls:<16} yes: {text}")
    print("solvers:")
    width = max(map(len, registry.solvers()))
    for name in registry.solvers():
        reason = registry.why_not(name, arm)
        spec = registry.get(name)
        state = "applies" if reason is None else f"does not apply: {reason}"
        print(f"  {name:<{width}} ({spec.kind}) {state}")
    print(f"  auto -> {registry.choose('auto', arm).name}")
    return 0


def frame_tree(info) -> list[str]:
    """The URDF's links and joints as indented tree lines (iterative: trees can be deep)."""
    children = info.children()
    lines: list[str] = []
    stack = [(info.root_link, "", "", None)]
    while stack:
        link, lead, tail, joint = stack.pop()
        label = link if joint is None else f"[{joint.type}] {joint.name} -> {link}"
        lines.append(lead + label)
        kids = children.get(link, [])
        for k, j in reversed(list(enumerate(kids))):
            last = k == len(kids) - 1
            stack.append(
                (j.child, tail + ("`- " if last else "|- "), tail + ("   " if last else "|  "), j)
            )
    return lines


def _link_lengths(arm: Arm) -> list[float]:
    """Distance from each joint's origin to the next joint's (the last: to the tip)."""
    arm.fk(arm.middle)
    data = arm.data
    points = [data.oMi[j].translation for j in range(1, arm.model.njoints)]
    points.append(data.oMf[arm.tip_frame_id].translation)
    return [float(np.linalg.norm(b - a)) for a, b in zip(points, points[1:])]


def _target(args: argparse.Namespace) -> object:
    xyz = np.array(args.xyz)
    if args.quat is not None:
        return (xyz, np.array(args.quat))
    if args.rpy is not None:
        return pin.SE3(pin.rpy.rpyToMatrix(*args.rpy), xyz)
    return xyz


def _solve(args: argparse.Namespace) -> int:
    arm = _load(args)
    options = {} if args.timeout is None else {"timeout": args.timeout}
    target = _target(args)
    if args.all:
        results = arm.solve_all(target, q0=args.q0, solver=args.solver, **options)
    else:
        results = [arm.solve(target, q0=args.q0, solver=args.solver, **options)]
    if args.json:
        print(
            json.dumps(
                {
                    "robot": arm.name,
                    "joints": arm.joint_names,
                    "results": [r.as_dict() for r in results],
                },
                indent=2,
            )
        )
    else:
        for i, r in enumerate(results):
            if len(results) > 1:
                print(f"solution {i + 1} of {len(results)}")
            _print_result(arm, r, show_time=len(results) == 1)
        if len(results) > 1:
            print(f"time: {results[0].time * 1e3:.3f} ms for the call ({len(results)} solutions)")
    return 0 if any(r.success for r in results) else 1


def _print_result(arm: Arm, r: IKResult, indent: str = "  ", show_time: bool = True) -> None:
    print(
        f"{indent}status   : {r.status} (success={r.success}), solver {r.solver}"
        + (f", branch {r.branch}" if r.branch else "")
    )
    for name, value, jtype in zip(arm.joint_names, r.q, arm.joint_types):
        unit = "m" if jtype == "prismatic" else f"rad ({math.degrees(value):9.4f} deg)"
        print(f"{indent}  {name:<22} {value: .9f} {unit}")
    ori = "n/a" if r.orientation_error is None else f"{r.orientation_error:.2e} rad"
    print(f"{indent}FK error : position {r.position_error:.2e} m, orientation {ori}")
    if show_time:
        print(f"{indent}time     : {r.time * 1e3:.3f} ms, {r.iterations} iterations")
    else:
        print(f"{indent}iterations: {r.iterations}")
    print(f"{indent}reason   : {r.reason}")


def _demo(args: argparse.Namespace) -> int:
    ok = True
    arm = load("planar_2link")
    print("planar_2link (l1 = 1.0 m, l2 = 0.8 m), target (x, y) = (1.2, 0.5):")
    for r in arm.solve_all([1.2, 0.5]):
        _print_result(arm, r)
        ok &= r.success
    panda = load("panda")
    q_goal = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
    T = panda.fk(q_goal)
    print(
        f"\npanda: full pose target at p = {np.round(T.translation, 4).tolist()} m, "
        "seeded from the mid-limit configuration:"
    )
    r = panda.solve(T, q0=panda.middle)
    _print_result(panda, r)
    ok &= r.success
    return 0 if ok else 1


def _bench(args: argparse.Namespace) -> int:
    notes: list[str] = []
    rows = bench_mod.run(
        _names(args.arms),
        _names(args.solvers),
        n=args.n,
        budget=args.budget,
        seed=args.seed,
        tol=args.tol,
        repeats=args.repeats,
        show_progress=not args.json,
        peers=_names(args.peers),
        notes=notes,
    )
    if args.json:
        print(json.dumps([r.as_dict() for r in rows], indent=2))
    else:
        passes = f" x {args.repeats} passes (other solver seeds)" if args.repeats > 1 else ""
        print(
            f"N = {args.n} targets per arm{passes}, budget {args.budget * 1e3:g} ms, tolerance "
            f"{args.tol:g} m / rad, seeds from mid-limits, sampling seed {args.seed}"
        )
        print(bench_mod.table(rows))
        for line in bench_mod.ratios(rows) + notes:
            print(line)
    return 0


def _names(values: list[str]) -> list[str]:
    """Names given as separate words or comma-separated ("dls qp" or "dls,qp")."""
    return [name for value in values for name in value.split(",") if name]


def _compare(args: argparse.Namespace) -> int:
    from . import compare

    if args.speed:
        rows = compare.speed(n=args.n, seed=args.seed)
        if args.json:
            print(json.dumps(rows, indent=2))
        else:
            print(compare.speed_table(rows))
        return 0
    report = compare.run(n=args.n, seed=args.seed)
    if args.json:
        print(json.dumps(report.as_dict(), indent=2))
    else:
        print(report.text())
    if args.plot:
        for path in compare.plot(report, args.plot):
            print(f"wrote {path}")
    return 0


# -- many targets: batch and reach ---------------------------------------------------------


def _batch_commands(command) -> None:
    c = command(
        "batch",
        "solve IK for many targets read from a file, on every core or on a Dask cluster; "
        "exit 0 once the results are written, whatever their success",
        "armik batch panda targets.npy -o out.npz --workers 2",
        _batch,
    )
    c.add_argument("robot", help="bundled robot name or path to a URDF file")
    c.add_argument(
        "targets",
        help="targets file: .npy or .npz (the array 'targets', or the only array; an array "
        "'q0' gives seeds) or .csv; rows x y z (positions), x y z qx qy qz qw, 16 numbers of "
        "a 4x4 transform, or an (N, 4, 4) array",
    )
    c.add_argument("-o", "--output", required=True, help="results file (.npz)")
    c.add_argument("--base", help="base frame")
    c.add_argument("--tip", help="tip frame")
    c.add_argument("--solver", default="auto", help="solver name or 'auto' (default)")
    c.add_argument("--workers", type=int, help="threads (default: one per core)")
    c.add_argument(
        "--cluster",
        metavar="ADDRESS",
        help="run on a Dask cluster: tcp://host:8786, or local:N for N local processes",
    )
    c.add_argument("--q0", nargs="+", type=float, help="one seed for every target (rad, m)")
    c.add_argument("--timeout", type=float, help="time budget per target (s)")
    c.add_argument("--tol", type=float, help="success tolerance, m and rad")
    c.add_argument("--seed", type=int, help="seed of the random restarts (0)")
    c.add_argument("--chunk-size", type=int, help="targets per task")

    c = command(
        "reach",
        "reachability map: per voxel, the fraction of tool orientations the arm reaches",
        "armik reach panda --resolution 0.1 --orientations 16 -o reach.npz --plot reach.png",
        _reach,
    )
    c.add_argument("robot", help="bundled robot name or path to a URDF file")
    c.add_argument("--base", help="base frame")
    c.add_argument("--tip", help="tip frame")
    c.add_argument("--resolution", type=float, default=0.1, help="voxel side, m (0.1)")
    c.add_argument("--orientations", type=int, default=16, help="per voxel (16)")
    c.add_argument("--timeout", type=float, default=0.005, help="budget per solve, s (0.005)")
    c.add_argument("--solver", default="auto", help="solver name or 'auto' (default)")
    c.add_argument("--workers", type=int, help="threads (default: one per core)")
    c.add_argument("--cluster", metavar="ADDRESS", help="run on a Dask cluster (see batch)")
    c.add_argument("--seed", type=int, default=0, help="orientation sample seed (0)")
    c.add_argument("-o", "--output", default="reach.npz", help="map file (reach.npz)")
    c.add_argument("--plot", metavar="PNG", help="also draw slices into this PNG")


def read_targets_file(path: str) -> tuple[np.ndarray, np.ndarray | None]:
    """The targets array of a .npy, .npz or .csv file, and the seeds if the file has them.

    Raises ``InputError`` with one line naming the file and the problem."""
    from pathlib import Path

    from .errors import InputError

    p = Path(path)
    if not p.is_file():
        raise InputError(f"targets file {path!r} does not exist (or is not a file)")
    suffix = p.suffix.lower()
    q0 = None
    try:
        if suffix == ".npy":
            arr = np.load(p, allow_pickle=False)
        elif suffix == ".npz":
            with np.load(p, allow_pickle=False) as z:
                names = list(z.files)
                if "targets" in names:
                    arr = z["targets"]
                elif len([n for n in names if n != "q0"]) == 1:
                    arr = z[next(n for n in names if n != "q0")]
                else:
                    raise InputError(
                        f"{path!r} holds the arrays {names}: name the targets array 'targets'"
                    )
                q0 = z["q0"] if "q0" in names else None
        elif suffix == ".csv":
            arr = _read_csv(p)
        else:
            raise InputError(f"targets file {path!r}: give a .npy, .npz or .csv file")
    except InputError:
        raise
    except (OSError, ValueError, EOFError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"cannot read targets from {path!r}: {first}") from None
    if arr.ndim == 2 and arr.shape[1] == 16:
        arr = arr.reshape(-1, 4, 4)
    return arr, q0


def _read_csv(path) -> np.ndarray:
    import csv

    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].lstrip().startswith("#")]
    if rows and not _numeric(rows[0]):
        rows = rows[1:]  # a header line
    widths = {len(r) for r in rows}
    if len(widths) > 1:
        raise ValueError(f"rows have different numbers of columns: {sorted(widths)}")
    out = np.empty((len(rows), widths.pop() if widths else 0))
    for i, r in enumerate(rows):
        try:
            out[i] = [float(v) for v in r]
        except ValueError:
            raise ValueError(f"row {i + 1} is not numbers: {','.join(r)[:80]}") from None
    return out


def _numeric(row: list[str]) -> bool:
    try:
        [float(v) for v in row]
    except ValueError:
        return False
    return True


def _solve_options(args: argparse.Namespace) -> dict:
    options: dict = {}
    if args.timeout is not None:
        options["timeout"] = args.timeout
    if getattr(args, "tol", None) is not None:
        options["tol_position"] = options["tol_orientation"] = args.tol
    if getattr(args, "seed", None) is not None:
        options["seed"] = args.seed
    return options


def _batch(args: argparse.Namespace) -> int:
    from pathlib import Path

    from .errors import InputError

    out = Path(args.output)
    if out.suffix.lower() != ".npz":
        raise InputError(f"output {args.output!r}: results are written as .npz; name it *.npz")
    if not out.parent.is_dir():
        raise InputError(f"output folder {str(out.parent)!r} does not exist")
    arm = _load(args)
    targets, q0 = read_targets_file(args.targets)
    if args.q0 is not None:
        q0 = np.array(args.q0)
    options = _solve_options(args)
    if args.cluster:
        from . import distributed

        result = distributed.solve_batch(
            arm,
            targets,
            q0=q0,
            solver=args.solver,
            address=args.cluster,
            chunk_size=args.chunk_size,
            **options,
        )
    else:
        from .batch import solve_batch

        result = solve_batch(
            arm,
            targets,
            q0=q0,
            solver=args.solver,
            workers=args.workers,
            chunk_size=args.chunk_size,
            **options,
        )
    result.save(out)
    print(result.summary())
    print(f"wrote {out}")
    return 0


def _reach(args: argparse.Namespace) -> int:
    from .reach import reachability

    arm = _load(args)
    client = None
    if args.cluster:
        from .distributed import connect

        client = connect(args.cluster)
    try:
        m = reachability(
            arm,
            args.resolution,
            args.orientations,
            solver=args.solver,
            workers=args.workers,
            seed=args.seed,
            client=client,
            timeout=args.timeout,
        )
    finally:
        if client is not None:
            from .distributed import close

            close(client)
    print(m.summary())
    print(f"wrote {m.save(args.output)}")
    if args.plot:
        print(f"wrote {m.plot(args.plot)}")
    return 0
