"""Write tests/golden/answers.json: armik's answers to a fixed set of seeded public calls.

    python tests/golden/make_golden.py

Run it only when a change of answers is intended (and say so in the commit); the golden
test (tests/golden/test_golden.py) recomputes the same calls with ``compute`` and checks
them against the file bit for bit.

Every call goes through the public API only (``armik.load``, ``Arm.solve``,
``Arm.solve_all``, ``Arm.solve_batch``, ``Arm.solve_path``, ``Arm.fk``, ``Arm.random_q``,
the result fields), but for the seeds near an answer, clipped to the arm model's
``sampling_box`` (``Arm.kinematics``). The targets come from ``Arm.fk`` of seeded
``Arm.random_q`` configurations. Numeric solves (``dls``, ``qp``, ``clik``, and ``auto``
where it picks one) always get ``iteration_budget`` and a fixed ``seed``: the default
budget is CPU time, which depends on the machine's load. Floats are stored as
``float.hex()`` strings, so the comparison is exact (the sign of a zero included).
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

if __name__ == "__main__":  # the kernels the tests pin (tests/golden/blas_kernels.py)
    sys.path.insert(0, str(Path(__file__).parents[2]))
    from tests.golden.blas_kernels import pin_openblas

    pin_openblas()

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402

import armik  # noqa: E402

ANSWERS = Path(__file__).with_name("answers.json")
FORMAT = "armik-golden/1"

#: Deterministic budgets for the numeric solvers (``timeout`` is never used).
BUDGET = 2000
CLIK = {"iteration_budget": 300, "max_iterations": 300}

ARMS = ("planar_2link", "ur5", "abb_irb120", "panda", "kinova", "scara")
FAR = {  # well beyond each arm's reach (m)
    "planar_2link": (3.0, 0.5),
    "ur5": (3.0, 0.5, 0.3),
    "abb_irb120": (2.0, -0.4, 0.6),
    "panda": (1.5, 0.8, 0.5),
    "kinova": (2.0, 0.3, 0.4),
    "scara": (2.0, 1.0, 0.1),
}


# -- records ------------------------------------------------------------------------------


def hx(x: float) -> str:
    return float(x).hex()


def hexes(a) -> list:
    """Floats as hex strings, nested as the array."""
    arr = np.asarray(a, dtype=float)
    if arr.ndim == 0:
        return hx(arr)
    return [hexes(row) for row in arr] if arr.ndim > 1 else [hx(v) for v in arr.tolist()]


def result_record(r: armik.IKResult) -> dict:
    return {
        "q": hexes(r.q),
        "success": bool(r.success),
        "status": r.status.value,
        "solver": r.solver,
        "iterations": int(r.iterations),
        "restarts": int(r.restarts),
        "branch": r.branch,
        "singular": bool(r.singular),
        "position_error": hx(r.position_error),
        "orientation_error": None if r.orientation_error is None else hx(r.orientation_error),
        "reason": r.reason,
    }


def batch_record(b: armik.BatchResult) -> dict:
    return {
        "solver": b.solver,
        "n": len(b),
        "q": hexes(b.q),
        "success": [bool(v) for v in b.success.tolist()],
        "status": [str(v) for v in b.status.tolist()],
        "iterations": [int(v) for v in b.iterations.tolist()],
        "restarts": [int(v) for v in b.restarts.tolist()],
        "position_error": hexes(b.position_error),
        "orientation_error": hexes(b.orientation_error),  # 'nan' where not measured
        "reasons": {str(k): b.reasons[k] for k in sorted(b.reasons)},
    }


# -- inputs -------------------------------------------------------------------------------

_ARMS: dict[str, armik.Arm] = {}


def arm(name: str) -> armik.Arm:
    if name not in _ARMS:
        _ARMS[name] = armik.load(name)
    return _ARMS[name]


def configurations(a: armik.Arm, n: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [a.random_q(rng) for _ in range(n)]


def quat_xyzw(T: pin.SE3) -> list[float]:
    return pin.Quaternion(T.rotation).coeffs().tolist()  # Pinocchio's order: x, y, z, w


def target(T: pin.SE3, form: str):
    """``T`` in one of the target forms ``Arm.solve`` accepts."""
    if form == "se3":
        return T
    if form == "h4":  # C-ordered float64 4x4
        return np.ascontiguousarray(T.homogeneous)
    if form == "h4list":  # nested lists: the general input path
        return T.homogeneous.tolist()
    if form == "pos":  # (3,) float64 position
        return np.array(T.translation)
    if form == "poslist":
        return T.translation.tolist()
    if form == "pq":  # (position, quaternion x y z w)
        return (T.translation.tolist(), quat_xyzw(T))
    if form == "prot":  # (position, 3x3 rotation)
        return (np.array(T.translation), np.array(T.rotation))
    if form == "x7":
        return np.concatenate([T.translation, quat_xyzw(T)])
    if form == "xy":  # planar arm, in the arm's plane
        return np.array(T.translation[:2])
    if form == "xylist":
        return T.translation[:2].tolist()
    raise ValueError(form)


def seed_q(a: armik.Arm, q_true: np.ndarray, form: str, rng: np.random.Generator):
    """A q0 of the given form: None (mid-limits), random, near the answer, the answer."""
    if form == "none":
        return None
    if form == "rand":
        return a.random_q(rng)
    if form == "randlist":
        return a.random_q(rng).tolist()
    if form == "near":
        lo, hi = a.kinematics.sampling_box()
        return np.clip(q_true + rng.normal(0.0, 0.05, a.dof), lo, hi)
    if form == "exact":
        return np.array(q_true)
    raise ValueError(form)


def numeric(seed: int, budget: int = BUDGET, **extra) -> dict:
    return {"iteration_budget": budget, "seed": seed, **extra}


def far_pose(name: str, T: pin.SE3) -> pin.SE3:
    p = np.zeros(3)
    far = FAR[name]
    p[: len(far)] = far
    return pin.SE3(T.rotation, p)


# -- the calls ----------------------------------------------------------------------------


class Group:
    """Records of one group of calls, in order; each names its call."""

    def __init__(self) -> None:
        self.records: list[dict] = []

    def solve(self, a: armik.Arm, call: str, tgt, *, q0=None, solver="auto", **opts) -> None:
        r = a.solve(tgt, q0=q0, solver=solver, **opts)
        self.records.append({"call": f"{a.name} solve {call}", "result": result_record(r)})

    def solve_all(self, a: armik.Arm, call: str, tgt, *, q0=None, solver="auto", **opts):
        rs = a.solve_all(tgt, q0=q0, solver=solver, **opts)
        self.records.append(
            {"call": f"{a.name} solve_all {call}", "results": [result_record(r) for r in rs]}
        )

    def batch(self, a: armik.Arm, call: str, targets, *, q0=None, solver="auto", **opts):
        b = a.solve_batch(targets, q0=q0, solver=solver, workers=1, progress=False, **opts)
        self.records.append({"call": f"{a.name} solve_batch {call}", "batch": batch_record(b)})

    def path(self, a: armik.Arm, call: str, poses, q0, **opts):
        b = a.solve_path(poses, q0, **opts)
        self.records.append({"call": f"{a.name} solve_path {call}", "batch": batch_record(b)})


def sweep(g: Group, a: armik.Arm, solver: str, n: int, seed: int, forms, q0s, opts=None):
    """``n`` solves of fk(random q) targets, cycling through target and seed forms.
    ``opts``: None (defaults: closed forms), or a callable i -> options."""
    qs = configurations(a, n, seed)
    rng = np.random.default_rng(seed + 1)
    for i, q in enumerate(qs):
        form, q0f = forms[i % len(forms)], q0s[(i // len(forms)) % len(q0s)]
        o = {} if opts is None else opts(i)
        g.solve(
            a,
            f"{solver} #{i} target={form} q0={q0f} opts={sorted(o.items())}",
            target(a.fk(q), form),
            q0=seed_q(a, q, q0f, rng),
            solver=solver,
            **o,
        )


def sweep_all(g: Group, a: armik.Arm, solver: str, n: int, seed: int, forms, q0s, opts=None):
    qs = configurations(a, n, seed)
    rng = np.random.default_rng(seed + 1)
    for i, q in enumerate(qs):
        form, q0f = forms[i % len(forms)], q0s[i % len(q0s)]
        o = {} if opts is None else opts(i)
        g.solve_all(
            a,
            f"{solver} #{i} target={form} q0={q0f} opts={sorted(o.items())}",
            target(a.fk(q), form),
            q0=seed_q(a, q, q0f, rng),
            solver=solver,
            **o,
        )


def group_arms() -> list[dict]:
    """What the arms are: joints, limits, the middle, and the registered solvers."""
    out = [{"call": "armik.solvers()", "solvers": armik.solvers()}]
    for name in ARMS:
        a = arm(name)
        out.append(
            {
                "call": f"armik.load({name!r})",
                "dof": a.dof,
                "joint_names": list(a.joint_names),
                "lower": hexes(a.lower),
                "upper": hexes(a.upper),
                "middle": hexes(a.middle),
                "tip": a.tip,
            }
        )
    return out


def group_fk() -> list[dict]:
    """The targets' source: fk of seeded random configurations."""
    out = []
    for k, name in enumerate(ARMS):
        a = arm(name)
        for i, q in enumerate(configurations(a, 8, 900 + k)):
            out.append({"call": f"{name} fk #{i}", "q": hexes(q), "T": hexes(a.fk(q).homogeneous)})
    return out


