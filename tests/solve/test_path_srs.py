"""Paths of an SRS arm (the iiwa, solved by its swivel closed form) through its singular
configurations: a stretched elbow, a shoulder with axes 1 and 3 in line. The closed form
answers at one swivel angle read from the seed, which such a configuration leaves
undefined or which changes fast near it; a continuous joint path exists (the one the
waypoints were made from), and the paths find one."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from ..conftest import arm

N = 41


def _through_zero(a, seed: int, joint: int) -> np.ndarray:
    """A straight joint path from ``a.random_q(seed)`` with ``joint`` going 0.2 -> -0.2 rad
    (0.4 rad of motion in all), exactly 0 at its middle row."""
    Q = np.repeat(a.random_q(seed)[None], N, 0)
    Q[:, joint] = np.linspace(0.2, -0.2, N)
    return Q


def _on_poses(a, Q, poses) -> None:
    """Each answer on its pose within the default tolerances (1e-6 m, 1e-6 rad), by
    Pinocchio's FK: a descent's answers are as near as that, a closed form's exact."""
    for q, T in zip(Q, poses, strict=True):
        at = a.fk(q)
        assert np.linalg.norm(at.translation - T.translation) <= 1e-6
        assert np.linalg.norm(pin.log3(at.rotation.T @ T.rotation)) <= 1e-6


@pytest.mark.parametrize("seed", range(6))
def test_a_followed_path_passes_a_stretched_elbow(seed):
    """Joint 4 through 0 (the elbow stretched at the middle waypoint): every waypoint
    reached without a jump (the waypoint after the stretched one was reachable only by a
    jump of 1.8-3.1 rad on five of these six paths)."""
    a = arm("kuka_iiwa14")
    Q = _through_zero(a, seed, 3)
    poses = [a.fk(q) for q in Q]
    p = a.solve_path(poses, Q[0])
    assert p.solver == "srs"
    assert p.success.all(), [p.reason(i) for i in np.flatnonzero(~p.success)]
    assert np.abs(np.diff(p.q, axis=0)).max() <= 0.1
    _on_poses(a, p.q, poses)


@pytest.mark.parametrize("joint", [1, 2, 3])
@pytest.mark.parametrize("seed", range(6))
def test_a_global_plan_moves_little_more_than_the_path_the_poses_came_from(seed, joint):
    """Joints 2, 3 and 4 each through 0: the global plan reaches every waypoint and moves
    the joints at most twice the 0.4 rad of the path the poses came from (it broke on 5 of
    these 18 paths, and moved 1.3-9.2 rad on 10 others, the swivel angle held where the
    shoulder passes its singularity)."""
    a = arm("kuka_iiwa14")
    Q = _through_zero(a, seed, joint)
    poses = [a.fk(q) for q in Q]
    p = a.solve_path(poses, Q[0], plan="global")
    assert p.success.all(), [p.reason(i) for i in np.flatnonzero(~p.success)]
    assert np.abs(np.diff(p.q, axis=0)).sum() <= 0.8
    _on_poses(a, p.q, poses)


# a configuration and a turn per waypoint (rad) of two tool spins the iiwa follows by descent
# where its swivel closed form's answers jump
SPINS = [
    (
        [0.2089044173768, 1.4694083548656, -1.8123982643247, -0.6435560975503, -2.0488724635962,
         0.1146459023645, -2.1414190503806],
        0.10876864316147,
    ),
    (
        [1.7974704874875, -1.1962951074836, -2.2737128309347, -0.9118483472045, -0.0846125270975,
         -0.8896145864785, -1.2850102041161],
        0.11026931990161,
    ),
]  # fmt: skip


@pytest.mark.parametrize("start, turn", SPINS)
def test_a_followed_descent_is_judged_by_descents_halfway(start, turn):
    """Where a waypoint is reached by a descent from the answer before (the closed form's
    answers there jump), each step is judged halfway by descents too: judged by the
    closed form alone, whose answers at the middle's swivel angle lie off the step, 10 and
    21 of these waypoints were said to hide a jump."""
    a = arm("kuka_iiwa14")
    T0 = a.fk(np.array(start))
    poses = [
        T0 * pin.SE3(pin.exp3(np.array([0.0, 0.0, turn * i])), np.zeros(3)) for i in range(100)
    ]
    p = a.solve_path(poses, np.array(start), max_joint_step=0.3)
    assert p.success.sum() >= 98
    assert not [i for i in range(100) if "hides a jump" in p.reason(i)]
    ok = np.flatnonzero(p.success)
    _on_poses(a, p.q[ok], [poses[i] for i in ok])


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_a_path_at_a_fixed_swivel_angle_keeps_it(plan):
    """``swivel=`` on a path: every answer at that swivel angle (no descent beside the
    closed form, which would not keep it; one raised that ``swivel=`` is not dls's)."""
    from armik.solvers.closed_form import srs

    a = arm("kuka_iiwa14")
    q0 = a.random_q(1)
    psi = srs.swivel_of(a.kinematics, q0)
    T = a.fk(q0)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(3)]
    p = a.solve_path(line, q0, swivel=psi, plan=plan)
    assert p.success.all(), [p.reason(i) for i in range(3)]
    for q in p.q:
        assert abs(srs.swivel_of(a.kinematics, q) - psi) < 1e-9
    _on_poses(a, p.q, line)


@pytest.mark.parametrize("plan", ["follow", "global"])
def test_a_path_at_a_swivel_angle_away_from_q0_answers_at_it(plan):
    """The first waypoint at another swivel angle than q0's is a jump (said so), re-solved
    near q0 at that angle: every answer, a jump's too, at the swivel asked for (the
    re-solve raised "swivel= is solved by the 'srs' solver, not 'dls'")."""
    from armik.solvers.closed_form import srs

    a = arm("kuka_iiwa14")
    q0 = a.middle + 0.2
    T = a.fk(q0)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(3)]
    p = a.solve_path(line, q0, swivel=0.3, plan=plan)
    assert p.success[1] and not p.success[0]
    assert "jump" in p.reason(0)
    for q in p.q:
        assert abs(srs.swivel_of(a.kinematics, q) - 0.3) < 1e-9
    _on_poses(a, p.q, line)
