"""Targets with a region (``bounds``): success, false successes by an independent FK
(yourdfpy), limit violations and time, beside TRAC-IK on the same targets.

Per arm and case, ``-n`` targets built so that an admissible answer always exists, from a
random configuration q within the limits:

- ``spin``: q's tip pose turned about its z axis by a random angle, bounds
  (0, 0, 0, 0, 0, inf): the tool's position and z direction, its spin free (on the 5-joint
  SO-101, "this point, pointing that way");
- ``box``: a pose whose error twist to q's tip pose lies at up to 80 % of +-5 mm and
  +-0.05 rad, bounds (0.005,) * 3 + (0.05,) * 3;
- ``cone``: a task list, q's tip position and its z axis within 0.05 rad of a direction
  up to 0.04 rad from q's (``[armik.Position(p), armik.Axis((0, 0, 1), d, 0.05)]``);
- ``look``: a task list, q's tip position and its z axis within 0.05 rad of the line to a
  point 0.2-1 m along q's z axis, moved up to 1 cm
  (``[armik.Position(p), armik.LookAt(point, (0, 0, 1), 0.05)]``);
- ``aim``: the look-at alone, the position free (``[armik.LookAt(point, (0, 0, 1), 0.05)]``
  with the point built as for ``look``): a camera aimed at a spot from anywhere;
- ``boxcone``: q's tip position moved up to 4 mm within a +-5 mm box, and the cone's axis
  as for ``cone`` (``[armik.Position(p, bounds=(0.005,) * 3), armik.Axis(...)]``): "place
  it within 5 mm, the tool down within 3 degrees".

armik solves with ``solver="auto"`` from mid-limits with a 5 ms budget; a success is
checked again by yourdfpy's FK against the bounds (plus 1e-6). TRAC-IK (the ``pytracik``
wheel, Speed mode, 5 ms, 1e-5) is timed on the same targets in the same loop, interleaved
target by target; its Python call takes no bounds, so it solves the exact pose: on the
``spin`` targets of a 5-joint arm that pose is out of reach and TRAC-IK spends its budget.

    python benchmarks/tolerances.py [-n 200] [--arms ur5 panda abb_irb120 so101]
        [--cases spin box cone look aim boxcone]
"""

from __future__ import annotations

import argparse
import math
import os
import re
import tempfile
import time

import numpy as np
import pinocchio as pin
import yourdfpy

import armik
from armik.model.catalogue import _erd_robot_dir
from armik.problem import Axis, LookAt, Pose, Position

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

SPIN = (0.0, 0.0, 0.0, 0.0, 0.0, math.inf)
BOX = (0.005, 0.005, 0.005, 0.05, 0.05, 0.05)


def load(name: str) -> armik.Arm:
    if name == "so101":
        return armik.load(str(_erd_robot_dir() / "so_arm_description" / "urdf" / "so101.urdf"))
    return armik.load(name)


CONE = 0.05
TASKS = ("cone", "look", "aim", "boxcone")  # the cases whose targets are task lists


def target(a: armik.Arm, case: str, rng: np.random.Generator):
    T = a.fk(a.random_q(rng))
    if case in ("cone", "boxcone"):
        tilt = pin.exp3(rng.uniform(-1.0, 1.0, 3) * 0.8 * CONE / math.sqrt(3.0))
        axis = Axis((0, 0, 1), tilt @ T.rotation[:, 2], CONE)
        if case == "cone":
            return [Position(T.translation), axis], T
        moved = T.translation + rng.uniform(-0.8, 0.8, 3) * BOX[0]
        return [Position(moved, bounds=BOX[:3]), axis], T
    if case in ("look", "aim"):
        point = T.translation + rng.uniform(0.2, 1.0) * T.rotation[:, 2]
        point = point + rng.uniform(-0.01, 0.01, 3)
        look = LookAt(point, (0, 0, 1), CONE)
        return ([Position(T.translation), look] if case == "look" else [look]), T
    if case == "spin":
        return T * pin.SE3(
            pin.exp3(np.array([0.0, 0.0, rng.uniform(-math.pi, math.pi)])), np.zeros(3)
        )
    e = rng.uniform(-0.8, 0.8, 6) * np.array(BOX)
    R_t = T.rotation @ pin.exp3(-e[3:])
    return pin.SE3(R_t, T.translation - R_t @ e[:3])


