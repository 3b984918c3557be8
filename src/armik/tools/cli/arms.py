"""Commands on one arm: ``robots``, ``info``, ``solve`` and ``demo``."""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
from collections.abc import Sequence

import numpy as np

from armik.arm import Arm
from armik.constraints.shapes_file import read_shapes
from armik.errors import FrameError, InputError, OptionError
from armik.kernel import warmup
from armik.kernel.problem import STEP_DLS
from armik.loading import load
from armik.model.arm_model import ArmModel
from armik.model.catalogue import CATALOGUE, entry
from armik.model.urdf import read_urdf, read_urdf_string
from armik.problem.problem import as_problem
from armik.result import IKResult
from armik.solve.read import options as read_options
from armik.solve.tasks import measure_tasks
from armik.solvers import registry
from armik.solvers.closed_form import families
from armik.tools.cli.flags import for_cli
from armik.tools.cli.routes import family_lines, route_lines
from armik.tools.cli.targets import (
    flag_targets,
    for_flags,
    task_errors,
    task_lines,
    task_names,
)


def load_arm(args: argparse.Namespace) -> Arm:
    tip = getattr(args, "tip", None)
    if isinstance(tip, list):  # --tip repeatable (info, solve): one here
        tip = tip[0] if tip else None
    return load(
        args.robot,
        base=getattr(args, "base", None),
        tip=tip,
        tip_offset=getattr(args, "tip_offset", None),
        locked=locked_joints(getattr(args, "lock", None)),
    )


def solve_options(args: argparse.Namespace) -> dict:
    """The keyword options of ``Arm.solve`` the flags of ``add_solve_options`` give."""
    options: dict = {}
    if args.timeout is not None:
        options["timeout"] = args.timeout
    if getattr(args, "tol", None) is not None:
        if not (args.tol > 0 and math.isfinite(args.tol)):  # the keywords' words name neither
            raise OptionError(
                f"--tol must be a positive number of m and rad, got {args.tol:g}",
                option="--tol",
                value=args.tol,
            )
        options["tol_position"] = options["tol_orientation"] = args.tol
    if args.iterations is not None:
        options["iteration_budget"] = args.iterations
    if args.seed is not None:
        options["seed"] = args.seed
    if args.hold:
        options["hold"] = joint_values(args.hold, "--hold")
    if getattr(args, "swivel", None) is not None:
        options["swivel"] = args.swivel
    if args.weights is not None:
        options["weights"] = tuple(args.weights)
    if args.bounds is not None:
        options["bounds"] = tuple(args.bounds)
    if args.position_only:
        options["position_only"] = True
    if getattr(args, "prefer", None) is not None:
        options["prefer"] = args.prefer
    if args.obstacles is not None:
        options["obstacles"] = read_shapes(args.obstacles)
    if args.self_collision:
        options["self_collision"] = True
    if args.margin is not None:
        options["margin"] = args.margin
    return options


def locked_joints(pairs: list[tuple[str, float]] | None) -> dict[str, float] | None:
    """The ``--lock`` pairs as a mapping; a joint given twice is an ``InputError``."""
    return joint_values(pairs, "--lock") if pairs else None


def joint_values(pairs: list, flag: str) -> dict:
    """``flag``'s (name, value) pairs as a mapping; a joint given twice is an ``InputError``."""
    out: dict = {}
    for name, value in pairs:
        if name in out:
            raise InputError(
                f"{flag} gives joint {name!r} twice ({out[name]} and {value}): give it once"
            )
        out[name] = value
    return out


def cmd_robots(args: argparse.Namespace) -> int:
    print(f"{'name':<16} {'dof':>3}  {'tip':<24} description")
    for name, spec in CATALOGUE.items():
        arm = load(name)
        print(f"{name:<16} {arm.dof:>3}  {arm.tip:<24} {spec.description}")
    return 0


