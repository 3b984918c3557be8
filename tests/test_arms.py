"""Several tips at once (``armik.load(..., tips=[...])``): a dual-arm cell of two IRB 120s
on one base, each arm by its own closed form; the Baxter's two 7-joint arms; chains that
share joints refused with the way round."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.arms_request import UNION_ITERATIONS, descent_settings, read_request
from armik.constraints.hold import HELD_TOL
from armik.status import Status
from tests.conftest import whole_placements

ROBOTS = Path(__file__).resolve().parents[1] / "robots"


def dual_irb120() -> str:
    """Two IRB 120s, 1 m apart on a common base: their links and joints prefixed."""
    text = (ROBOTS / "abb_irb120.urdf").read_text()
    body = text[text.index("<robot") :]
    body = body[body.index(">") + 1 : body.rindex("</robot>")]
    body = re.sub(r"<!--.*?-->", "", body, flags=re.S)
    arms = []
    for side, y in (("l_", 0.5), ("r_", -0.5)):
        part = re.sub(
            r'(name|link)="([^"]+)"', lambda m, s=side: f'{m.group(1)}="{s}{m.group(2)}"', body
        )
        arms.append(
            part + f'<joint name="{side}mount" type="fixed"><parent link="cell"/>'
            f'<child link="{side}base_link"/><origin xyz="0 {y} 0" rpy="0 0 0"/></joint>'
        )
    return '<robot name="dual_irb120"><link name="cell"/>' + "".join(arms) + "</robot>"


@pytest.fixture(scope="module")
def cell() -> armik.Arms:
    return armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])


def test_two_arms_each_by_its_closed_form(cell):
    assert cell.tips == ("l_tool0", "r_tool0") and cell.dof == 12
    assert cell.joint_names[:2] == ("l_joint_1", "l_joint_2")
    rng = np.random.default_rng(33)
    for _ in range(20):
        q = cell.random_q(rng)
        targets = {"l_tool0": cell.fk(q, "l_tool0"), "r_tool0": cell.fk(q, "r_tool0").translation}
        r = cell.solve(targets)
        assert r.success and r.status is Status.CONVERGED, r.reason
        assert "l_tool0 by spherical" in r.reason
        assert set(r.extra["errors"]) == {"l_tool0", "r_tool0"}
        assert r.extra["errors"]["r_tool0"][1] is None  # a position target
        parts = cell.split(r.q)
        left = cell.chain("l_tool0").fk(parts["l_tool0"])
        assert np.allclose(left.homogeneous, targets["l_tool0"].homogeneous, atol=1e-9)
        # the cell's own FK, as Pinocchio reads the whole URDF
        full = pin.buildModelFromXML(dual_irb120())
        data = full.createData()
        qf = pin.neutral(full)
        for name, value in zip(cell.joint_names, r.q):
            qf[full.joints[full.getJointId(name)].idx_q] = value
        pin.framesForwardKinematics(full, data, qf)
        right = data.oMf[full.getFrameId("r_tool0")].translation
        assert np.allclose(right, targets["r_tool0"], atol=1e-6)  # the solve's tolerance


def test_a_failing_tip_is_named(cell):
    q = cell.middle
    r = cell.solve({"l_tool0": cell.fk(q, "l_tool0"), "r_tool0": np.array([5.0, 0.0, 0.0])})
    assert not r.success and r.reason.startswith("r_tool0: unreachable")
    assert r.extra["results"]["l_tool0"].success


def test_the_baxter_two_arms():
    path = armik.load("panda").source  # example-robot-data's folder, beside the Panda's
    baxter = Path(path).parents[2] / "baxter_description" / "urdf" / "baxter.urdf"
    robot = armik.load(baxter, tips=["left_gripper", "right_gripper"])
    rng = np.random.default_rng(1)
    q = robot.random_q(rng)
    r = robot.solve({tip: robot.fk(q, tip) for tip in robot.tips}, iteration_budget=3000)
    assert r.success, r.reason
    J = robot.jacobian(r.q, "right_gripper")
    assert J.shape == (6, 14) and not J[:, :7].any()


def test_two_hands_over_a_shared_torso():
    """TALOS (example-robot-data): both grippers' poses, the torso's two joints shared;
    every success checked on Pinocchio's model of the whole URDF."""
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    tips = ["gripper_left_base_link", "gripper_right_base_link"]
    robot = armik.load(urdf, tips=tips)
    assert robot.shared == ("torso_1_joint", "torso_2_joint") and robot.dof == 16
    full = pin.buildModelFromUrdf(str(urdf))
    data = full.createData()
    rng = np.random.default_rng(5)
    solved = 0
    for _ in range(40):
        q = robot.random_q(rng)
        whole_placements(full, data, robot.joint_names, q)
        targets = {tip: data.oMf[full.getFrameId(tip)].copy() for tip in tips}
        r = robot.solve(targets, iteration_budget=3000)  # deterministic, not timed
        if not r.success:
            assert r.status is Status.NOT_CONVERGED
            continue
        solved += 1
        whole_placements(full, data, robot.joint_names, r.q)
        for tip in tips:
            err = pin.log6(targets[tip].inverse() * data.oMf[full.getFrameId(tip)]).vector
            assert np.abs(err).max() <= 2e-6
        assert (r.q >= robot.lower - 1e-9).all() and (r.q <= robot.upper + 1e-9).all()
        assert set(r.extra["errors"]) == set(tips)
    # restarts from each chain's compiled answer, chains in a random order, short descents:
    # every one of these (18 of 20 from random restarts with 100-step descents)
    assert solved == 40


