"""A batch sent to a Dask cluster whose jobs cannot travel: named by armik."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import armik
from armik.constraints.base import Check, Constraint
from armik.solve import distributed as armik_distributed
from armik.status import Status

from ..conftest import arm


class HoldsALock(Constraint):
    """A user's constraint that keeps a lock (for its own bookkeeping): it cannot pickle."""

    def __init__(self) -> None:
        self.lock = threading.Lock()

    def check(self, arm, Q):
        return Check(np.ones(len(Q), bool), Status.JOINT_LIMITS, lambda i: "")


@pytest.mark.parametrize("rows", [False, True])
def test_a_constraint_that_cannot_pickle_is_named_before_the_batch_goes(client, rows):
    # compiled chunks and rows alike; Dask's own TypeError said "Could not serialize object
    # of type LLGExpr"
    a = arm("ur5")
    T = a.fk_batch(a.random_q(1, n=6))
    options = {"constraints": [HoldsALock()], **({"prefer": "nearest"} if rows else {})}
    backend = armik_distributed.OnDask(client)
    with pytest.raises(armik.ArmikError, match=r"do not pickle \(TypeError: cannot pickle"):
        a.solve_batch(T, backend=backend, chunk_size=3, progress=False, **options)
    # the same batch here: the constraint holds (every answer passes it)
    assert a.solve_batch(T, workers=1, progress=False, **options).success.all()


@pytest.mark.parametrize("rows", [False, True])
def test_seeds_clipped_into_the_limits_are_said_at_the_callers_line(client, rows):
    a = arm("ur5")
    T = a.fk_batch(a.random_q(1, n=3))
    outside = np.zeros((3, 6))
    outside[2, 2] = 10.0
    options = {"prefer": "nearest"} if rows else {}
    with pytest.warns(armik.ArmikWarning, match="1 target.*target 2") as said:
        armik_distributed.solve_batch(a, T, q0=outside, client=client, progress=False, **options)
    assert said[0].filename == __file__


@pytest.mark.parametrize("rows", [False, True])
def test_a_constraint_of_the_users_script_goes_to_the_workers(client, rows):
    # a class of a script (here a test's own, pickled by value as __main__'s are) whose
    # check reads armik.Status: "cannot pickle '_Package' object", the armik module's class

    class ShoulderDown(Constraint):
        def check(self, arm, Q):
            return Check(Q[:, 1] < 0.0, armik.Status.JOINT_LIMITS, lambda i: "shoulder up")

    a = arm("ur5")
    T = a.fk_batch(a.random_q(4, n=6))
    options = {"constraints": [ShoulderDown()], **({"prefer": "nearest"} if rows else {})}
    backend = armik_distributed.OnDask(client)
    there = a.solve_batch(T, backend=backend, chunk_size=3, progress=False, **options)
    here = a.solve_batch(T, workers=1, progress=False, **options)
    np.testing.assert_array_equal(there.q, here.q)
    assert list(there.status) == list(here.status) and there.success.any()
    assert (there.q[there.success, 1] < 0.0).all()


def test_a_closed_client_given_is_named():
    # Dask raised RuntimeError: IOLoop is closed
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0"
    )
    client = distributed.Client(cluster)
    client.close()
    cluster.close()
    a = arm("ur5")
    T = a.fk_batch(a.random_q(1, n=2))
    with pytest.raises(armik.InputError, match="client given is not connected .status 'closed'"):
        a.solve_batch(T, backend=armik_distributed.OnDask(client), progress=False)
    with pytest.raises(armik.InputError, match="client given is not connected"):
        armik_distributed.solve_batch(a, T, client=client, progress=False)
