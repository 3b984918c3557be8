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
