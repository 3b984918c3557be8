"""7-joint arms with one joint held (``hold=``): every answer has the joint at its value and
reaches the target (Pinocchio on the 7-joint arm), the configuration that made the target
is among ``solve_all``'s answers, and bad ``hold=`` values get a clear error."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import InputError, JointError, OptionError
from armik.model.catalogue import CATALOGUE
from armik.model.random_arms import iiwa_like_urdf

from ..conftest import write_urdf

iiwa_urdf = iiwa_like_urdf  # a KUKA iiwa 14's kinematics (armik.model.random_arms)


@pytest.fixture(scope="module")
def iiwa(tmp_path_factory):
    path = write_urdf(tmp_path_factory.mktemp("iiwa"), iiwa_urdf(), name="iiwa.urdf")
    return armik.load(path, base="base", tip="tool")


def _wrapped(a, b) -> float:
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max())


def _check_complete(arm, joint: str, seeds: int, rng) -> set[str]:
    k = arm.joint_names.index(joint)
    solvers = set()
    for _ in range(seeds):
        q = arm.random_q(rng)
        T = arm.fk(q)
        results = arm.solve_all(T, hold={joint: float(q[k])})
        ok = [r for r in results if r.success]
        assert ok
        for r in ok:
            assert r.q.shape == (7,)
            assert r.q[k] == pytest.approx(q[k], abs=1e-12)
            assert np.linalg.norm(pin.log6(arm.fk(r.q).inverse() * T).vector) < 1e-9
            assert np.all(r.q >= arm.lower) and np.all(r.q <= arm.upper)
            assert "held at" in r.reason
        assert min(_wrapped(r.q, q) for r in ok) < 1e-6, (joint, q)
        solvers.add(ok[0].solver)
        one = arm.solve(T, hold={joint: float(q[k])}, q0=q)
        assert one.success and _wrapped(one.q, q) < 1e-6  # from q itself: q is nearest
    return solvers


def test_panda_with_joint_7_held_is_the_swept_closed_form():
    arm = armik.load("panda")
    assert _check_complete(arm, "panda_joint7", 6, np.random.default_rng(1)) == {"swept"}


def test_panda_with_joint_7_held_by_the_general_search_asked_by_name():
    arm = armik.load("panda")
    rng = np.random.default_rng(5)
    q = arm.random_q(rng)
    T = arm.fk(q)
    every = arm.solve_all(T, hold={"panda_joint7": float(q[6])}, solver="general_6r")
    ok = [r for r in every if r.success]
    assert ok and {r.solver for r in ok} == {"general_6r"}
    assert min(_wrapped(r.q, q) for r in ok) < 1e-6


def test_panda_with_joint_1_held():
    arm = armik.load("panda")
    solvers = _check_complete(arm, "panda_joint1", 4, np.random.default_rng(2))
    assert solvers == {"elimination_6r"}  # no closed form: the elimination, not a search


def test_iiwa_like_arm_with_joint_3_held_is_a_closed_form(iiwa):
    solvers = _check_complete(iiwa, "j3", 6, np.random.default_rng(3))
    assert solvers == {"spherical"}  # axes 1, 2 meet and the wrist is spherical


def test_hold_none_is_q0s_value(iiwa):
    rng = np.random.default_rng(4)
    q = iiwa.random_q(rng)
    T = iiwa.fk(q)
    r = iiwa.solve(T, hold={"j3": None}, q0=q)
    assert r.success and r.q[2] == q[2]
    every = iiwa.solve_all(T, hold={"j3": None}, q0=q)
    assert all(x.q[2] == q[2] for x in every)


def test_bad_hold_values_are_refused_with_the_fix(iiwa):
    T = iiwa.fk(np.zeros(7))
    with pytest.raises(JointError, match="unknown joint 'j9'.*'j1'"):
        iiwa.solve(T, hold={"j9": 0.0})
    with pytest.raises(JointError, match=r"outside joint 'j3'.*limits.*within them"):
        iiwa.solve(T, hold={"j3": 4.0})
    with pytest.raises(OptionError, match="finite number"):
        iiwa.solve(T, hold={"j3": float("nan")})
    with pytest.raises(OptionError, match="map joint names"):
        iiwa.solve(T, hold={})
    with pytest.raises(OptionError, match="map joint names"):
        iiwa.solve(T, hold="j3")
    two = {"j3": 0.0, "j4": 0.0}  # the task solver's, one answer a waypoint: no global plan
    with pytest.raises(OptionError, match=r"plan='global'.*plan='follow'.*with_locked"):
        iiwa.solve_path([T, T], np.zeros(7), hold=two, plan="global")
    assert issubclass(OptionError, InputError)


def test_a_path_holds_joints_the_compiled_path_cannot_as_solve_does():
    """``hold=`` on a path where no closed form holds it (a 6-joint arm, two joints of a
    7-joint arm) is the task solver's, waypoint by waypoint, as ``solve`` takes it, where
    it was refused; every waypoint's answer holds the joint and reaches its position."""
    ur5 = armik.load("ur5")
    q = ur5.middle + 0.1
    start = ur5.fk(q).translation
    points = [start + np.array([0.0, 0.01 * k, 0.0]) for k in range(3)]
    path = ur5.solve_path(points, q, hold={"wrist_3_joint": 0.1})
    assert path.success.all()
    for p, answer in zip(points, path.q):
        assert answer[5] == 0.1 and np.linalg.norm(ur5.fk(answer).translation - p) < 1e-6
        assert np.abs(answer - q).max() < 0.5  # followed from the start, not elsewhere