def talos() -> armik.Arms:
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    return armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])


def test_a_shared_torso_takes_a_solver_name():
    """``solver=`` names the chains' own solver (the descent's starts); an unknown name is
    refused by name, not skipped."""
    robot = talos()
    q = robot.random_q(np.random.default_rng(3))
    targets = {tip: robot.fk(q, frame=tip) for tip in robot.tips}
    for solver in ("dls", "qp"):
        r = robot.solve(targets, solver=solver, iteration_budget=3000)
        assert r.success, r.reason
    with pytest.raises(armik.SolverError, match="unknown solver 'nope'"):
        robot.solve(targets, solver="nope")
    # a name no chain takes would start no chain from it: refused by name, each chain's why
    with pytest.raises(armik.SolverError, match="'planar2r' applies to no chain.*exactly 2"):
        robot.solve(targets, solver="planar2r")


def test_a_posture_over_a_shared_torso_moves_the_answer_along_the_tasks_null_space():
    """``prefer=armik.Posture(...)`` weighted on the torso: the answer found moved along
    what the hands' tasks leave free while the score falls, every hand still on its target
    by Pinocchio's FK: a score no higher than the plain answer's from the same start, and
    the score reported is the hand computation's. ``manipulability`` (one tip's Jacobian)
    is refused by name."""
    robot = talos()
    torso = [robot.joint_names.index(j) for j in robot.shared]
    weights = np.zeros(robot.dof)
    weights[torso] = 1.0
    upright = armik.Posture(robot.middle, weights)
    rng = np.random.default_rng(9)
    lowered = 0
    for _ in range(6):
        q = robot.random_q(rng)
        targets = {tip: robot.fk(q, frame=tip).translation for tip in robot.tips}
        plain = robot.solve(targets, iteration_budget=3000, seed=1)
        r = robot.solve(targets, iteration_budget=3000, seed=1, prefer=upright)
        assert plain.success and r.success, r.reason
        for tip in robot.tips:
            assert np.linalg.norm(robot.fk(r.q, frame=tip).translation - targets[tip]) <= 1e-6
        assert (r.q >= robot.lower - 1e-9).all() and (r.q <= robot.upper + 1e-9).all()
        score = float(weights @ (r.q - robot.middle) ** 2)
        assert r.score == r.extra["score"] == pytest.approx(score, rel=1e-12, abs=1e-15)
        assert set(r.errors) == set(robot.tips) and max(p for p, _ in r.errors.values()) <= 1e-6
        assert r.as_dict()["score"] == r.score and set(r.as_dict()["errors"]) == set(robot.tips)
        assert "prefer=posture" in r.reason
        assert score <= float(weights @ (plain.q - robot.middle) ** 2) + 1e-12
        lowered += score < float(weights @ (plain.q - robot.middle) ** 2) - 1e-6
    assert lowered >= 3  # hands' positions leave the torso free: it moves upright
    with pytest.raises(armik.OptionError, match="manipulability.*torso_1"):
        robot.solve(targets, prefer="manipulability")