def cmd_info(args: argparse.Namespace) -> int:
    try:
        arm = load_arm(args).kinematics  # everything it prints is the model's
    except FrameError as exc:
        if not args.frames or getattr(args, "tip", None) is not None:
            raise
        # no tip could be chosen: the frames are what was asked for, to choose one
        info = _urdf_info(args.robot)
        print(f"{info.name}: no tip chosen: {for_cli(str(exc))}")
        _print_frames(info, set(exc.candidates or ()), None)
        return 0
    print(f"{arm.name}: {arm.dof} joints from {arm.base!r} to {arm.tip!r}  ({arm.source})")
    if arm.tip_reason != "given":
        print(f"  tip: {arm.tip_reason}")
    if arm.tip_offset is not None:
        print(f"  {offset_words(arm.tip, arm.tip_offset)}")
    for note in arm.info.notes:
        print(f"  note: {note}")
    for jname, value in arm.locked.items():
        where = "on the chain" if jname in arm.locked_on_chain else "off the chain"
        unit = "m" if arm.info.joint_types.get(jname) == "prismatic" else "rad"
        print(f"  locked: {jname} = {value:g} {unit} ({where})")
    for m in arm.mimics:
        print(f"  mimic: {m.name} = {m.multiplier:g} x {m.driver} + {m.offset:g}")
    for jname, value in (arm.chain.fixed_mimics or {}).items():
        print(f"  mimic: {jname} fixed at {value:g} (its driver does not move on the chain)")
    if args.frames:
        _print_frames(arm.info, set(), arm.tip)
    print(f"  {'joint':<24} {'type':<11} {'lower':>9} {'upper':>9}  link to next (m)")
    for i, (name, jtype) in enumerate(zip(arm.joint_names, arm.joint_types)):
        print(
            f"  {name:<24} {jtype:<11} {arm.lower[i]:>9.4f} {arm.upper[i]:>9.4f}  "
            f"{_link_lengths(arm)[i]:.4f}"
        )
    if arm.plane is not None:
        print(f"  planar: {arm.plane.axes_words(list(arm.joint_names))}")
    print("structure:")
    classes = families.classify(arm)
    wide = max(map(len, classes))
    for cls, geo in classes.items():
        if isinstance(geo, str):
            print(f"  {cls:<{wide}} no: {geo}")
        else:
            text = getattr(geo, "description", "all joint axes parallel")
            print(f"  {cls:<{wide}} yes: {text}")
    for line in family_lines(arm):
        print(line)
    for line in route_lines(arm):
        print(line)
    print("solvers:")
    width = max(map(len, registry.solvers()))
    for name in registry.solvers():
        reason = registry.why_not(name, arm)
        spec = registry.get(name)
        state = "applies" if reason is None else f"does not apply: {reason}"
        print(f"  {name:<{width}} ({spec.kind}) {state}")
    one, every = registry.choose("auto", arm).name, registry.choose("auto", arm, every=True).name
    if one == every:
        print(f"  auto -> {one}")
    else:  # a search: for every solution only (registry.choose)
        print(f"  auto -> {one} (one answer); solve_all -> {every} (every solution, a search)")
    return 0


def _print_frames(info, candidates: set[str], tip: str | None) -> None:
    children = info.children()
    marks = {link: "  (leaf)" for link in info.links if not children.get(link)}
    for link in candidates:
        marks[link] = "  (leaf: a tip to choose, --tip)"
    if tip is not None:
        marks[tip] = "  (the tip)"
    print("frames (link, then [joint type] joint -> child link):")
    for line in frame_tree(info, marks):
        print(f"  {line}")


def _urdf_info(source: str):
    """What the URDF of ``source`` (a bundled name, a path or XML text) says."""
    if source in CATALOGUE:
        return read_urdf(entry(source).urdf_path())[1]
    if source.lstrip().startswith("<"):
        return read_urdf_string(source.lstrip())[1]
    return read_urdf(source)[1]


def frame_tree(info, marks: dict[str, str] | None = None) -> list[str]:
    """The URDF's links and joints as indented tree lines (iterative: trees can be deep),
    each link followed by its mark in ``marks`` (link -> text), if any."""
    marks = marks or {}
    children = info.children()
    lines: list[str] = []
    stack = [(info.root_link, "", "", None)]
    while stack:
        link, lead, tail, joint = stack.pop()
        label = link if joint is None else f"[{joint.type}] {joint.name} -> {link}"
        lines.append(lead + label + marks.get(link, ""))
        kids = children.get(link, [])
        for k, j in reversed(list(enumerate(kids))):
            last = k == len(kids) - 1
            stack.append(
                (j.child, tail + ("`- " if last else "|- "), tail + ("   " if last else "|  "), j)
            )
    return lines


def _link_lengths(arm: ArmModel) -> list[float]:
    """Distance from each joint's origin to the next joint's (the last: to the tip); mimic
    joints are not joints of the arm: the distance goes on to the next driving joint."""
    arm.fk(arm.middle)
    data = arm.data
    points = [data.oMi[i + 1].translation for i in arm.driving_joints]
    points.append(data.oMf[arm.tip_frame_id].translation)
    return [float(np.linalg.norm(b - a)) for a, b in zip(points, points[1:])]


def cmd_solve(args: argparse.Namespace) -> int:
    options = solve_options(args)
    (target,) = flag_targets(args, options, several=False)
    names = task_names(target)
    arm = load_arm(args)
    try:
        if args.all:
            results = list(arm.solve_all(target, q0=args.q0, solver=args.solver, **options))
        else:
            results = [arm.solve(target, q0=args.q0, solver=args.solver, **options)]
    except OptionError as exc:
        raise for_flags(exc) from None
    if names:  # a task list the compiled path solved: each task measured all the same
        results = [_with_task_errors(arm, target, r, options) for r in results]
    if args.json:
        print(
            json.dumps(
                {
                    "robot": arm.name,
                    "joints": arm.joint_names,
                    "results": [_as_dict(r, names) for r in results],
                },
                indent=2,
            )
        )
    else:
        for i, r in enumerate(results):
            if len(results) > 1:
                print(f"solution {i + 1} of {len(results)}")
            print_result(arm, r, show_time=len(results) == 1, tasks=names)
        if len(results) > 1:
            print(
                f"time: {results[0].time * 1e3:.3f} ms for the call ({len(results)} solutions)"
                + FIRST
            )
    return 0 if any(r.success for r in results) else 1


