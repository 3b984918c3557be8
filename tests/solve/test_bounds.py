"""Targets with a region (``bounds``, TRAC-IK's meaning): solved by the numeric solvers,
every success within the bounds by an independent FK (yourdfpy), the limits held; a target
already inside needs no step; the closed forms refuse; bad bounds are named."""

from __future__ import annotations

import math
import zlib

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

import armik
from armik.errors import OptionError, SolverError
from armik.model.catalogue import _erd_robot_dir
from armik.problem import Pose
from armik.tools.cli import main

from ..conftest import arm

SPIN = (0.0, 0.0, 0.0, 0.0, 0.0, math.inf)  # a free spin about the tool's z axis
BOX = (0.005, 0.005, 0.005, 0.05, 0.05, 0.05)  # +- 5 mm, +- 0.05 rad
SO101 = _erd_robot_dir() / "so_arm_description" / "urdf" / "so101.urdf"


def so101() -> armik.Arm:
    if not SO101.exists():
        pytest.skip(f"this example-robot-data has no SO-101 at {SO101}")
    return armik.load(str(SO101))


def spun(a: armik.Arm, q: np.ndarray, rng) -> pin.SE3:
    """q's tip pose turned about its z axis: q stays an admissible answer for SPIN."""
    return a.fk(q) * pin.SE3(pin.exp3(np.array([0.0, 0.0, rng.uniform(-3, 3)])), np.zeros(3))


def boxed(a: armik.Arm, q: np.ndarray, rng) -> pin.SE3:
    """A target whose error twist to q's tip pose lies inside BOX (at 80 % of it)."""
    e = rng.uniform(-0.8, 0.8, 6) * np.array(BOX)
    T = a.fk(q)
    R_t = T.rotation @ pin.exp3(-e[3:])
    return pin.SE3(R_t, T.translation - R_t @ e[:3])


class Independent:
    """yourdfpy's FK of the arm's URDF (the joints off the chain at their neutral value)."""

    def __init__(self, a: armik.Arm) -> None:
        self.arm = a
        self.model = yourdfpy.URDF.load(
            str(a.kinematics.source), build_scene_graph=True, load_meshes=False,
            build_collision_scene_graph=False, load_collision_meshes=False,
        )  # fmt: skip

    def fk(self, q: np.ndarray) -> pin.SE3:
        cfg = {j: 0.0 for j in self.model.actuated_joint_names}
        cfg.update(dict(self.arm.locked))
        cfg.update(dict(zip(self.arm.joint_names, q)))
        self.model.update_cfg(cfg)
        return pin.SE3(self.model.get_transform(frame_to=self.arm.tip, frame_from=self.arm.base))


CASES = [("ur5", spun), ("ur5", boxed), ("panda", spun), ("panda", boxed),
         ("abb_irb120", boxed), ("so101", spun)]  # fmt: skip


@pytest.mark.parametrize(("robot", "make"), CASES)
def test_region_targets_are_solved_and_truly_inside(robot, make):
    a = so101() if robot == "so101" else arm(robot)
    bounds = SPIN if make is spun else BOX
    # a seed of its own per case, the same in every process (``hash`` of a str is not)
    rng = np.random.default_rng(zlib.crc32(f"{robot}/{make.__name__}".encode()))
    independent = Independent(a)
    for _ in range(25):
        T = make(a, a.random_q(rng), rng)
        r = a.solve(T, bounds=bounds, iteration_budget=3000)
        assert r.success, r.reason
        assert a.within_limits(r.q)
        m = Pose(T, bounds=bounds).measure(independent.fk(r.q), 1e-6, 1e-6)
        assert m.within, (m, r.reason)


def test_a_target_inside_its_bounds_needs_no_step():
    a = arm("ur5")
    q = a.random_q(np.random.default_rng(1))
    r = a.solve(boxed(a, q, np.random.default_rng(2)), bounds=BOX, q0=q)
    assert r.success and r.iterations == 0
    np.testing.assert_array_equal(r.q, q)
    assert "inside the region: position error 0 m" in r.reason  # a success says what held
    assert "outside the region" not in r.reason


def test_no_bounds_is_the_exact_target():
    a = arm("panda")
    T = a.fk(a.random_q(np.random.default_rng(3)))
    plain, spelled = a.solve(T), a.solve(T, bounds=None)
    np.testing.assert_array_equal(spelled.q, plain.q)
    assert (spelled.status, spelled.reason) == (plain.status, plain.reason)
    exact = a.solve(T, bounds=(0.0,) * 6)
    assert exact.success and exact.position_error <= 1e-6