def test_a_tip_beyond_reach_over_a_shared_torso_is_named_and_the_other_solved():
    """The right hand's target beyond its chain's reach: unreachable (a proof, not a
    search's miss), the reason naming that tip first; the left hand solved without it, its
    error Pinocchio's; the right hand's error measured at the answer."""
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    left, right = "gripper_left_base_link", "gripper_right_base_link"
    robot = armik.load(urdf, tips=[left, right])
    T_left = robot.fk(robot.random_q(np.random.default_rng(4)), frame=left)
    far = pin.SE3(np.eye(3), np.array([2.0, -1.0, 1.0]))
    r = robot.solve({left: T_left, right: far}, iteration_budget=3000)
    assert not r.success and r.status is Status.UNREACHABLE
    assert r.reason.startswith(f"tip '{right}': target is ") and "beyond" in r.reason
    assert f"the other tips ['{left}'], solved without it: converged" in r.reason
    err = pin.log6(T_left.actInv(robot.fk(r.q, frame=left))).vector
    assert np.abs(err).max() <= 1e-6
    assert r.extra["errors"][left][0] <= 1e-6
    X = robot.fk(r.q, frame=right)
    assert r.extra["errors"][right][0] == pytest.approx(
        np.linalg.norm(X.translation - far.translation)
    )
    assert r.position_error == r.extra["errors"][right][0]
    both = robot.solve({left: np.array([2.0, 1.0, 1.0]), right: far})  # nothing to solve
    assert both.status is Status.UNREACHABLE and both.reason.count("beyond") == 2
    assert both.extra["errors"][left][1] is None  # a position target: no orientation


def test_bad_tips_are_armik_errors(cell):
    with pytest.raises(armik.InputError, match="not both"):
        armik.load("panda", tip="panda_hand", tips=["panda_hand"])
    with pytest.raises(armik.InputError, match=r"name \['panda_hand'\] more than once"):
        armik.load("panda", tips=["panda_hand", "panda_link7", "panda_hand"])
    with pytest.raises(armik.FrameError, match="unknown tips"):
        cell.solve({"hand": np.zeros(3)})
    with pytest.raises(armik.InputError, match="12 values"):
        cell.split([0.0] * 6)


def test_a_held_torso_over_two_hands():
    """TALOS's two hands with its torso held at the values of a configuration that reaches
    both (the task solver over every joint, the torso a box row of its steps): solved with
    the torso exactly there, each hand's pose on the robot's FK."""
    robot = talos()
    rng = np.random.default_rng(21)
    solved = 0
    for _ in range(4):
        q = robot.random_q(rng)
        targets = {tip: robot.fk(q, frame=tip) for tip in robot.tips}
        k1, k2 = (robot.joint_names.index(n) for n in robot.shared)
        held = [
            armik.Hold(robot.shared[0], float(q[k1])),
            armik.Hold(robot.shared[1], float(q[k2])),
        ]
        r = robot.solve(targets, constraints=held, iteration_budget=3000)
        if not r.success:
            assert r.status is Status.NOT_CONVERGED
            continue
        solved += 1
        assert r.q[k1] == q[k1] and r.q[k2] == q[k2]
        for tip in robot.tips:
            err = pin.log6(targets[tip].inverse() * robot.fk(r.q, frame=tip)).vector
            assert np.abs(err).max() <= 2e-6
        assert "held at" in r.reason
    assert solved >= 3


def test_held_joints_of_two_independent_arms_each_on_its_chain(cell):
    """A joint of each IRB 120 held: each chain holds its own (the task solver, a 6-joint
    arm); a joint on neither chain is named."""
    rng = np.random.default_rng(4)
    q = cell.random_q(rng)
    targets = {tip: cell.fk(q, frame=tip) for tip in cell.tips}
    left, right = cell.joint_names.index("l_joint_6"), cell.joint_names.index("r_joint_6")
    hold = {"l_joint_6": float(q[left]), "r_joint_6": float(q[right])}
    r = cell.solve(targets, q0=cell.middle, hold=hold, iteration_budget=3000)
    assert r.success, r.reason
    # within the hold's tolerance: a closed form's exact answer may hold it to the last bits
    assert abs(r.q[left] - q[left]) <= HELD_TOL and abs(r.q[right] - q[right]) <= HELD_TOL
    for tip in cell.tips:
        err = pin.log6(targets[tip].inverse() * cell.fk(r.q, frame=tip)).vector
        assert np.abs(err).max() <= 2e-6
    with pytest.raises(armik.JointError, match="unknown joint 'elbow'.*l_joint_1"):
        cell.solve(targets, hold={"elbow": 0.0})


