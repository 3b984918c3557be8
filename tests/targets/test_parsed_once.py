"""A user's target is parsed once per solve, on every route: the stages below the door
take the parsed ``Target`` (``armik.targets.pose.parsed``), never the raw value again.

The parsers are counted by the targets each call reads (``parse_target`` one,
``parse_by_tip`` one per tip, ``parse_targets`` one per row; a ``TargetBatch`` read
already, none), wherever armik calls them; a task's pose was read when the task was
built."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import armik
import armik.arms  # noqa: F401  (imported before the fixture patches its parsers)
import armik.targets.batch as batch_module
import armik.targets.pose as pose_module
from tests.conftest import arm as bundled


@pytest.fixture
def reads(monkeypatch):
    """How many targets the parsers read from every armik module that calls them, as
    ``reads()`` (the count since the last call, which starts it again)."""
    seen: list[int] = []
    originals = {
        "parse_target": (pose_module.parse_target, lambda value: 1),
        "parse_by_tip": (pose_module.parse_by_tip, len),
        "parse_targets": (
            batch_module.parse_targets,
            lambda value: 0 if isinstance(value, batch_module.TargetBatch) else len(value),
        ),
    }

    def counting(original, count):
        def parser(value, *args, **kwargs):
            seen.append(count(value))
            return original(value, *args, **kwargs)

        return parser

    wrapped = {name: counting(*given) for name, given in originals.items()}
    for module in list(sys.modules.values()):
        name = getattr(module, "__name__", "") or ""
        if not name.startswith("armik"):
            continue
        for parser, (original, _) in originals.items():
            # the batch parser's own reading of each row is its rows' count
            inside = name == "armik.targets.batch" and parser == "parse_target"
            if getattr(module, parser, None) is original and not inside:
                monkeypatch.setattr(module, parser, wrapped[parser])

    def count() -> int:
        found = sum(seen)
        seen.clear()
        return found

    return count


def _pose(name: str):
    a = bundled(name)
    return a, a.fk(a.middle + 0.1)


@pytest.mark.parametrize(
    "name, options",
    [
        ("ur5", {}),
        ("ur5", {"bounds": (0.01,) * 3 + (0.1,) * 3}),
        ("panda", {"obstacles": [armik.Sphere(0.05, (2.0, 2.0, 2.0))]}),
        ("panda", {"prefer": "manipulability", "iteration_budget": 300}),
        ("panda", {"hold": {"panda_joint7": 0.3}}),
        ("panda", {"hold": {"panda_joint7": 0.3, "panda_joint1": 0.1}}),  # the task solver
        ("panda", {"weights": (1, 1, 1, 1, 1, 0)}),
    ],
    ids=str,
)
def test_a_solve_parses_its_target_once(reads, name, options):
    a, T = _pose(name)
    reads()
    for target in (T, (T.translation, pin.Quaternion(T.rotation).coeffs())):
        a.solve(target, **options)
        assert reads() <= 1


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_solve_all_parses_once(reads, name):
    a, T = _pose(name)
    reads()
    a.solve_all(T)
    assert reads() <= 1


@pytest.mark.parametrize("name", ["ur5", "panda"])  # the Panda's global plan: swept rungs
def test_a_path_parses_each_waypoint_once_at_most(reads, name):
    a, T = _pose(name)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.01 * k, 0]) for k in range(3)]
    reads()
    for plan in ("follow", "global"):
        a.solve_path(line, a.middle + 0.1, plan=plan)
        assert reads() <= len(line), plan


def test_a_batch_parses_each_target_once_at_most(reads):
    a = bundled("panda")
    T = a.fk_batch(a.random_q(0, n=4))
    reads()
    for given in (T, list(T)):
        a.solve_batch(given, workers=1, progress=False)
        assert reads() <= len(T)


def test_a_pose_read_already_is_not_read_again(reads):
    """A ``Pose`` task read its pose when it was built, and a ``Target`` is read: a solve
    reads neither again, where the compiled solver finds no answer (its verdict read the
    pose again from the 4x4 it was handed) nor where the task solver holds joints (its
    start read the task's pose again). A pose as given is read once."""
    ur5 = bundled("ur5")
    T = ur5.fk(ur5.middle + 0.1)
    inside = pin.SE3(T.rotation, 0.05 * T.translation)  # within reach, no answer
    task, target = armik.Pose(inside), armik.parse_target(inside)
    held = {ur5.joint_names[0]: 0.1, ur5.joint_names[1]: 0.2}  # two: the task solver's
    reads()
    for given in (task, [task], target):
        assert not ur5.solve(given).success
        assert reads() == 0
        assert not ur5.solve(given, hold=held, iteration_budget=300).success
        assert reads() == 0
    ur5.solve(inside)
    assert reads() == 1


def _talos() -> armik.Arms:
    """TALOS's two hands, whose chains share the torso's two joints."""
    robots = Path(armik.load("panda").source).parents[2]
    urdf = robots / "talos_data" / "robots" / "talos_reduced.urdf"
    return armik.load(urdf, tips=["gripper_left_base_link", "gripper_right_base_link"])


@pytest.mark.parametrize("robot", ["panda, two tips", "talos, shared torso"])
def test_several_tips_parse_their_targets_once(reads, robot):
    """The request's target, one pose per tip, is parsed in one call (the chains apart, and
    over the shared torso: one task per tip on the union), in each form a tip's pose takes."""
    if robot.startswith("panda"):
        arms = armik.load("panda", tips=["panda_hand", "panda_link5"])
    else:
        arms = _talos()
    q = arms.middle + 0.1
    placed = {tip: arms.fk(q, tip) for tip in arms.tips}
    spelled = {t: (T.translation, pin.Quaternion(T.rotation).coeffs()) for t, T in placed.items()}
    reads()
    for targets in (placed, spelled):
        r = arms.solve(targets, iteration_budget=3000)
        assert r.success, r.reason
        assert reads() == len(arms.tips)


def test_a_tips_bad_target_is_named_by_its_tip():
    arms = armik.load("panda", tips=["panda_hand", "panda_link5"])
    with pytest.raises(armik.TargetError, match="tip 'panda_link5'.*NaN"):
        arms.solve({"panda_hand": arms.fk(arms.middle, "panda_hand"), "panda_link5": [np.nan] * 3})