def group_planar_closed() -> list[dict]:
    g, a = Group(), arm("planar_2link")
    forms, q0s = ("xy", "xylist", "pos", "poslist", "se3"), ("none", "rand", "randlist")
    sweep(g, a, "planar2r", 30, 10, forms, q0s)
    sweep(g, a, "auto", 8, 12, forms, ("none", "rand"))
    sweep_all(g, a, "planar2r", 10, 14, forms, ("none", "rand"))
    for label, xy in (("far", FAR["planar_2link"]), ("too close", (0.1, 0.05)), ("origin", (0, 0))):
        g.solve(a, f"planar2r {label}", np.array(xy, float), solver="planar2r")
        g.solve_all(a, f"planar2r {label}", np.array(xy, float), solver="planar2r")
    g.solve(a, "planar2r stretched", np.array([1.8, 0.0]), solver="planar2r")
    g.solve_all(a, "planar2r stretched", np.array([1.8, 0.0]), solver="planar2r")
    return g.records


def group_planar_numeric() -> list[dict]:
    g, a = Group(), arm("planar_2link")
    forms, q0s = ("xy", "pos", "xylist"), ("none", "rand")
    sweep(g, a, "dls", 10, 20, forms, q0s, lambda i: numeric(i))
    sweep(g, a, "qp", 6, 22, forms, q0s, lambda i: numeric(i))
    sweep(g, a, "clik", 4, 24, forms, q0s, lambda i: dict(CLIK))
    far = np.array(FAR["planar_2link"])
    for solver in ("dls", "qp"):
        g.solve(a, f"{solver} far", far, solver=solver, **numeric(5))
    g.solve(a, "clik far", far, solver="clik", **CLIK)
    g.solve(a, "dls too close", np.array([0.1, 0.05]), solver="dls", **numeric(6, 500))
    return g.records


