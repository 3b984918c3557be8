"""Collision-aware IK on two scenes, every success re-checked by an independent coal model.

- panda: a Panda on a table (z = 0) in front of a shelf of two plates beside a wall,
  self-collision on;
- ur5: a UR5 in a cell: a table, a wall behind it and a box beside it, self-collision on.

Targets are the poses of configurations sampled within the limits and collision-free with
a margin of 1 cm (so each has a collision-free answer); seeds at mid-limits; the solves
keep every checked pair 0 m apart (``margin=0``) with the default budget. Reported:
success, false successes (a success that the independent model finds closer than
``margin`` by more than ``TOL`` m, or out of its pose or limits), limit violations, the
mean and 99th-percentile time per collision-aware ``solve`` (and the mean per plain solve
of the same targets), ``solve_batch``'s throughput with collisions on ``--workers``
workers (its successes checked the same way), one check's time and how many pairs coal
measures in it.

The independent model is built here from the URDF with Pinocchio and coal only: the whole
model (the locked finger joints at armik's values), its collision geometry with meshes as
coal's convex hulls (as armik's contract says), every pair of objects on bodies that move
relative to one another (a locked joint moving nothing) except a joint's two sides, and
the obstacles as coal shapes built from the same numbers as the scene.

``--near``: targets whose tip lies 1 to 8 cm from an obstacle's surface (of
configurations 1 cm clear, as ``collision_near.py``), where more first answers collide.
``--all-pairs``: every check asks coal for every pair, as before the pair bounds.
``--slide always``: a numeric answer in collision is first slid out of contact
(``armik.solve.slide``), as on paths, before any restart.

Run: PYTHONPATH=src python benchmarks/collision_scenes.py -n 1000 [--scenes panda ur5]
"""

from __future__ import annotations

import argparse
import gc
import os
import time
import warnings

import coal
import numpy as np
import pinocchio as pin

import armik
from armik.constraints.collision import Checker, checker
from armik.model.catalogue import erd_share

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

warnings.simplefilter("ignore")
TOL = 1e-6  # m: two GJK runs on the same pair agree to far better than this
SAMPLE_MARGIN = 0.01  # m
POSE_TOL = 1e-6 + 1e-12  # m and rad: armik's default tolerances, measured again here

# (kind, numbers): a box (full sizes, centre) or a half space (normal, offset)
SCENES = {
    "panda": [
        ("halfspace", (0, 0, 1), 0.0),  # the table top
        ("box", (0.35, 0.8, 0.02), (0.62, 0.0, 0.25)),  # the shelf's lower plate
        ("box", (0.35, 0.8, 0.02), (0.62, 0.0, 0.6)),  # its upper plate
        ("box", (2.0, 0.04, 1.6), (0.2, -0.55, 0.8)),  # the wall beside
    ],
    "ur5": [
        ("halfspace", (0, 0, 1), 0.0),  # the table top
        ("box", (0.04, 2.0, 1.6), (-0.5, 0.0, 0.8)),  # the wall behind
        ("box", (0.2, 0.2, 0.3), (0.45, -0.3, 0.15)),  # a box on the table
    ],
}


def armik_shapes(scene) -> list:
    return [
        armik.HalfSpace(a, b) if kind == "halfspace" else armik.Box(a, b) for kind, a, b in scene
    ]


def coal_shapes(scene) -> list[tuple[object, coal.Transform3s]]:
    out = []
    for kind, a, b in scene:
        if kind == "halfspace":
            out.append((coal.Halfspace(np.array(a, float), float(b)), coal.Transform3s()))
        else:
            out.append((coal.Box(*map(float, a)), coal.Transform3s(np.eye(3), np.array(b, float))))
    return out


