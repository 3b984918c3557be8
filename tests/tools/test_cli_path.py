"""``armik path`` (waypoints from a file, followed or planned) and ``--prefer``."""

from __future__ import annotations

import json
import math

import numpy as np
import pinocchio as pin
import pytest

from armik.batch_result import BatchResult
from armik.errors import InputError
from armik.problem.scores import manipulability
from armik.tools.cli import main

from ..conftest import arm


def _spun(n: int = 90) -> tuple[np.ndarray, np.ndarray]:
    a = arm("ur5")
    q = a.middle.copy()
    q[4] = 1.0
    T0 = a.fk(q)
    turn = [pin.exp3(np.array([0.0, 0.0, 3.0 * math.pi * k / (n - 1)])) for k in range(n)]
    return np.array([(T0 * pin.SE3(R, np.zeros(3))).homogeneous for R in turn]), q


def test_path_follows_or_plans_from_a_file(tmp_path, capsys):
    poses, q = _spun()
    np.save(tmp_path / "spin.npy", poses)
    base = ["path", "ur5", str(tmp_path / "spin.npy"), "--max-joint-step", "0.3"]
    q0 = ["--q0", *map(str, q)]
    assert main(base + ["-o", str(tmp_path / "f.npz"), *q0]) == 0
    assert main(base + ["-o", str(tmp_path / "g.npz"), "--plan", "global"]) == 0
    follow, planned = BatchResult.load(tmp_path / "f.npz"), BatchResult.load(tmp_path / "g.npz")
    assert not follow.success.all() and "discontinuous" in set(follow.status)
    assert planned.success.all() and np.abs(np.diff(planned.q, axis=0)).max() <= 0.3
    assert "wrote" in capsys.readouterr().out
    assert main(base + ["-o", str(tmp_path / "x.txt")]) == 2  # a bad input: exit 2


def test_solve_prefers_by_a_score(capsys):
    a = arm("ur5")
    T = a.fk(a.random_q(4))
    xyz = [f"{v:.15g}" for v in T.translation]
    rpy = [f"{v:.15g}" for v in pin.rpy.matrixToRpy(T.rotation)]
    argv = ["solve", "ur5", "--xyz", *xyz, "--rpy", *rpy, "--json", "--prefer", "manipulability"]
    assert main(argv) == 0
    got = json.loads(capsys.readouterr().out)
    best = a.solve(T, prefer="manipulability")  # mirrored branches may tie: the score counts
    assert manipulability(a.jacobian(got["results"][0]["q"])) == pytest.approx(
        -best.extra["score"], abs=1e-9
    )


def test_path_without_q0_starts_free(tmp_path):
    """No --q0: the first waypoint is judged against no start (as solve_path without q0)."""
    a = arm("ur5")
    T = a.fk(a.random_q(3))
    poses = [pin.SE3(T.rotation, T.translation + [0.0, 0.002 * k, 0.0]) for k in range(3)]
    np.save(tmp_path / "line.npy", np.array([P.homogeneous for P in poses]))
    assert main(["path", "ur5", str(tmp_path / "line.npy"), "-o", str(tmp_path / "f.npz")]) == 0
    assert BatchResult.load(tmp_path / "f.npz").success.all()


def test_path_starts_from_the_files_q0_and_q0_flag_takes_its_place(tmp_path, capsys):
    """An .npz's 'q0' is the path's start (it was read and dropped); --q0, as on batch, in
    its place; a 'q0' of several rows is refused naming the file."""
    a = arm("ur5")
    start = a.random_q(3)
    T = a.fk(start)
    line = np.array([pin.SE3(T.rotation, T.translation + [0, 0.002 * k, 0]).homogeneous
                     for k in range(5)])  # fmt: skip
    np.savez(tmp_path / "seam.npz", targets=line, q0=start)
    out = str(tmp_path / "p.npz")
    assert main(["path", "ur5", str(tmp_path / "seam.npz"), "-o", out]) == 0
    assert np.allclose(BatchResult.load(out).q[0], start, atol=1e-6)
    np.savez(tmp_path / "rows.npz", targets=line, q0=np.tile(start, (5, 1)))
    capsys.readouterr()
    assert main(["path", "ur5", str(tmp_path / "rows.npz"), "-o", out]) == 2
    err = capsys.readouterr().err
    assert "rows.npz" in err and "'q0' has shape (5, 6)" in err and "--q0" in err
    flag = ["--q0", *map(repr, start.tolist())]
    assert main(["path", "ur5", str(tmp_path / "rows.npz"), "-o", out, *flag]) == 0
    assert np.allclose(BatchResult.load(out).q[0], start, atol=1e-6)