@pytest.mark.parametrize(
    "said", [{"weights": (1, 1, 1, 1, 1, 0)}, {"bounds": (0, 0, 0, 0, 0, np.inf)}]
)
def test_a_held_joint_of_a_6_joint_arm_with_a_poses_weights_or_bounds(said):
    """Held by the task solver, the weights and bounds said by the pose's task: refused
    before, as if hold= were for 7-joint arms only."""
    ur5 = armik.load("ur5")
    q = np.array([0.3, -1.0, 1.2, -0.5, 1.0, 0.2])
    T = ur5.fk(q)
    T.rotation = T.rotation @ pin.exp3(np.array([0.0, 0.0, 0.7]))  # off about the free axis
    r = ur5.solve(T, q0=q, hold={"shoulder_pan_joint": 0.3}, **said)
    assert r.success and r.q[0] == pytest.approx(0.3, abs=1e-9)
    got = ur5.fk(r.q)
    assert np.linalg.norm(got.translation - T.translation) < 1e-6
    axis_z = T.rotation[:, 2]
    assert np.allclose(got.rotation[:, 2], axis_z, atol=1e-5)  # only the free axis turns


def test_hold_in_a_batch_holds_the_joint_on_every_row_as_solve_does(iiwa):
    """A batch with a joint held is solved row by row as solve solves it, with or without a
    preference (it was refused without one and taken with one)."""
    rng = np.random.default_rng(4)
    qs = [iiwa.random_q(rng) for _ in range(3)]
    held = float(qs[0][2])
    for q in qs:
        q[2] = held
    poses = np.array([iiwa.fk(q).homogeneous for q in qs])
    for prefer in (None, "nearest"):
        out = iiwa.solve_batch(poses, hold={"j3": held}, prefer=prefer, progress=False)
        assert out.success.all()
        assert np.allclose(out.q[:, 2], held, atol=1e-9)
        for i, T in enumerate(poses):
            r = iiwa.solve(T, hold={"j3": held}, prefer=prefer)
            assert np.array_equal(r.q, out.q[i])


def test_a_path_with_a_joint_held_keeps_it_there(iiwa):
    rng = np.random.default_rng(8)
    q = iiwa.random_q(rng)
    poses = [iiwa.fk(q + 0.01 * k * np.array([1, 1, 0, 1, 1, 1, 1.0])) for k in range(3)]
    out = iiwa.solve_path(poses, q, hold={"j3": float(q[2])})
    assert out.success.all() and np.all(out.q[:, 2] == q[2])


def test_a_solver_named_for_a_held_joint_it_does_not_hold_says_so():
    """The swept closed form holds the Panda's joint 7: with joint 1 held, the six left are
    solved by what "auto" chooses, and the reason says why the one named did not; a closed
    form of neither the arm nor the six joints is refused naming the held joint; a second
    held joint names the task solver that holds it."""
    from armik.errors import SolverError

    arm = armik.load("panda")
    q = arm.random_q(950)
    T = arm.fk(q)
    r = arm.solve(T, hold={"panda_joint1": float(q[0])}, solver="swept")
    assert r.success and r.solver != "swept" and "swept solves all seven" in r.reason
    with pytest.raises(SolverError, match="with 'panda_joint1' held, six joints are left"):
        arm.solve(T, hold={"panda_joint1": float(q[0])}, solver="srs")
    with pytest.raises(OptionError, match="held by the task solver.*solver='auto', got 'swept'"):
        two = {"panda_joint1": float(q[0]), "panda_joint2": float(q[1])}
        arm.solve(T, hold=two, solver="swept")


@pytest.mark.parametrize("solver", ["auto", "dls"])
def test_a_held_joints_result_says_its_verdict_once_and_counts_its_search(solver):
    """The six joints' answer is verified again on the whole arm: its reason says the
    measure once, and its counts are the six joints' search's (what its words say)."""
    arm = armik.load("panda")
    q = arm.random_q(950)
    r = arm.solve(arm.fk(q), hold={"panda_joint1": float(q[0])}, solver=solver)
    assert r.success and r.reason.count("verified by forward kinematics") == 1
    if "restart(s)" in r.reason:
        assert f"converged after {r.restarts} restart(s)" in r.reason and r.iterations > 0


