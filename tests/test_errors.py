"""armik's errors pickle whole: a worker process or a cluster sends them to the caller."""

from __future__ import annotations

import pickle

import pytest

from armik import errors

CASES = [
    errors.ArmikError("plain"),
    errors.InputError("bad input"),
    errors.URDFError("no such file", path="/x.urdf"),
    errors.FrameError("no frame", frame="tool", candidates=["a", "b"]),
    errors.JointError("no joint", joint="j9", candidates=["j1"]),
    errors.TargetError("bad target"),
    errors.OptionError("bad option", option="timeout", value=-1.0),
    errors.CollisionError("bad shape", value=(1, 2)),
    errors.SolverError("no solver", solver="auto", candidates=["dls"]),
    errors.ViewerError("port taken", port=8080),
]


@pytest.mark.parametrize("error", CASES, ids=lambda e: type(e).__name__)
def test_an_error_pickles_with_its_message_and_fields(error):
    back = pickle.loads(pickle.dumps(error))
    assert type(back) is type(error)
    assert str(back) == str(error) and back.args == error.args
    assert vars(back) == vars(error)


@pytest.mark.parametrize(
    ("call", "meant"),
    [
        (lambda a, T: a.solve(T, max_iterations=5, tol_pos=1e-3), "'tol_position'"),
        (lambda a, T: a.solve(T, solver="dsl"), "'dls'"),
        (lambda a, T: a.solve(T, hold={"elbow": 0.1}), "'elbow_joint'"),
        (lambda a, T: a.with_limits({"elbow": (0, 1)}), "'elbow_joint'"),
    ],
)
def test_a_typo_of_an_option_a_solver_or_a_joint_is_answered_with_the_name_meant(call, meant):
    """As a typo of a tip, a frame or a locked joint was: the unknown name, the closest
    names ("did you mean"), then every name."""
    import armik

    a = armik.load("ur5")
    with pytest.raises(armik.ArmikError, match=f"did you mean [^?]*{meant}"):
        call(a, a.fk(a.middle))