def group_ur5_closed() -> list[dict]:
    g, a = Group(), arm("ur5")
    forms = ("se3", "h4", "pq", "x7", "prot", "h4list")
    q0s = ("none", "rand", "near", "randlist")
    sweep(g, a, "three_parallel", 36, 30, forms, q0s)
    sweep(g, a, "auto", 8, 32, forms, ("none", "rand"))
    sweep_all(g, a, "three_parallel", 12, 34, forms, ("none", "rand", "near"))
    qs = configurations(a, 3, 36)
    for i, q in enumerate(qs):  # wrist singularity: q5 = 0
        q = q.copy()
        q[4] = 0.0
        T = a.fk(q)
        g.solve(a, f"three_parallel singular #{i}", T, q0=q, solver="three_parallel")
        g.solve_all(a, f"three_parallel singular #{i}", T, q0=q, solver="three_parallel")
    T = a.fk(a.middle)
    cylinder = pin.SE3(T.rotation, np.array([0.0, 0.0, 0.05]))
    for label, P in (("far", far_pose("ur5", T)), ("inside the shoulder cylinder", cylinder)):
        g.solve(a, f"three_parallel {label}", P, solver="three_parallel")
        g.solve_all(a, f"three_parallel {label}", P, solver="three_parallel")
        g.solve(a, f"auto {label}", P)
    g.solve(a, "three_parallel with options", T, solver="three_parallel", tol_position=1e-9)
    return g.records