def test_view_path_starts_where_armik_path_does(tmp_path):
    # `armik view --path` read the waypoints as `armik path` does but dropped the file's
    # 'q0': its followed plan started from the middle of the limits instead
    import argparse

    from armik.tools.cli.view import _solve_paths

    poses, q = _spun(12)
    np.savez(tmp_path / "spin.npz", targets=poses, q0=q)
    args = argparse.Namespace(
        path=str(tmp_path / "spin.npz"), q0=None, plan=["follow"], max_joint_step=0.3,
        solver="auto",
    )  # fmt: skip
    ur5 = arm("ur5")
    shown = _solve_paths(ur5, args, [])["follow"]
    assert main(["path", "ur5", args.path, "--max-joint-step", "0.3", "-o",
                 str(tmp_path / "f.npz")]) == 0  # fmt: skip
    written = BatchResult.load(tmp_path / "f.npz")
    assert np.array_equal(shown.q, written.q) and np.array_equal(shown.success, written.success)
    assert shown.success[0] and np.abs(shown.q[0] - q).max() <= 0.3  # from the file's q0
    np.savez(tmp_path / "bad.npz", targets=poses, q0=np.tile(q, (2, 1)))
    with pytest.raises(InputError, match="a path starts from one configuration"):
        _solve_paths(
            ur5, argparse.Namespace(**{**vars(args), "path": str(tmp_path / "bad.npz")}), []
        )


def test_view_path_without_q0_starts_free_as_armik_path(tmp_path):
    # without a start (no --q0, no 'q0' in the file) `armik view --path` started its followed
    # plan at the middle of the limits, so a first waypoint farther than --max-joint-step
    # from it was 'discontinuous', where `armik path` solves it free
    import argparse

    from armik.tools.cli.view import _solve_paths

    ur5 = arm("ur5")
    q = ur5.random_q(3)
    q[0] = 2.5  # far from the middle in joint 1
    T = ur5.fk(q).homogeneous
    poses = np.repeat(T[None], 4, axis=0)
    poses[:, 1, 3] += np.linspace(0.0, 0.03, 4)
    np.save(tmp_path / "line.npy", poses)
    args = argparse.Namespace(
        path=str(tmp_path / "line.npy"), q0=None, plan=["follow", "global"],
        max_joint_step=0.5, solver="auto",
    )  # fmt: skip
    shown = _solve_paths(ur5, args, [])
    out = str(tmp_path / "f.npz")
    assert main(["path", "ur5", args.path, "--max-joint-step", "0.5", "-o", out]) == 0
    written = BatchResult.load(out)
    assert written.success.all()
    assert np.array_equal(shown["follow"].q, written.q)
    assert shown["follow"].success.all() and shown["global"].success.all()


def test_errors_name_the_flags_that_fix_them(tmp_path, capsys):
    # a refusal's fix was named in Python's words, none of which the command line takes:
    # plan='follow', arm.with_locked({name: value}), hold={joint: value}, iteration_budget
    poses, _ = _spun(4)
    np.save(tmp_path / "w.npy", poses)
    out = str(tmp_path / "o.npz")
    held = ["--hold", "shoulder_pan_joint=0.2"]
    cases = [
        (["path", "ur5", str(tmp_path / "w.npy"), "-o", out, "--plan", "global", *held],
         ["--plan follow", "--lock NAME=VALUE"]),
        (["solve", "ur5", "--xyz", "0.4", "0.2", "0.3", "--swivel", "0.3"],
         ["--hold NAME=VALUE"]),
        (["solve", "ur5", "--xyz", "0.4", "0.2", "0.3", "--iterations", "0"],
         ["--iterations must be >= 1"]),
    ]  # fmt: skip
    for argv, said in cases:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.startswith("armik: error: ") and err.count("\n") == 1
        assert all(words in err for words in said), err
        assert not any(w in err for w in ("plan='", "with_locked", "hold={", "iteration_budget"))


def test_a_refused_option_is_named_by_its_flag(tmp_path, capsys):
    # the refusal began with the library's keyword: max_joint_step, chunk_size, tip_offset,
    poses, _ = _spun(3)
    np.save(tmp_path / "w.npy", poses)
    out = str(tmp_path / "o.npz")
    for argv, said in [
        (["path", "ur5", str(tmp_path / "w.npy"), "-o", out, "--max-joint-step", "-1"],
         "--max-joint-step must be positive"),
        (["batch", "ur5", str(tmp_path / "w.npy"), "-o", out, "--chunk-size", "0"],
         "--chunk-size must be a whole number"),
        (["solve", "ur5", "--xyz", "0.4", "0.2", "0.3", "--tip-offset", "nan", "0", "0"],
         "--tip-offset [nan, 0.0, 0.0] is not finite"),
        # they said timeout, seed and margin
        (["solve", "ur5", "--xyz", "0.4", "0.2", "0.3", "--timeout", "0"],
         "--timeout must be > 0"),
        (["batch", "ur5", str(tmp_path / "w.npy"), "-o", out, "--seed", "-1"],
         "--seed must be >= 0"),
        (["path", "ur5", str(tmp_path / "w.npy"), "-o", out, "--margin", "-1"],
         "--margin must be a distance"),
    ]:  # fmt: skip
        assert main(argv) == 2
        assert capsys.readouterr().err.startswith(f"armik: error: {said}")