def test_a_posture_over_two_independent_arms_is_split_by_chain(cell):
    """secondary=[armik.Posture(...)] over the robot's 12 joints: each IRB 120 follows its
    own six (positions: three free joints each), every answer verified; a posture of
    another length is named."""
    rng = np.random.default_rng(5)
    posture = armik.Posture(cell.middle)
    nearer = 0
    for _ in range(6):
        q = cell.random_q(rng)
        targets = {tip: cell.fk(q, frame=tip).translation for tip in cell.tips}
        q0 = cell.random_q(rng)
        plain = cell.solve(targets, q0=q0, iteration_budget=3000)
        pulled = cell.solve(targets, q0=q0, secondary=[posture], iteration_budget=3000)
        assert plain.success and pulled.success, (plain.reason, pulled.reason)
        for tip in cell.tips:
            assert np.linalg.norm(cell.fk(pulled.q, frame=tip).translation - targets[tip]) <= 1e-6
        nearer += np.linalg.norm(pulled.q - cell.middle) < np.linalg.norm(plain.q - cell.middle)
    assert nearer >= 4
    with pytest.raises(armik.OptionError, match="has 6 values, the robot 12 joints"):
        cell.solve(targets, secondary=[armik.Posture(np.zeros(6))])


def test_solve_all_gives_every_combination_of_the_chains_answers(cell):
    """``Arms.solve_all`` says what ``Arm.solve_all`` says: every answer, each verified by
    each tip's FK, best first; a tip out of reach fails the one answer, naming it."""
    q = cell.random_q(np.random.default_rng(8))
    targets = {tip: cell.fk(q, tip) for tip in cell.tips}
    every = cell.solve_all(targets, q0=q)
    assert isinstance(every, armik.Solutions)  # the type Arm.solve_all gives
    left = cell.chain("l_tool0").solve_all(targets["l_tool0"])
    right = cell.chain("r_tool0").solve_all(targets["r_tool0"])
    count = sum(r.success for r in left) * sum(r.success for r in right)
    assert len(every) == count > 1 and all(r.success for r in every)
    for r in every:
        for tip in cell.tips:
            assert cell.fk(r.q, tip).isApprox(targets[tip], 1e-9)
    np.testing.assert_allclose(every[0].q, q, atol=1e-9)  # nearest q0 first
    far = {**targets, "r_tool0": np.array([5.0, 0.0, 0.0])}
    (failed,) = cell.solve_all(far)
    assert not failed.success and "r_tool0" in failed.reason


def test_a_flat_list_of_tasks_naming_their_frames_is_the_mapping(cell):
    """Pink's and mink's spelling, one list of tasks each naming its frame, is the same
    request as the mapping of tips: the same answer, bit for bit."""
    q = cell.random_q(np.random.default_rng(9))
    T_l, T_r = cell.fk(q, "l_tool0"), cell.fk(q, "r_tool0")
    between = T_l.inverse() * T_r
    flat = [armik.Pose(T_l, frame="l_tool0"), armik.Relative("r_tool0", "l_tool0", between)]
    mapped = {"l_tool0": [flat[0]], "r_tool0": [flat[1]]}
    a, b = cell.solve(flat, q0=q), cell.solve(mapped, q0=q)
    assert a.success and np.array_equal(a.q, b.q)
    assert cell.fk(a.q, "r_tool0").isApprox(T_r, 1e-9)
    assert np.array_equal(cell.solve_all(flat, q0=q)[0].q, cell.solve_all(mapped, q0=q)[0].q)
    with pytest.raises(armik.TargetError, match="names no frame"):
        cell.solve([armik.Pose(T_l)])
    with pytest.raises(armik.TargetError, match="no_such_link"):
        cell.solve([armik.Pose(T_l, frame="no_such_link")])


def test_shared_joints_keep_the_settings_of_a_call_without_options_and_read_the_others():
    """The descent's settings of a call without options are read once and kept with the
    robot (in the request of such a call); a call with options reads its own, and the kept
    ones stay as they were."""
    robot = talos()
    q = robot.random_q(np.random.default_rng(5))
    targets = {tip: robot.fk(q, frame=tip) for tip in robot.tips}
    assert robot.solve(targets).success
    kept = robot._plain
    assert kept is not None and kept[0].max_iterations == UNION_ITERATIONS
    assert robot._bare is not None and robot._bare.together is kept
    r = robot.solve(targets, max_iterations=7, iteration_budget=3000)
    assert r.success, r.reason
    assert descent_settings(robot, {"max_iterations": 7})[0].max_iterations == 7
    assert read_request(robot, {"max_iterations": 7}).together[0].max_iterations == 7
    assert robot._plain is kept and descent_settings(robot, {}) is kept
    assert read_request(robot, {}) is robot._bare


