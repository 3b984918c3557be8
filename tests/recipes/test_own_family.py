"""A closed-form family of a test's own, added by CONTRIBUTING's recipe: a solver that
returns its branches as ``Answers``, registered with ``registry.register(SolverSpec(...))``
at a priority above the bundled families, applying to one arm only, and removed again with
``registry.unregister``. "auto" chooses it for that arm on every route, every answer it
gives is verified by forward kinematics, and a wrong answer it claims comes out a failure.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solvers import registry
from armik.solvers.answers import Answers
from armik.solvers.registry import SolverSpec
from armik.status import Status
from tests.conftest import arm as bundled

NAME = "toy2r"
ROOT = Path(__file__).resolve().parents[2]
ARM = "planar_2link"  # two revolute joints about z, l1 = 1.0 m, l2 = 0.8 m (robots/)
L1, L2 = 1.0, 0.8
WRONG = {"on": False}  # True: the elbow-up branch is off by 0.1 rad and still claimed


def why_not(arm, target=None, _opts=None):
    """None for the bundled planar 2-link arm, else why not (as a family's ``classify``
    would say it); weights and bounds the registry refuses (``solves``)."""
    if arm.name != ARM:
        return f"arm {arm.name!r} is not {ARM!r}, the one arm this family knows"
    return None


def run(arm, target, q0, opts, all_solutions):
    """Both elbow branches of the position in the plane z = 0 (the orientation is not
    chosen: the verdict measures it), nearest ``q0`` first, each joint within the arm's
    limits (+-pi: joint 1 turned by 2 pi into them, joint 2 an arccosine's value, which it
    keeps it declares, ``enforces_limits=True``); out of reach, the stretched arm towards
    it, claimed unreachable."""
    x, y = float(target.position[0]), float(target.position[1])
    r = math.hypot(x, y)
    c = (r * r - L1 * L1 - L2 * L2) / (2 * L1 * L2)
    if abs(c) > 1.0:
        q = np.array([[math.atan2(y, x), 0.0 if c > 0 else math.pi]])
        return Answers.of(q, [Status.UNREACHABLE], [f"{r:.3g} m is out of reach"], 2)
    rows = []
    # elbow-up: the elbow left of the line to the target seen from +z (armik's planar2r)
    for sign, label in ((-1.0, "elbow-up"), (1.0, "elbow-down")):
        q2 = sign * math.acos(c)
        q1 = math.atan2(y, x) - math.atan2(L2 * math.sin(q2), L1 + L2 * math.cos(q2))
        if WRONG["on"] and label == "elbow-up":
            q1 += 0.1
        q1 = math.remainder(q1, 2 * math.pi)  # its 2 pi turn within the limits, +-pi
        rows.append(((q1, q2), label))
    rows.sort(key=lambda row: float(np.linalg.norm(np.subtract(row[0], q0))))
    q = np.array([row[0] for row in rows])
    branches = [row[1] for row in rows]
    return Answers.of(q, [Status.CONVERGED] * 2, ["toy closed form"] * 2, 2, branch=branches)


@pytest.fixture
def family():
    """The family registered for one test, and removed after it whatever happens."""
    spec = registry.register(
        SolverSpec(
            name=NAME,
            kind="analytic",
            enforces_limits=True,  # its answers within the arm's limits (``run``)
            priority=1000,  # above planar2r (100): "auto" takes it wherever it applies
            why_not=why_not,
            run=run,
            summary="a test's closed form for the planar 2-link arm",
            solves=frozenset({"position_only"}),  # no weights, bounds, spin or cone
        )
    )
    try:
        yield spec
    finally:
        WRONG["on"] = False
        registry.unregister(NAME)


def _q(seed: int, n: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform([-2.5, 0.3], [2.5, 2.5], (n, 2))


def _verified(arm, r, T) -> None:
    """Pinocchio's FK of the answer, computed here, is the target: the tip's position."""
    assert r.success, r.reason
    got = arm.fk(r.q)
    np.testing.assert_allclose(got.translation, T.translation, atol=1e-9)


def test_auto_chooses_it_for_its_arm_only(family):
    arm = bundled(ARM)
    T = arm.fk(_q(1, 1)[0])
    r = arm.solve(T)
    assert r.solver == NAME and r.branch in ("elbow-up", "elbow-down")
    _verified(arm, r, T)
    ur5 = bundled("ur5")
    assert ur5.solve(ur5.fk(ur5.middle)).solver != NAME
    assert NAME in armik.solvers()
    with pytest.raises(armik.SolverError, match="not 'planar_2link'"):
        ur5.solve(ur5.fk(ur5.middle), solver=NAME)


def test_solve_and_solve_all(family):
    arm = bundled(ARM)
    for q in _q(2, 5):
        T = arm.fk(q)
        r = arm.solve(T, q0=q + 0.05)
        assert r.solver == NAME
        _verified(arm, r, T)
        np.testing.assert_allclose(r.q, q, atol=1e-9)  # the branch nearest q0
        # a full pose: the branch whose tip turns the other way fails the verdict's check
        found = arm.solve_all(T)
        assert [a.solver for a in found] == [NAME, NAME]
        assert [a.success for a in found] == [True, False]
        _verified(arm, found[0], T)
        assert "orientation error" in found[1].reason
        # a position: both branches reach it, both verified
        both = arm.solve_all(T.translation)
        assert {a.branch for a in both} == {"elbow-up", "elbow-down"}
        for a in both:
            _verified(arm, a, T)
    far = arm.solve(pin.SE3(np.eye(3), np.array([2.5, 0.0, 0.0])))
    assert not far.success and far.solver == NAME


def _with_collisions() -> armik.Arm:
    """The planar 2-link arm with a thin box round each link (the bundled URDF has no
    ``<collision>``): the same name, so the family applies."""
    text = (ROOT / "robots" / f"{ARM}.urdf").read_text()
    for link, length in (("link1", L1), ("link2", L2)):
        box = (
            f'<collision><origin xyz="{length / 2} 0 0"/><geometry>'
            f'<box size="{length * 0.8} 0.04 0.04"/></geometry></collision>'
        )
        text = text.replace(f'<link name="{link}">', f'<link name="{link}">{box}')
    return armik.load_string(text)


def test_a_position_an_obstacle_and_a_preference(family):
    arm = bundled(ARM)
    q = np.array([0.3, 1.2])
    T = arm.fk(q)
    r = arm.solve(T.translation)
    assert r.solver == NAME and r.success
    # an obstacle on link 2 of the branch nearest q0: the other branch, verified clear
    boxed = _with_collisions()
    assert boxed.name == ARM
    on_link2 = arm.fk(q, frame="link2").act(np.array([0.4, 0.0, 0.0]))
    ball = armik.Sphere(0.05, tuple(on_link2))
    clear = boxed.solve(T.translation, q0=q, obstacles=[ball])
    assert clear.solver == NAME
    _verified(arm, clear, T)
    assert clear.q[1] < 0 and clear.extra["min_distance"] > 0
    # a preference ranks the family's verified branches: elbow-up, though farther
    ranked = arm.solve(T.translation, q0=q, prefer=armik.Posture(np.array([0.0, -1.0])))
    assert ranked.solver == NAME and ranked.q[1] < 0
    _verified(arm, ranked, T)


@pytest.mark.parametrize("workers", [1, 2])
def test_solve_batch(family, workers):
    arm = bundled(ARM)
    qs = _q(4, 8)
    targets = [arm.fk(q) for q in qs]
    res = arm.solve_batch(targets, q0=qs + 0.05, workers=workers, chunk_size=2)
    assert res.solver == NAME and res.success.all()
    for i, T in enumerate(targets):
        np.testing.assert_allclose(arm.fk(res.q[i]).translation, T.translation, atol=1e-9)
        np.testing.assert_allclose(res.q[i], qs[i], atol=1e-9)


def test_solve_batch_on_a_dask_cluster(family):
    # the workers are processes of their own: the family travels to them and is
    # registered there, as the arm is (``armik.solve.distributed.SolverOnWorker``)
    distributed = pytest.importorskip("distributed", reason="the cluster extra")
    from armik.solve import distributed as on_dask

    arm = bundled(ARM)
    qs = _q(6, 6)
    targets = [arm.fk(q) for q in qs]
    cluster = distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None
    )
    try:
        with distributed.Client(cluster) as client:
            res = on_dask.solve_batch(arm, targets, q0=qs + 0.05, client=client, chunk_size=2)
    finally:
        cluster.close()
    here = arm.solve_batch(targets, q0=qs + 0.05, workers=1)
    assert res.solver == NAME and res.success.sum() >= 5, res.summary()
    np.testing.assert_array_equal(res.q, here.q)
    np.testing.assert_array_equal(res.success, here.success)


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_solve_path(family, plan):
    arm = bundled(ARM)
    q = np.array([0.2, 1.0])
    line = [arm.fk(q + [0.02 * k, 0.01 * k]) for k in range(5)]
    path = arm.solve_path(line, q, plan=plan)
    assert path.solver == NAME and path.success.all()
    for i, T in enumerate(line):
        np.testing.assert_allclose(arm.fk(path.q[i]).translation, T.translation, atol=1e-9)
    assert np.abs(np.diff(path.q, axis=0)).max() < 0.1  # one branch all along


def test_held_joints(family):
    """Holding a joint of a 2-joint arm is the task solver's (its box rows), which starts
    from the family's answer to the plain target: the answer holds the joint."""
    arm = bundled(ARM)
    q = np.array([0.4, 1.1])
    T = arm.fk(q)
    r = arm.solve(T.translation, hold={"joint1": 0.4}, q0=[0.4, 0.5])
    assert abs(r.q[0] - 0.4) < 1e-9
    _verified(arm, r, T)