def group_ur5_numeric() -> list[dict]:
    g, a = Group(), arm("ur5")
    forms, q0s = ("se3", "h4", "pq", "pos"), ("none", "rand", "near")
    sweep(g, a, "dls", 12, 40, forms, q0s, lambda i: numeric(i))
    sweep(g, a, "dls", 4, 41, ("se3", "h4"), q0s, lambda i: numeric(i, weights=(1, 1, 1, 1, 1, 0)))
    sweep(g, a, "dls", 3, 42, ("se3", "h4"), q0s, lambda i: numeric(i, position_only=True))
    sweep(g, a, "qp", 8, 43, forms, q0s, lambda i: numeric(i))
    sweep(g, a, "qp", 2, 44, ("se3",), q0s, lambda i: numeric(i, weights=(1, 1, 1, 1, 1, 0)))
    sweep(g, a, "clik", 4, 45, ("se3", "h4"), q0s, lambda i: dict(CLIK))
    sweep(g, a, "auto", 4, 46, ("pos", "poslist"), q0s, lambda i: numeric(i))  # auto -> dls
    T = a.fk(a.middle)
    far = far_pose("ur5", T)
    for solver in ("dls", "qp"):
        g.solve(a, f"{solver} far", far, solver=solver, **numeric(7))
        g.solve(a, f"{solver} far position", np.array(far.translation), solver=solver, **numeric(7))
    g.solve(a, "clik far", far, solver="clik", **CLIK)
    inside = pin.SE3(T.rotation, np.array([0.0, 0.0, 0.05]))
    g.solve(a, "dls inside the shoulder cylinder", inside, solver="dls", **numeric(8, 600))
    g.solve_all(
        a,
        "dls solve_all",
        a.fk(configurations(a, 1, 47)[0]),
        solver="dls",
        **numeric(9, 1500, max_solutions=4),
    )
    return g.records


def group_abb_closed() -> list[dict]:
    g, a = Group(), arm("abb_irb120")
    forms = ("se3", "h4", "x7", "pq", "prot")
    q0s = ("none", "rand", "near", "randlist")
    sweep(g, a, "spherical", 36, 50, forms, q0s)
    sweep(g, a, "auto", 8, 52, forms, ("none", "rand"))
    sweep_all(g, a, "spherical", 12, 54, forms, ("none", "rand", "near"))
    for i, q in enumerate(configurations(a, 3, 56)):  # wrist singularity: q5 = 0
        q = q.copy()
        q[4] = 0.0
        T = a.fk(q)
        g.solve(a, f"spherical singular #{i}", T, q0=q, solver="spherical")
        g.solve_all(a, f"spherical singular #{i}", T, q0=q, solver="spherical")
    T = a.fk(a.middle)
    near_axis = pin.SE3(T.rotation, np.array([0.0, 0.0, 0.4]))  # wrist centre near axis 1
    for label, P in (("far", far_pose("abb_irb120", T)), ("near axis 1", near_axis)):
        g.solve(a, f"spherical {label}", P, solver="spherical")
        g.solve_all(a, f"spherical {label}", P, solver="spherical")
        g.solve(a, f"auto {label}", P)
    return g.records


def group_abb_numeric() -> list[dict]:
    g, a = Group(), arm("abb_irb120")
    q0s = ("none", "rand")
    sweep(g, a, "dls", 6, 60, ("se3", "h4", "pos"), q0s, lambda i: numeric(i))
    sweep(g, a, "qp", 4, 61, ("se3", "h4"), q0s, lambda i: numeric(i))
    sweep(g, a, "auto", 3, 62, ("pos",), q0s, lambda i: numeric(i))
    return g.records