def _with_task_errors(arm: Arm, tasks, r: IKResult, options: dict) -> IKResult:
    """``r`` with each task's error at its ``q`` (Pinocchio's FK) where it has none, within
    the tolerances of ``options`` (the only options a measure reads: ``prefer`` and the
    others the solve took are no options of a measure)."""
    if "task_errors" in r.extra:
        return r
    problem = as_problem(tasks)
    assert problem is not None  # names were found: a task list
    tolerances = {k: v for k, v in options.items() if k in ("tol_position", "tol_orientation")}
    errors = measure_tasks(arm.kinematics, problem, r.q, read_options(tolerances))
    return dataclasses.replace(r, extra={**r.extra, "task_errors": errors})


def _as_dict(r: IKResult, names: list[str]) -> dict:
    out = r.as_dict()
    rows = task_errors(r, names)
    if rows is not None:
        out["task_errors"] = rows
    return out


# every solve the command line prints is its solver's first in the process: loading its
# compiled code counts, or it ran as Python while a helper compiled it (armik.kernel.tier)
FIRST = "; its solver's first call in this process, not a warm call's time (armik bench)"


def print_result(
    arm, r: IKResult, indent: str = "  ", show_time: bool = True, tasks: Sequence[str] = ()
) -> None:
    """A result as text; ``arm`` gives the joints' names and types (an ``Arm``, or the
    several tips' joints side by side)."""
    print(
        f"{indent}status   : {r.status} (success={r.success}), solver {r.solver}"
        + (f", branch {r.branch}" if r.branch else "")
    )
    for name, value, jtype in zip(arm.joint_names, r.q, arm.joint_types):
        unit = "m" if jtype == "prismatic" else f"rad ({math.degrees(value):9.4f} deg)"
        print(f"{indent}  {name:<22} {value: .9f} {unit}")
    ori = "n/a" if r.orientation_error is None else f"{r.orientation_error:.2e} rad"
    pos = "n/a" if r.position_error is None else f"{r.position_error:.2e} m"
    print(f"{indent}FK error : position {pos}, orientation {ori}")
    for tip, errors in r.extra.get("errors", {}).items():  # several tips: each tip's
        pos, tip_ori = (
            "n/a" if e is None else f"{e:.2e} {u}" for e, u in zip(errors, ("m", "rad"))
        )
        print(f"{indent}  {tip}: position {pos}, orientation {tip_ori}")
    for line in task_lines(r, list(tasks), indent):
        print(line)
    if show_time:
        print(f"{indent}time     : {r.time * 1e3:.3f} ms, {r.iterations} iterations{FIRST}")
    else:
        print(f"{indent}iterations: {r.iterations}")
    if r.min_distance is not None:
        a, b = r.closest_pair or ("-", "-")
        print(f"{indent}clearance: {r.min_distance:.4g} m, closest pair {a} / {b}")
    print(f"{indent}reason   : {r.reason}")


def cmd_demo(args: argparse.Namespace) -> int:
    ok = True
    # The Panda's dls solve comes second; its first run on a machine compiles it, and
    # ``start`` starts its step now in a helper process, so that the 2-link arm compiles
    # while the helper works; the rest compiles at the Panda's solve, under one notice
    # (the 2-link arm uses no numeric solver: nothing says so before it)
    warmup.start(STEP_DLS)
    arm = load("planar_2link")
    print("planar_2link (l1 = 1.0 m, l2 = 0.8 m), target (x, y) = (1.2, 0.5):")
    results = arm.solve_all([1.2, 0.5])
    for r in results:
        print_result(arm, r, show_time=False)  # r.time is the whole call's
        ok &= r.success
    print(
        f"  time     : {results[0].time * 1e3:.3f} ms for the call ({len(results)} solutions)"
        + FIRST
    )
    panda = load("panda")
    q_goal = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
    T = panda.fk(q_goal)
    print(
        f"\npanda: full pose target at p = {np.round(T.translation, 4).tolist()} m, "
        "seeded from the mid-limit configuration:"
    )
    r = panda.solve(T, q0=panda.middle)
    print_result(panda, r)
    ok &= r.success
    return 0 if ok else 1


def offset_words(tip: str, offset: tuple[float, float, float]) -> str:
    """The tool point a tip offset adds, in words: what fk gives and targets place."""
    xyz = ", ".join(f"{v:g}" for v in offset)
    return f"tip offset: ({xyz}) m in the frame of {tip!r}: the tool point fk gives, targets place"