def test_a_wrong_answer_is_a_failure(family):
    """The family claims a wrong elbow-up branch converged: the verdict measures it and
    refuses it on every route, and goes on to the branch that holds."""
    arm = bundled(ARM)
    WRONG["on"] = True
    q = np.array([0.3, -1.2])  # elbow-up: the wrong branch is the nearest
    p = arm.fk(q).translation
    found = arm.solve_all(p, q0=q)
    up = [a for a in found if a.branch == "elbow-up"][0]
    assert not up.success and "position error" in up.reason
    r = arm.solve(p, q0=q)
    assert r.success and r.branch == "elbow-down"
    np.testing.assert_allclose(arm.fk(r.q).translation, p, atol=1e-9)
    res = arm.solve_batch([p, p], q0=[q, q], workers=1)
    assert res.success.all() and (res.q[:, 1] > 0).all()
    path = arm.solve_path([p, p], q, plan="global")
    assert (~path.success | (path.q[:, 1] > 0)).all()
    assert arm.solve(arm.fk(q), q0=q).success is False  # a pose: neither branch holds


def test_unregister_drops_what_auto_chose(family):
    arm = bundled(ARM)
    T = arm.fk(np.array([0.5, 0.7]))
    assert arm.solve(T).solver == NAME
    before = registry.generation
    registry.unregister(NAME)
    try:
        assert registry.generation == before + 1 and NAME not in armik.solvers()
        assert arm.solve(T).solver == "planar2r"  # kept choices and plans dropped
        with pytest.raises(armik.SolverError, match="unknown solver 'toy2r'"):
            registry.unregister(NAME)
    finally:
        registry.register(family)
    assert arm.solve(T).solver == NAME


def test_a_taken_solver_name_is_an_armik_error_naming_it():
    from armik.solvers import registry

    with pytest.raises(armik.SolverError, match="solver name 'dls' is taken: register it"):
        registry.register(registry.get("dls"))