def test_an_aim_keyword_over_shared_joints_is_refused_by_name():
    """``cone=``, ``look_at=`` and ``toward=`` are a target's aim, which the descent over
    every joint takes as a tip's task: as keywords there they are refused by name, never
    dropped; the task itself is solved."""
    robot = armik.load("panda", tips=["panda_link4", "panda_hand"])
    q = robot.random_q(np.random.default_rng(4))
    T = robot.fk(q)
    for aim in ({"cone": (0, 0, 1, 0.1)}, {"cone": (0, 0, 1, 0.1), "look_at": (0.5, 0, 0)}):
        with pytest.raises(armik.OptionError, match="not taken where several tips") as info:
            robot.solve(T, **aim)
        assert info.value.option == "cone"
    hand = robot.fk(q, frame="panda_hand")
    tasks = [
        armik.Pose(robot.fk(q, frame="panda_link4"), frame="panda_link4"),
        armik.Position(hand.translation, frame="panda_hand"),
        armik.Axis((0, 0, 1), hand.rotation[:, 2], 0.1, frame="panda_hand"),
    ]
    assert robot.solve(tasks, iteration_budget=3000).success


def test_a_bad_q0_is_named_whole_with_its_joint(cell):
    """A q0 over the robot's 12 joints that is not finite: the message quoted one chain's
    six values and no joint; it names the q0 given and the robot's joint."""
    q = cell.random_q(np.random.default_rng(9))
    T = {tip: cell.fk(q, tip) for tip in cell.tips}
    q0 = np.r_[np.zeros(6), 0, 0, np.nan, 0, 0, 0]
    for call in (cell.solve, cell.solve_all):
        with pytest.raises(armik.OptionError, match="must be finite") as info:
            call(T, q0=q0)
        said = str(info.value)
        assert str(q0.tolist()) in said and "'r_joint_3'" in said and "l_joint" not in said
    many = {tip: [T[tip], T[tip]] for tip in cell.tips}
    with pytest.raises(armik.OptionError, match="not finite at 'r_joint_3'"):
        cell.solve_batch(many, q0=q0)
    with pytest.raises(armik.OptionError, match="row 1 .* not finite at 'l_joint_2'"):
        cell.solve_batch(many, q0=np.vstack([q, np.r_[0, np.inf, np.zeros(10)]]))


def test_a_link_of_either_arm_is_placed_by_the_chain_that_moves_it(cell):
    # each chain's model holds every frame, the other arm locked: the other arm's links
    # are placed by their own chain, as Pinocchio places them on the whole URDF
    model = pin.buildModelFromXML(dual_irb120())
    data = model.createData()
    rng = np.random.default_rng(5)
    for _ in range(3):
        q = cell.random_q(rng)
        whole_placements(model, data, cell.joint_names, q)
        for frame in ("l_link_3", "r_link_3", "r_link_5", "cell"):
            truth = data.oMf[model.getFrameId(frame)]
            assert cell.fk(q, frame).isApprox(truth, 1e-12), frame
        J = cell.jacobian(q, "r_link_5", reference="base")
        assert np.abs(J[:, :6]).max() == 0.0 and np.abs(J[:, 6:]).max() > 0.1


def test_a_task_on_the_other_arms_link_is_that_arms_to_give(cell):
    q = cell.random_q(4)
    at = cell.fk(q, "r_link_3").translation
    elbow = armik.Position(at, frame="r_link_3")
    with pytest.raises(armik.TargetError, match="r_link_3.*give it in the target of 'r_tool0'"):
        cell.solve({"l_tool0": [elbow]})
    with pytest.raises(armik.TargetError, match="give each tip its own tasks"):
        far = armik.Position(cell.fk(q, "r_tool0").translation, frame="r_tool0")
        cell.solve({"l_tool0": [far]})
    # in a flat list it goes to the chain that moves it, and holds there
    left = armik.Pose(cell.fk(q, "l_tool0"), frame="l_tool0")
    r = cell.solve([elbow, left])
    assert r.success, r.reason
    assert np.linalg.norm(cell.fk(r.q, "r_link_3").translation - at) < 1e-6
    # a frame no chain moves (the common base) stays any tip's
    base = armik.Position(cell.fk(q, "cell").translation, frame="cell")
    assert cell.solve({"l_tool0": [base, left]}).success