def independent_fk(a: armik.Arm):
    model = yourdfpy.URDF.load(
        str(a.kinematics.source), build_scene_graph=True, load_meshes=False,
        build_collision_scene_graph=False, load_collision_meshes=False,
    )  # fmt: skip

    def fk(q: np.ndarray) -> pin.SE3:
        cfg = {j: 0.0 for j in model.actuated_joint_names}
        cfg.update(dict(a.locked))
        cfg.update(dict(zip(a.joint_names, q)))
        model.update_cfg(cfg)
        return pin.SE3(model.get_transform(frame_to=a.tip, frame_from=a.base))

    return fk


def tracik(a: armik.Arm, mode: str = "Speed"):
    """TRAC-IK (``mode``: Speed, Distance, Manip1, Manip2) on the arm's URDF under a
    massless root link (KDL warns of a root link with an inertia, the Panda's and the
    SO-101's), with armik's joint limits."""
    try:
        from trac_ik import TracIK
    except ImportError:
        return None
    text = open(a.kinematics.source).read()
    children = set(re.findall(r"<child\s+link=\"([^\"]+)\"", text))
    root = next(n for n in re.findall(r"<link\s+name=\"([^\"]+)\"", text) if n not in children)
    dummy = (
        '<link name="tracik_root"/><joint name="tracik_root_joint" type="fixed">'
        f'<parent link="tracik_root"/><child link="{root}"/></joint>'
    )
    text = re.sub(r"(<robot\b[^>]*>)", lambda m: m.group(1) + dummy, text, count=1)
    fd, path = tempfile.mkstemp(suffix=".urdf")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    peer = TracIK(a.base, a.tip, path, timeout=0.005, epsilon=1e-5, solver_type=mode)
    peer.joint_limits = (a.lower, a.upper)  # KDL reads the Panda's as [0, 0]: armik's
    return peer


def run(name: str, case: str, n: int) -> None:
    a = load(name)
    bounds = SPIN if case == "spin" else BOX
    options = {} if case in TASKS else {"bounds": bounds}
    rng = np.random.default_rng(0)
    targets = [target(a, case, rng) for _ in range(n)]
    fk, peer = independent_fk(a), tracik(a)
    first = targets[0][0] if case in TASKS else targets[0]
    a.solve(first, **options)  # compiled before the clock runs
    ok = false = outside = peer_ok = 0
    t_armik = t_peer = 0.0
    for T in targets:
        tasks, T = T if case in TASKS else ([Pose(T, bounds=bounds)], T)
        asked = tasks if case in TASKS else T
        t0 = time.perf_counter()
        r = a.solve(asked, q0=a.middle, timeout=0.005, **options)
        t_armik += time.perf_counter() - t0
        if r.success:
            ok += 1
            reached = fk(r.q)
            false += not all(t.measure(reached, 1e-6, 1e-6).within for t in tasks)
            outside += not a.within_limits(r.q)
        if peer is not None:
            t0 = time.perf_counter()
            got = peer.ik(T.translation, T.rotation, a.middle)
            t_peer += time.perf_counter() - t0
            peer_ok += got is not None
    line = (
        f"{name:<11} {case:<5} n={n}  success {100 * ok / n:6.2f} %  false {false}  "
        f"limits {outside}  armik {1e3 * t_armik / n:.4f} ms"
    )
    if peer is not None:
        line += (
            f"  TRAC-IK (exact pose) {1e3 * t_peer / n:.4f} ms, {100 * peer_ok / n:.1f} %  "
            f"ratio {t_armik / t_peer:.2f}"
        )
    print(line, flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=200, help="targets per arm and case (200)")
    parser.add_argument("--arms", nargs="+", default=["ur5", "panda", "abb_irb120", "so101"])
    parser.add_argument("--cases", nargs="+", default=["spin", "box", *TASKS])
    args = parser.parse_args()
    for name in args.arms:
        for case in args.cases:
            run(name, case, args.n)


if __name__ == "__main__":
    main()