class Independent:
    """Distances, FK and limits of an arm from its URDF, built with Pinocchio and coal."""

    def __init__(self, arm: armik.Arm, scene) -> None:
        source = arm.kinematics.source
        self.model = full = pin.buildModelFromUrdf(source)
        self.data = full.createData()
        geom = pin.buildGeomFromUrdf(full, source, pin.COLLISION, package_dirs=[erd_share()])
        self.objects = []
        for o in geom.geometryObjects:
            g = o.geometry
            if isinstance(g, coal.BVHModelBase):
                g.buildConvexHull(True, "Qt")
                g = g.convex
            self.objects.append((o.parentJoint, o.placement, g))
        self.q_full = pin.neutral(full)
        for name, value in arm.locked.items():
            self.q_full[full.joints[full.getJointId(name)].idx_q] = value
        self.idx = [full.joints[full.getJointId(n)].idx_q for n in arm.joint_names]
        self.lower = full.lowerPositionLimit[self.idx]
        self.upper = full.upperPositionLimit[self.idx]
        # every joint off the chain holds its value (the fingers: at armik's locked values,
        # else at neutral), so it moves nothing
        chain = {full.getJointId(n) for n in arm.joint_names}
        locked = {j for j in range(1, full.njoints) if j not in chain}

        def body(j: int) -> int:  # the moving joint that carries joint j's link
            while j in locked:
                j = full.parents[j]
            return j

        bodies = [body(j) for j, _, _ in self.objects]
        self.self_pairs = []
        for a in range(len(bodies)):
            for b in range(a + 1, len(bodies)):
                ja, jb = bodies[a], bodies[b]
                if ja == jb or body(full.parents[ja]) == jb or body(full.parents[jb]) == ja:
                    continue
                self.self_pairs.append((a, b))
        self.obstacles = coal_shapes(scene)
        self.tip = full.getFrameId(arm.tip)

    def check(self, q: np.ndarray, T_target: pin.SE3) -> tuple[float, float, float, bool]:
        """(min distance m, position error m, orientation error rad, within limits)."""
        qf = self.q_full.copy()
        qf[self.idx] = q
        pin.framesForwardKinematics(self.model, self.data, qf)
        placed = []
        for j, placement, g in self.objects:
            M = self.data.oMi[j] * placement
            placed.append((j, g, coal.Transform3s(M.rotation, M.translation)))
        best = np.inf
        for a, b in self.self_pairs:
            best = min(best, _distance(placed[a][1], placed[a][2], placed[b][1], placed[b][2]))
        for j, g, T in placed:
            if j == 0:
                continue  # fixed to the base: it cannot move into or out of an obstacle
            for shape, Ts in self.obstacles:
                best = min(best, _distance(g, T, shape, Ts))
        M = self.data.oMf[self.tip]
        dp = float(np.linalg.norm(M.translation - T_target.translation))
        dr = float(np.linalg.norm(pin.log3(M.rotation.T @ T_target.rotation)))
        ok = bool(((q >= self.lower) & (q <= self.upper)).all())
        return best, dp, dr, ok


def _distance(g1, T1, g2, T2) -> float:
    return coal.distance(g1, T1, g2, T2, coal.DistanceRequest(), coal.DistanceResult())


def every_pair(self, q):
    """``Checker.distance`` asking coal for every pair (before the pair bounds)."""
    if not self.pair_names:
        return float("inf"), None
    gd = self.geometry_data()
    arm = self.arm
    pin.updateGeometryPlacements(arm.model, arm.data, self.model, gd, arm.to_pin(q))
    k = pin.computeDistances(self.model, gd)
    return float(gd.distanceResults[k].min_distance), self.pair_names[k]


def every_row(self, Q):
    """``Checker.distances`` (a batch's answers) asking coal for every pair of each."""
    return [every_pair(self, q) for q in Q]


BOUNDED = Checker.distance


def targets(arm: armik.Arm, shapes, n: int, seed: int) -> list[pin.SE3]:
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        q = arm.random_q(rng)
        if not arm.in_collision(q, shapes, self_collision=True, margin=SAMPLE_MARGIN):
            out.append(arm.fk(q))
    return out


NEAR = (0.01, 0.08)  # m: the tip's distance to the nearest obstacle with ``--near``


def near_targets(arm: armik.Arm, scene, n: int, seed: int) -> list[pin.SE3]:
    """Poses of configurations 1 cm clear of everything whose tip lies ``NEAR`` from an
    obstacle's surface."""
    shapes = armik_shapes(scene)
    obstacles = coal_shapes(scene)
    point = coal.Sphere(1e-9)
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        q = arm.random_q(rng)
        if arm.in_collision(q, shapes, self_collision=True, margin=SAMPLE_MARGIN):
            continue
        T = arm.fk(q)
        at = coal.Transform3s(np.eye(3), T.translation)
        req = coal.DistanceRequest()
        d = min(coal.distance(point, at, s, Ts, req, coal.DistanceResult()) for s, Ts in obstacles)
        if NEAR[0] <= d <= NEAR[1]:
            out.append(T)
    return out