def test_a_path_holding_the_pandas_joint_7_is_solved_as_solve_solves_it():
    # the sweep at the held value, as solve and solve_batch run it: a target no branch
    # reaches at that value is proved unreachable, not left unconverged after the budget
    panda = armik.load("panda")
    hold = {"panda_joint7": 0.3}
    q = panda.random_q(2)
    q[6] = 0.3
    T = panda.fk(q)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.002 * k, 0]) for k in range(4)]
    for plan in ("follow", "global"):
        path = panda.solve_path(line, q, hold=hold, plan=plan)
        assert path.success.all() and path.solver == "swept", (plan, path.summary())
        assert np.abs(path.q[:, 6] - 0.3).max() <= 1e-9
    Tp = panda.fk(panda.random_q(2))
    alone = panda.solve(Tp, q0=panda.random_q(1), hold=hold)
    assert alone.status is armik.Status.UNREACHABLE, alone.reason
    path = panda.solve_path([Tp, Tp], panda.random_q(1), hold=hold)
    assert path.counts() == {"unreachable": 2} and path.solver == "swept", path.summary()


def test_a_global_path_holding_another_joint_than_7_names_the_solver_that_solved_it():
    """Joint 3 of the Panda held on a global path: no sweep runs (each rung is solved on
    the arm with joint 3 locked, as solve solves it), so the result names that solver,
    as the followed path does, not the sweep's; with a numeric solver named, both."""
    panda = armik.load("panda")
    q = panda.random_q(np.random.default_rng(1))
    q[2] = 0.2
    T = panda.fk(q)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(4)]
    hold = {"panda_joint3": 0.2}
    alone = panda.solve(line[0], q0=q, hold=hold)
    assert alone.success and alone.solver != "swept"
    for plan in ("follow", "global"):
        path = panda.solve_path(line, q, hold=hold, plan=plan)
        assert path.success.all() and path.solver == alone.solver, (plan, path.summary())
        assert np.abs(path.q[:, 2] - 0.2).max() <= 1e-9
        for pose, x in zip(line, path.q):
            assert np.abs(pin.log6(pose.actInv(panda.fk(x))).vector).max() <= 1e-6
    named = panda.solve_path(line, q, hold=hold, plan="global", solver="dls")
    assert named.success.all() and "swept" not in named.solver.split("+"), named.solver
    held7 = panda.solve_path(line, q, hold={"panda_joint7": float(q[6])}, plan="global")
    assert held7.success.all() and held7.solver == "swept"  # the sweep at the held value


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_a_path_holding_a_joint_at_none_holds_it_at_the_starts_value(plan, monkeypatch):
    """``hold={"panda_joint7": None}`` on a path holds the joint at q0's value, as on
    ``solve`` (docs/solvers.md): every waypoint, and on a global plan every rung it plans
    over, at that value, the answers an explicit hold at it gives; without q0 at the
    middle of its limits."""
    from armik.solve import ladder

    panda = armik.load("panda")
    q = panda.random_q(3)
    q[6] = 0.4
    step = np.array([1.0, -1.0, 1.0, 1.0, -1.0, 1.0, 0.0])  # joint 7 stays
    line = [panda.fk(q + 0.03 * k * step) for k in range(1, 5)]
    rungs: list = []
    plan_over = ladder.plan

    def spied(arm, every, batch, found, *args, **kwargs):
        rungs.extend(r for at in found for r in at)
        return plan_over(arm, every, batch, found, *args, **kwargs)

    monkeypatch.setattr(ladder, "plan", spied)
    budget = {"iteration_budget": 2000}
    held = panda.solve_path(line, q, hold={"panda_joint7": None}, plan=plan, **budget)
    given = panda.solve_path(line, q, hold={"panda_joint7": 0.4}, plan=plan, **budget)
    assert held.success.all(), held.summary()
    np.testing.assert_array_equal(held.q, given.q)
    assert (held.q[:, 6] == 0.4).all()
    for T, x in zip(line, held.q):
        tip = panda.fk(x)
        assert np.linalg.norm(tip.translation - T.translation) < 1e-6
    assert (plan == "global") == bool(rungs)
    assert all(r.q[6] == 0.4 for r in rungs)
    middle = panda.solve_path(line[:2], None, hold={"panda_joint7": None}, plan=plan, **budget)
    assert (middle.q[:, 6] == panda.middle[6]).all()


