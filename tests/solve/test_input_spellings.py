"""Every plain spelling of q0 (a list, a tuple, a strided or read-only row) takes the
prepared path and gives the contiguous array's answer; other spellings still go the
general way with its checks."""

from __future__ import annotations

import numpy as np
import pytest

from armik.errors import OptionError
from armik.solve import stages

from ..conftest import arm


def spellings(q: np.ndarray) -> dict:
    table = np.asfortranarray(np.tile(q, (4, 1)))
    frozen = q.copy()
    frozen.setflags(write=False)
    return {
        "list": [float(v) for v in q],
        "tuple": tuple(float(v) for v in q),
        "strided row": table[1],
        "read-only": frozen,
        "ints": [int(round(v)) for v in q],
    }


@pytest.mark.parametrize("robot", ["ur5", "panda"])
def test_every_plain_seed_takes_the_prepared_path(robot, monkeypatch):
    a = arm(robot)
    rng = np.random.default_rng(9)
    H = a.fk(a.random_q(rng)).homogeneous
    q = np.clip(a.random_q(rng), a.lower + 0.6, a.upper - 0.6)
    for name, q0 in spellings(q).items():
        expected = a.solve(H, q0=np.array(q0, dtype=float))

        def general(*args, name=name, **kwargs):
            raise AssertionError(f"{name}: the general path was taken")

        with monkeypatch.context() as m:
            m.setattr(stages, "general", general)
            got = a.solve(H, q0=q0)
        np.testing.assert_array_equal(got.q, expected.q)
        assert (got.status, got.reason, got.iterations) == (
            expected.status,
            expected.reason,
            expected.iterations,
        )


def test_other_seeds_keep_the_general_checks():
    a = arm("ur5")
    H = a.fk(a.middle).homogeneous
    with pytest.raises(OptionError):
        a.solve(H, q0=[0.0] * 5)
    with pytest.raises(OptionError):
        a.solve(H, q0=[float("nan")] + [0.0] * 5)
    with pytest.warns(Warning, match="clipped"):
        a.solve(H, q0=[100.0] + [0.0] * 5)
