"""A held joint with obstacles or self-collision: every success keeps clear, on the swept
closed form at the value (the Panda's joint 7) and on the locked arm's solve (joint 1)."""

import numpy as np
import pytest

import armik

BALL = [armik.Sphere(0.15, (0.45, 0.0, 0.55))]


@pytest.fixture(scope="module")
def panda():
    return armik.load("panda")


def _cases(panda, joint: int, n: int):
    """Targets whose held solve without obstacles gives an answer the ball overlaps, and
    the value held: what the collision check must refuse."""
    name = panda.joint_names[joint]
    found = []
    for q in panda.random_q(7, n=200):
        hold = {name: float(q[joint])}
        T = panda.fk(q)
        plain = panda.solve(T, hold=hold)
        if plain.success and panda.min_distance(plain.q, BALL, True)[0] < 0:
            found.append((T, hold))
        if len(found) == n:
            break
    assert len(found) == n  # the check has something to refuse
    return found


@pytest.mark.parametrize("joint", [6, 0])
def test_a_held_solve_among_obstacles_keeps_clear(panda, joint):
    solved = 0
    name = panda.joint_names[joint]
    others = [(panda.fk(q), {name: float(q[joint])}) for q in panda.random_q(11, n=6)]
    for T, hold in _cases(panda, joint, 4) + others:
        r = panda.solve(T, hold=hold, obstacles=BALL, self_collision=True)
        if r.success:
            solved += 1
            assert panda.min_distance(r.q, BALL, True)[0] >= 0
            assert r.extra["min_distance"] >= 0
            assert r.q[joint] == next(iter(hold.values()))
        else:
            assert r.status in (armik.Status.COLLISION, armik.Status.JOINT_LIMITS)
    assert solved  # some of them have a clear branch at that value


@pytest.mark.parametrize("joint", [6, 0])
def test_every_held_solution_among_obstacles_is_clear_or_a_collision(panda, joint):
    for T, hold in _cases(panda, joint, 2):
        rows = panda.solve_all(T, hold=hold, obstacles=BALL, self_collision=True)
        assert any(r.status == armik.Status.COLLISION for r in rows)
        for r in rows:
            if r.success:
                assert panda.min_distance(r.q, BALL, True)[0] >= 0


def test_a_held_batch_among_obstacles_keeps_clear(panda):
    cases = _cases(panda, 6, 3)
    value = next(iter(cases[0][1].values()))
    T = np.array([panda.fk(q) for q in panda.random_q(3, n=4)] + [t for t, _ in cases])
    b = panda.solve_batch(
        T, hold={"panda_joint7": value}, obstacles=BALL, self_collision=True, progress=False
    )
    assert np.isfinite(b.min_distance).all()  # every row's collisions checked
    for i in np.flatnonzero(b.success):
        assert panda.min_distance(b.q[i], BALL, True)[0] >= 0
