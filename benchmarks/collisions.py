"""Collision checks on the UR5 and the Panda over a table and a box, self-collision on:
the distance call on convex hulls against the raw meshes, and a collision-aware solve
against a plain one (200 targets from collision-free configurations, seeds mid-limits).

Run: PYTHONPATH=src python benchmarks/collisions.py
"""

import os
import time
import warnings

import numpy as np
import pinocchio as pin

import armik
from armik.constraints.collision import arm_geometry, checker
from armik.model.catalogue import erd_share

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

warnings.simplefilter("ignore")
SCENE = (armik.HalfSpace((0, 0, 1), 0.0), armik.Box((0.2, 0.2, 0.3), (0.45, -0.3, 0.15)))


def raw_meshes(a, ch):
    """The checker's pairs on the URDF's meshes as they are (no hulls); ``a``: the arm's
    model (``Arm.kinematics``)."""
    full = pin.buildModelFromUrdf(a.source)
    raw = pin.buildGeomFromUrdf(full, a.source, pin.COLLISION, package_dirs=[erd_share()])
    if a.chain.locked_joints:
        _, (raw,) = pin.buildReducedModel(full, [raw], list(a.chain.locked_joints), a.chain.q_ref)
    n = arm_geometry(a).model.ngeoms
    for k in range(len(SCENE)):
        raw.addGeometryObject(ch.model.geometryObjects[n + k])
    for p in ch.model.collisionPairs:
        raw.addCollisionPair(p)
    return raw


def per_call(f, items) -> float:
    for x in items[:10]:
        f(x)
    t = time.perf_counter()
    for x in items:
        f(x)
    return (time.perf_counter() - t) / len(items)


for name in ["ur5", "panda"]:
    a = armik.load(name)
    kin = a.kinematics
    ch = checker(kin, SCENE, True)
    Q = list(a.random_q(0, n=200))
    hull = per_call(ch.distance, Q)
    raw = raw_meshes(kin, ch)
    gd = pin.GeometryData(raw)

    def mesh_distance(q, kin=kin, raw=raw, gd=gd):  # this pass's arm model, bound now
        pin.updateGeometryPlacements(kin.model, kin.data, raw, gd, kin.to_pin(q))
        pin.computeDistances(raw, gd)

    mesh = per_call(mesh_distance, Q[:30])
    print(
        f"{name}: {len(ch.pair_names)} pairs; distance call: hulls {hull * 1e3:.3f} ms, "
        f"meshes {mesh * 1e3:.2f} ms ({mesh / hull:.0f}x)"
    )
    rng = np.random.default_rng(1)
    targets = []
    while len(targets) < 200:
        q = a.random_q(rng)
        if not a.in_collision(q, SCENE, self_collision=True, margin=0.01):
            targets.append(a.fk(q))
    for label, kw in [("plain", {}), ("collisions", dict(obstacles=SCENE, self_collision=True))]:
        solved = sum(a.solve(T, q0=a.middle, **kw).success for T in targets)
        dt = per_call(lambda T, kw=kw, a=a: a.solve(T, q0=a.middle, **kw), targets)
        print(f"  solve, {label}: {dt * 1e3:.3f} ms mean, {solved}/{len(targets)} solved")