def run(
    name: str,
    n: int,
    workers: int,
    seed: int,
    solver: str = "auto",
    slide: bool = False,
    near: bool = False,
) -> None:
    arm = armik.load(name)
    shapes = armik_shapes(SCENES[name])
    opts = dict(obstacles=shapes, self_collision=True, solver=solver, slide=slide)
    T = near_targets(arm, SCENES[name], n, seed) if near else targets(arm, shapes, n, seed)
    # compile what the timed solves use (a colliding answer's restarts run the batch entry,
    # which the first targets may not reach), then warm up
    armik.compile(["dls", "qp", "batch", "collisions", "three_parallel"], progress=False)
    for t in T[:10]:
        arm.solve(t, q0=arm.middle, **opts)
        arm.solve(t, q0=arm.middle, solver=solver)
    results, per_solve, cpu_solve, p99 = timed(lambda t: arm.solve(t, q0=arm.middle, **opts), T)
    plain, per_plain, cpu_plain, _ = timed(lambda t: arm.solve(t, q0=arm.middle, solver=solver), T)
    check = checker(arm.kinematics, tuple(shapes), True)
    Q = [r.q for r in results]
    passes = {"bounded": [], "every pair": []}
    for _ in range(5):  # interleaved: the machine is shared
        for label, f in (("bounded", BOUNDED), ("every pair", every_pair)):
            t0 = time.process_time()
            for q in Q:
                f(check, q)
            passes[label].append((time.process_time() - t0) / n)
    calls = coal_calls(check, Q)
    ind = Independent(arm, SCENES[name])
    solved = false = outside = batch_false = 0
    closest = np.inf
    for r, t in zip(results, T):
        if not r.success:
            continue
        solved += 1
        d, dp, dr, within = ind.check(r.q, t)
        closest = min(closest, d)
        outside += not within
        false += d < -TOL or dp > POSE_TOL or dr > POSE_TOL or not within
    statuses: dict[str, int] = {}
    for r in results:
        statuses[r.status.value] = statuses.get(r.status.value, 0) + 1
    batch = np.array([t.homogeneous for t in T])
    arm.solve_batch(batch[:20], q0=arm.middle, workers=workers, progress=False, **opts)
    b = arm.solve_batch(batch, q0=arm.middle, workers=workers, progress=False, **opts)
    for i in np.flatnonzero(b.success).tolist():  # the batch's successes, checked the same way
        d, dp, dr, within = ind.check(b.q[i], T[i])
        batch_false += d < -TOL or dp > POSE_TOL or dr > POSE_TOL or not within
    print(
        f"{name}: {n} targets, {len(ind.self_pairs)} self pairs and {len(shapes)} obstacles "
        f"(independent model); solver {results[0].solver}\n"
        f"  success {100 * solved / n:.2f} % ({solved}/{n}; {statuses})\n"
        f"  false successes {false}, limit violations {outside}, smallest independent "
        f"distance of a success {closest:.4g} m\n"
        f"  solve: {per_solve * 1e3:.3f} ms mean with collisions (p99 {p99 * 1e3:.3f} ms, "
        f"CPU {cpu_solve * 1e3:.3f} ms), "
        f"{per_plain * 1e3:.3f} ms plain (CPU {cpu_plain * 1e3:.3f} ms; "
        f"{sum(r.success for r in plain)}/{n} solved plain, "
        f"{sum(r.restarts for r in results) / n:.2f} restarts a target)\n"
        f"  solve_batch, {workers} workers: {n / b.time:,.0f} targets/s "
        f"({100 * b.success_rate:.2f} % solved, {batch_false} false successes)\n"
        f"  one check at the answers, CPU, median of 5 interleaved passes: "
        + ", ".join(f"{k} {np.median(v) * 1e3:.3f} ms" for k, v in passes.items())
        + f"; coal called {calls:.2f} times a bounded check"
    )


def timed(solve, T: list) -> tuple[list, float, float, float]:
    """(results, wall s, CPU s a target, the 99th percentile of a target's wall s) of
    ``solve`` over ``T``, the garbage collector off as ``timeit`` has it: a full collection
    of this process's 147 000 objects (most of them numba's and Pinocchio's) paused 70-80 ms
    here, which landed in one loop or the other."""
    gc.collect()
    gc.disable()
    try:
        each = []
        results = []
        clock = time.perf_counter
        t0, c0 = clock(), time.process_time()
        for t in T:
            t1 = clock()
            results.append(solve(t))
            each.append(clock() - t1)
        wall, cpu = (clock() - t0) / len(T), (time.process_time() - c0) / len(T)
        return results, wall, cpu, float(np.percentile(each, 99))
    finally:
        gc.enable()


def coal_calls(check: Checker, Q: list) -> float:
    """The pairs coal measures in one bounded check, averaged over the answers ``Q``."""
    count = 0
    compute = pin.computeDistance

    def counted(*args):
        nonlocal count
        count += 1
        return compute(*args)

    pin.computeDistance = counted  # Checker.distance reads it from the module at each call
    try:
        for q in Q:
            check.distance(q)
    finally:
        pin.computeDistance = compute
    return count / max(len(Q), 1)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-n", type=int, default=1000, help="targets per scene (1000)")
    p.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    p.add_argument("--workers", type=int, default=2, help="solve_batch threads (2)")
    p.add_argument("--seed", type=int, default=0, help="target sampling seed (0)")
    p.add_argument("--solver", default="auto", help="the solver of every solve (auto)")
    p.add_argument(
        "--slide",
        choices=["paths", "always"],
        default="paths",
        help="slide a colliding numeric answer out of contact before restarting: on paths "
        "only (armik's default; these solves restart at once) or in every solve",
    )
    p.add_argument(
        "--near",
        action="store_true",
        help="targets whose tip lies 1-8 cm from an obstacle (as benchmarks/collision_near.py)",
    )
    p.add_argument(
        "--all-pairs",
        action="store_true",
        help="measure every pair at each check (coal's computeDistances), as before the "
        "pair bounds",
    )
    args = p.parse_args()
    if args.all_pairs:
        Checker.distance = every_pair  # type: ignore[method-assign]
        Checker.distances = every_row  # type: ignore[method-assign]
    for name in args.scenes:
        run(name, args.n, args.workers, args.seed, args.solver, args.slide == "always", args.near)


if __name__ == "__main__":
    main()