def group_panda_numeric() -> list[dict]:
    g, a = Group(), arm("panda")
    forms, q0s = ("se3", "h4", "pq", "x7"), ("none", "rand", "near")
    sweep(g, a, "dls", 16, 70, forms, q0s, lambda i: numeric(i))
    sweep(g, a, "dls", 4, 71, ("se3", "h4"), q0s, lambda i: numeric(i, weights=(1, 1, 1, 1, 1, 0)))
    sweep(g, a, "dls", 4, 72, ("pos", "se3"), q0s, lambda i: numeric(i, position_only=True))
    sweep(g, a, "dls", 2, 73, ("se3",), q0s, lambda i: numeric(i, nullspace_gain=0.0))
    sweep(g, a, "qp", 8, 74, forms, q0s, lambda i: numeric(i))
    sweep(g, a, "qp", 2, 75, ("pos",), q0s, lambda i: numeric(i))
    sweep(g, a, "clik", 4, 76, ("se3", "h4"), ("none", "near"), lambda i: dict(CLIK))
    sweep(g, a, "auto", 8, 77, forms + ("pos",), q0s, lambda i: numeric(i))  # auto -> dls
    T = a.fk(a.middle)
    far = far_pose("panda", T)
    for solver in ("dls", "qp", "auto"):
        g.solve(a, f"{solver} far", far, solver=solver, **numeric(3))
    g.solve(a, "clik far", far, solver="clik", **CLIK)
    below = pin.SE3(T.rotation, np.array([0.0, 0.0, -0.3]))  # within the reach bound
    g.solve(a, "dls below the base", below, solver="dls", **numeric(4, 800))
    g.solve(a, "qp below the base", below, solver="qp", **numeric(4, 300))
    for i, q in enumerate(configurations(a, 2, 78)):
        g.solve_all(
            a, f"dls solve_all #{i}", a.fk(q), solver="dls", **numeric(i, 1500, max_solutions=4)
        )
    return g.records


def group_panda_swept() -> list[dict]:
    g, a = Group(), arm("panda")
    sweep(g, a, "swept", 15, 80, ("se3", "h4", "pq"), ("exact", "none", "near", "rand", "randlist"))
    sweep_all(g, a, "swept", 5, 82, ("se3", "h4"), ("exact", "none", "rand"))
    T = a.fk(a.middle)
    g.solve(a, "swept far", far_pose("panda", T), solver="swept")
    g.solve_all(a, "swept far", far_pose("panda", T), solver="swept")
    g.solve(
        a, "swept below the base", pin.SE3(T.rotation, np.array([0.0, 0.0, -0.3])), solver="swept"
    )
    return g.records


def group_others() -> list[dict]:
    """Continuous joints (kinova, a spherical wrist) and a prismatic joint (scara)."""
    g = Group()
    k = arm("kinova")
    sweep(g, k, "spherical", 8, 90, ("se3", "h4"), ("none", "rand", "near"))
    sweep(g, k, "auto", 3, 91, ("se3",), ("rand",))
    sweep_all(g, k, "spherical", 3, 92, ("se3",), ("none", "rand"))
    sweep(g, k, "dls", 4, 93, ("se3", "pos"), ("none", "rand"), lambda i: numeric(i))
    s = arm("scara")
    sweep(g, s, "dls", 8, 94, ("se3", "pos", "h4"), ("none", "rand"), lambda i: numeric(i))
    sweep(g, s, "qp", 3, 95, ("se3", "pos"), ("none", "rand"), lambda i: numeric(i))
    sweep(g, s, "auto", 3, 96, ("pos",), ("rand",), lambda i: numeric(i))
    g.solve(s, "dls far", np.array(FAR["scara"]), solver="dls", **numeric(1))
    return g.records