def test_the_closed_forms_leave_regions_to_the_numeric_solvers():
    a = arm("ur5")
    T = a.fk(a.random_q(np.random.default_rng(4)))
    assert a.solve(T, bounds=BOX).solver == "dls"
    with pytest.raises(SolverError, match="bounds are for the numeric solvers"):
        a.solve(T, bounds=BOX, solver="three_parallel")
    assert a.solve(T, bounds=BOX, solver="qp").success


def test_an_unreachable_region_fails_with_its_reason():
    a = arm("ur5")
    far = pin.SE3(np.eye(3), np.array([3.0, 0.0, 0.3]))
    r = a.solve(far, bounds=BOX)
    assert not r.success and r.status == "unreachable" and "beyond the arm's reach" in r.reason
    just_out = pin.SE3(np.eye(3), np.array([0.0, 0.0, -0.5]))  # under the base, no box
    r = a.solve(just_out, bounds=(0.001,) * 6, iteration_budget=500)
    assert not r.success and r.status == "not_converged" and "outside the region" in r.reason


def test_batch_and_solve_all_take_bounds(tmp_path):
    a = arm("panda")
    rng = np.random.default_rng(6)
    poses = np.array([spun(a, a.random_q(rng), rng).homogeneous for _ in range(6)])
    opts = {"bounds": SPIN, "iteration_budget": 2000}
    b = a.solve_batch(poses, workers=1, progress=False, **opts)
    for i, H in enumerate(poses):
        r = a.solve(H, **opts)
        assert b.success[i] and r.success
        np.testing.assert_allclose(b.q[i], r.q, atol=1e-12)
        assert "inside the region: position error" in b.reason(i)  # as a solve says
        assert "inside the region: position error" in r.reason
    kept = b[np.arange(len(poses)) % 2 == 0]  # a batch's rows keep their region
    assert kept.region and "inside the region" in kept.reason(0)
    back = armik.BatchResult.load(kept.save(tmp_path / "spun.npz"))
    assert back.region and back.reason(0) == kept.reason(0)
    assert not a.solve_batch(poses[:2], workers=1, progress=False).region
    every = a.solve_all(poses[0], **opts)
    assert every and all(r.success for r in every)
    q = a.random_q(rng)  # a path of spun poses along a short joint-space line
    line = [
        a.fk(q + 0.02 * s) * pin.SE3(pin.exp3(np.array([0, 0, 0.3 * s])), np.zeros(3))
        for s in range(5)
    ]
    path = a.solve_path(np.array([T.homogeneous for T in line]), q0=q, **opts)
    assert path.success.all(), path.reasons


@pytest.mark.parametrize(
    "bounds", [(0.1, -0.1, 0, 0, 0, 0), (0.1, math.nan, 0, 0, 0, 0), (0.1,) * 5, "loose"]
)
def test_bad_bounds_are_named(bounds):
    with pytest.raises(OptionError, match="bounds must be 6 numbers >= 0") as info:
        arm("ur5").solve(np.eye(4), bounds=bounds)
    assert info.value.option == "bounds"


def test_the_cli_takes_bounds(capsys):
    a = arm("ur5")
    T = boxed(a, a.random_q(np.random.default_rng(7)), np.random.default_rng(8))
    xyz = [f"{v:.12g}" for v in T.translation]
    rpy = [f"{v:.12g}" for v in pin.rpy.matrixToRpy(T.rotation)]
    code = main(["solve", "ur5", "--xyz", *xyz, "--rpy", *rpy, "--bounds", *map(str, BOX)])
    assert code == 0, capsys.readouterr()


@pytest.mark.parametrize(
    "spelled",
    [
        {"bounds": (math.inf,) * 6},
        {"bounds": (math.inf,) * 3 + (0.1,) * 3, "weights": (1, 1, 1, 0, 0, 0)},
        {"bounds": (math.inf,) * 3 + (0.1,) * 3, "position_only": True},
    ],
    ids=["inf", "weights", "position_only"],
)
def test_bounds_that_free_every_component_are_refused(spelled):
    """A request whose bounds (with its weights or ``position_only``) free every component
    holds at any configuration: refused by name, where a target 5 m away was called a
    success ("no component measured")."""
    ur5 = armik.load("ur5")
    far = pin.SE3(np.eye(3), np.array([5.0, 0.0, 0.0]))
    with pytest.raises(armik.OptionError, match="every component of the pose free") as e:
        ur5.solve(far, **spelled)
    assert e.value.option == "bounds"
    with pytest.raises(armik.OptionError, match="every component of the pose free"):
        ur5.solve_batch([far, far], **spelled)
    if "bounds" in spelled and len(spelled) == 1:
        with pytest.raises(armik.OptionError, match="every component of the pose free"):
            ur5.solve(armik.Pose(far, bounds=spelled["bounds"]))
