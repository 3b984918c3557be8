"""Several tips of one robot (``--tip A --tip B``): ``info`` prints each chain and the
joints they share, ``solve`` takes one target per tip (``armik.load(..., tips=[...])``)."""

from __future__ import annotations

import argparse
import json
import math
from types import SimpleNamespace

import numpy as np

from armik.arms import Arms
from armik.errors import InputError, OptionError
from armik.loading import load
from armik.solvers import registry
from armik.tools.cli.arms import (
    frame_tree,
    locked_joints,
    offset_words,
    print_result,
    solve_options,
)
from armik.tools.cli.targets import flag_targets, for_flags, task_errors, task_names

# options the task solver of chains that share joints does not take (flag -> option)
_NOT_TOGETHER = {
    "--weights": "weights",
    "--position-only": "position_only",  # left in the options with --axis only
    "--prefer": "prefer",
    "--obstacles": "obstacles",
    "--self-collision": "self_collision",
}


def load_tips(args: argparse.Namespace) -> Arms:
    return load(
        args.robot,
        tips=args.tip,
        base=args.base,
        tip_offset=getattr(args, "tip_offset", None),
        locked=locked_joints(args.lock),
    )


def cmd_info_tips(args: argparse.Namespace) -> int:
    robot = load_tips(args)
    first = robot.chain(robot.tips[0]).kinematics
    shared = f", {len(robot.shared)} shared" if robot.shared else ""
    print(
        f"{first.name}: {len(robot.tips)} tips from {first.base!r}, {robot.dof} joints"
        f"{shared}  ({first.source})"
    )
    for note in first.info.notes:
        print(f"  note: {note}")
    for jname, value in first.locked.items():
        unit = "m" if first.info.joint_types.get(jname) == "prismatic" else "rad"
        print(f"  locked: {jname} = {value:g} {unit}")
    if args.frames:
        marks = {tip: "  (a tip)" for tip in robot.tips}
        print("frames (link, then [joint type] joint -> child link):")
        for line in frame_tree(first.info, marks):
            print(f"  {line}")
    for tip in robot.tips:
        arm = robot.chain(tip).kinematics
        auto = registry.choose("auto", arm).name
        print(f"tip {tip!r}: {arm.dof} joints; this chain alone: auto -> {auto}")
        if arm.tip_offset is not None:
            print(f"  {offset_words(tip, arm.tip_offset)}")
        print(f"  {'joint':<24} {'type':<11} {'lower':>9} {'upper':>9}")
        for i, (name, jtype) in enumerate(zip(arm.joint_names, arm.joint_types)):
            mark = "  shared" if name in robot.shared else ""
            print(f"  {name:<24} {jtype:<11} {arm.lower[i]:>9.4f} {arm.upper[i]:>9.4f}{mark}")
    if robot.shared:
        print(
            f"shared joints: {', '.join(robot.shared)}: the chains are solved together "
            "(one model, the task solver over every joint)"
        )
    else:
        print("shared joints: none: each chain is solved by its own solver, side by side")
    print(f"robot joints, in the order of --q0 and of the answers: {', '.join(robot.joint_names)}")
    return 0


def cmd_solve_tips(args: argparse.Namespace) -> int:
    if args.all:
        raise InputError(
            "--all lists every solution of one chain; several tips give one answer for the "
            "whole robot: leave --all out, or give one --tip"
        )
    options = solve_options(args)
    targets = flag_targets(args, options, several=True)
    robot = load_tips(args)
    if robot.shared:
        _refuse_together(robot, args, options)
    if args.solver != "auto":
        options["solver"] = args.solver
    q0 = None
    if args.q0 is not None:
        if len(args.q0) != robot.dof or not all(map(math.isfinite, args.q0)):
            raise InputError(
                f"--q0 must give {robot.dof} finite values (rad or m), one per joint of "
                f"{list(robot.joint_names)}, got {args.q0}"
            )
        q0 = np.array(args.q0)
    try:
        r = robot.solve(dict(zip(robot.tips, targets)), q0=q0, **options)
    except OptionError as exc:
        raise for_flags(exc) from None
    if args.json:
        print(json.dumps(_as_dict(robot, r, targets), indent=2))
    else:
        print_result(_joints(robot), r)
    return 0 if r.success else 1


def _refuse_together(robot: Arms, args: argparse.Namespace, options: dict) -> None:
    """Chains sharing joints are solved together by the task solver: the options it does
    not take, named by their flags."""
    given = [flag for flag, name in _NOT_TOGETHER.items() if name in options]
    if args.solver != "auto":
        given.insert(0, "--solver")
    if given:
        raise InputError(
            f"{given[0]} does not apply to these tips: they share joints "
            f"({', '.join(robot.shared)}) and are solved together by the task solver; "
            f"leave {given[0]} out"
            + (
                " (for a pose, give --bounds too: its weights go with them)"
                if given[0] == "--weights"
                else ""
            )
        )


def _joints(robot: Arms) -> SimpleNamespace:
    """The robot's joints' names and types, as ``print_result`` reads them off an arm."""
    types: dict[str, str] = {}
    for tip in robot.tips:
        arm = robot.chain(tip).kinematics
        types.update(zip(arm.joint_names, arm.joint_types))
    names = list(robot.joint_names)
    return SimpleNamespace(joint_names=names, joint_types=[types[n] for n in names])


def _as_dict(robot: Arms, r, targets: list[object]) -> dict:
    """The JSON of a several-tip solve: the whole robot's result, and each tip's errors
    (with its chain's status, solver and reason where it was solved alone, and its tasks'
    errors where measured)."""
    result = r.as_dict()
    result.pop("errors", None)  # each tip's row below holds its errors
    alone = r.extra.get("results", {})
    tips: dict = {}
    names = [task_names(t) for t in targets]
    # a plain target is one task when solved together: a Position or a Pose
    plain = [["Position"] if isinstance(t, np.ndarray) else ["Pose"] for t in targets]
    together = task_errors(r, [n for ns, p in zip(names, plain) for n in (ns or p)])
    start = 0
    for tip, ns in zip(robot.tips, names):
        pos, ori = r.extra["errors"].get(tip, (None, None))
        row: dict = {"position_error": pos, "orientation_error": ori}
        if tip in alone:
            chain = alone[tip]
            row.update(status=chain.status.value, solver=chain.solver, reason=chain.reason)
            rows = task_errors(chain, ns)
        else:
            count = max(len(ns), 1)
            rows = None if together is None else together[start : start + count]
            start += count
        if rows is not None:
            row["task_errors"] = rows
        tips[tip] = row
    result["tips"] = tips
    return {
        "robot": robot.chain(robot.tips[0]).name,
        "tips": list(robot.tips),
        "joints": list(robot.joint_names),
        "shared": list(robot.shared),
        "results": [result],
    }