def group_batch() -> list[dict]:
    g = Group()
    u = arm("ur5")
    qs = configurations(u, 31, 100)
    T = [u.fk(q) for q in qs] + [far_pose("ur5", u.fk(u.middle))]
    H = np.stack([t.homogeneous for t in T])
    g.batch(u, "dls (N, 4, 4)", H, solver="dls", **numeric(0))
    g.batch(u, "dls (N, 4, 4) chunk_size=8", H[:16], solver="dls", chunk_size=8, **numeric(1))
    g.batch(u, "auto (N, 4, 4)", H[:20])  # three_parallel
    near = np.clip(np.stack(qs[:5]) + 0.05, u.lower, u.upper)
    g.batch(u, "clik (N, 4, 4) q0 per target", H[:5], q0=near, solver="clik", **CLIK)

    p = arm("panda")
    qs = configurations(p, 16, 101)
    X = np.stack([np.concatenate([p.fk(q).translation, quat_xyzw(p.fk(q))]) for q in qs])
    rng = np.random.default_rng(102)
    Q0 = np.stack([p.random_q(rng) for _ in qs])
    g.batch(p, "qp (N, 7) q0 per target", X, q0=Q0, solver="qp", **numeric(2))
    P = np.stack([p.fk(q).translation for q in qs] + [np.array(FAR["panda"])])
    g.batch(p, "dls (N, 3)", P, solver="dls", **numeric(3))
    g.batch(p, "auto (N, 7) one q0", X[:8], q0=p.middle, **numeric(4))  # dls
    g.batch(p, "swept list of SE3", [p.fk(q) for q in qs[:6]], solver="swept")

    b = arm("abb_irb120")
    H = np.stack([b.fk(q).homogeneous for q in configurations(b, 24, 103)])
    g.batch(b, "auto (N, 4, 4)", H)  # spherical

    a = arm("planar_2link")
    xy = [a.fk(q).translation[:2].tolist() for q in configurations(a, 12, 104)] + [[3.0, 0.5]]
    g.batch(a, "planar2r list of (x, y)", xy, solver="planar2r")
    g.batch(a, "dls list of (x, y)", xy, solver="dls", **numeric(5))
    return g.records


def group_path() -> list[dict]:
    g = Group()
    u = arm("ur5")
    rng = np.random.default_rng(110)
    qa = u.random_q(rng)
    qb = np.clip(qa + rng.uniform(-0.6, 0.6, u.dof), u.lower, u.upper)
    line = [u.fk(qa + (qb - qa) * t) for t in np.linspace(0.0, 1.0, 12)]
    g.path(u, "auto (three_parallel), joint-space line", line, qa)
    g.path(u, "dls, joint-space line", line, qa, solver="dls", **numeric(0))

    p = arm("panda")
    rng = np.random.default_rng(111)
    qa, qc = p.random_q(rng), p.random_q(rng)
    qb = np.clip(qa + rng.uniform(-0.4, 0.4, p.dof), p.lower, p.upper)
    poses = [p.fk(qa + (qb - qa) * t) for t in np.linspace(0.0, 1.0, 8)]
    poses.insert(5, p.fk(qc))  # a jump: discontinuous at max_joint_step 0.3
    H = np.stack([t.homogeneous for t in poses])
    g.path(p, "dls, line with a jump", H, qa, solver="dls", max_joint_step=0.3, **numeric(1))
    return g.records


GROUPS = {
    "arms": group_arms,
    "fk": group_fk,
    "planar_2link/closed_form": group_planar_closed,
    "planar_2link/numeric": group_planar_numeric,
    "ur5/closed_form": group_ur5_closed,
    "ur5/numeric": group_ur5_numeric,
    "abb_irb120/closed_form": group_abb_closed,
    "abb_irb120/numeric": group_abb_numeric,
    "panda/numeric": group_panda_numeric,
    "panda/swept": group_panda_swept,
    "kinova_scara": group_others,
    "batch": group_batch,
    "path": group_path,
}


def compute() -> dict[str, list[dict]]:
    """Every group's records, computed in this order (the order is part of the record)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", armik.ArmikWarning)  # no call here should warn
        return {name: make() for name, make in GROUPS.items()}


def dumps(groups: dict[str, list[dict]]) -> str:
    """The answers file: one record a line, so that a change shows as a short diff."""
    lines = ["{" + f'"format": {json.dumps(FORMAT)}, "groups": {{']
    for k, (name, records) in enumerate(groups.items()):
        lines.append(f"{json.dumps(name)}: [")
        last = len(records) - 1
        lines += [
            json.dumps(r, separators=(",", ":")) + ("," * (i < last)) for i, r in enumerate(records)
        ]
        lines.append("]" + "," * (k < len(groups) - 1))
    lines.append("}}")
    return "\n".join(lines) + "\n"


def main() -> int:
    groups = compute()
    ANSWERS.write_text(dumps(groups))
    calls = sum(len(v) for v in groups.values())
    print(f"wrote {ANSWERS} ({ANSWERS.stat().st_size / 1024:.0f} kB, {calls} records)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