def test_held_joints_with_an_aim_are_the_task_solvers_on_every_route():
    """``hold=`` with ``cone=`` on a 6-joint arm: the aimed target as the tasks it lowers
    from (its position and an ``armik.Axis``), held by the task solver, on ``solve``,
    ``solve_batch`` and a followed path, where ``solve`` refused it and a batch dropped
    the cone (every row an exact pose, failed)."""
    ur5 = armik.load("ur5")
    q = ur5.middle + 0.1
    T = ur5.fk(q)
    cone = (0.0, 0.0, 1.0, 0.1)  # the tool's z within 0.1 rad: its spin is free

    def holds(answer, target):
        F = ur5.fk(answer)
        angle = np.arccos(np.clip(F.rotation[:, 2] @ target.rotation[:, 2], -1, 1))
        near = np.linalg.norm(F.translation - target.translation) < 1e-6
        return answer[5] == 0.7 and near and angle <= 0.1 + 1e-6

    r = ur5.solve(T, q0=q, hold={"wrist_3_joint": 0.7}, cone=cone)
    assert r.success and holds(r.q, T), r.reason
    batch = ur5.solve_batch([T, T], q0=q, hold={"wrist_3_joint": 0.7}, cone=cone, workers=1)
    assert batch.success.all() and all(holds(a, T) for a in batch.q)
    shifted = [pin.SE3(T.rotation, T.translation + [0.0, 0.01 * k, 0.0]) for k in range(3)]
    near = ur5.solve(T, q0=q, hold={"wrist_3_joint": 0.7}, cone=cone).q  # start held
    path = ur5.solve_path(shifted, near, hold={"wrist_3_joint": 0.7}, cone=cone)
    assert path.success.all() and all(holds(a, t) for a, t in zip(path.q, shifted))
    with pytest.raises(OptionError, match="on a position target points the tip.s axis nowhere"):
        ur5.solve(T.translation, hold={"wrist_3_joint": 0.7}, cone=cone)


def test_a_held_value_outside_the_limits_is_told_in_the_joints_unit_and_digits():
    """The refusal of a held value outside a joint's limits prints the limits to as many
    digits as tell them from the value (a UR wrist's 2 pi, 6.28319 against 6.2832 given),
    in metres for a prismatic joint."""
    ur5 = armik.load("ur5")
    T = ur5.fk(ur5.middle)
    with pytest.raises(JointError, match=r"6.2832 rad .*\[-6.283185307, 6.283185307\] rad"):
        ur5.solve(T, hold={"wrist_3_joint": 6.2832})
    scara = armik.load("scara")
    k = int(np.flatnonzero(scara.kinematics.prismatic)[0])
    name, beyond = scara.joint_names[k], float(scara.upper[k]) + 0.01
    with pytest.raises(JointError, match=rf"{beyond!r} m is outside .* m: give"):
        scara.solve(scara.fk(scara.middle), hold={name: beyond})


def test_a_held_value_within_limits_with_limits_widened_is_solved_there():
    arm = armik.load("panda").with_limits({"panda_joint1": (-3.2, 3.2)})  # URDF's: 2.8973
    q = np.array([3.0, -0.3, 0.2, -2.0, 0.1, 1.5, 0.4])
    model = pin.buildModelFromUrdf(str(CATALOGUE["panda"].urdf_path()))
    data = model.createData()

    def fk(values):  # Pinocchio on the whole URDF (its root is the base), the fingers at 0
        qp = pin.neutral(model)
        qp[:7] = values
        pin.framesForwardKinematics(model, data, qp)
        return data.oMf[model.getFrameId(arm.tip, pin.BODY)]

    T = arm.fk(q)
    assert fk(q).isApprox(T, 1e-12)
    r = arm.solve(T, hold={"panda_joint1": 3.0})
    assert r.success, r.reason
    assert r.q[0] == 3.0 and np.linalg.norm(pin.log6(fk(r.q).inverse() * T).vector) < 1e-9
    narrow = armik.load("panda").with_limits({"panda_joint1": (-1.0, 1.0)})
    with pytest.raises(JointError, match=r"'panda_joint1', whose limits are \[-1, 1\]"):
        narrow.solve(T, hold={"panda_joint1": 2.0})


@pytest.mark.parametrize(
    "joint, words",
    [
        ("panda_finger_joint1", "'panda_finger_joint1' is not on this arm's chain from"),
        ("panda_joint8", "'panda_joint8' is a fixed joint: it has no value to hold"),
    ],
)
def test_a_held_joint_of_the_urdf_off_the_chain_is_named_as_such(joint, words):
    """A finger off the Panda's chain, its fixed flange joint: said as such, not as an
    unknown joint with a joint of the chain suggested for it."""
    arm = armik.load("panda")
    T = arm.fk(arm.middle)
    for how in ({"hold": {joint: 0.01}}, {"constraints": [armik.Hold(joint, 0.01)]}):
        with pytest.raises(JointError, match=words) as info:
            arm.solve(T, **how)
        assert "unknown" not in str(info.value) and info.value.joint == joint
