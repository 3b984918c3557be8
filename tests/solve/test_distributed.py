"""The Dask runner on a local cluster of two worker processes: the local answers."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import armik
from armik import BatchResult
from armik.errors import InputError
from armik.solve import distributed as armik_distributed
from armik.tools.cli import main

from ..conftest import arm, model


def _targets(name: str, n: int) -> np.ndarray:
    a = arm(name)
    rng = np.random.default_rng(21)
    T = np.array([a.fk(a.random_q(rng)).homogeneous for _ in range(n)])
    T[3, :3, 3] = (4.0, 0.0, 0.0)  # out of reach
    return T


@pytest.mark.parametrize("name", ["panda", "kinova"])
def test_cluster_gives_the_local_answers(client, name):
    a = arm(name)
    T = _targets(name, 24)
    q0 = np.array([a.random_q(k) for k in range(len(T))])
    options = dict(timeout=1.0, max_restarts=50, seed=2)
    local = a.solve_batch(T, q0=q0, workers=1, **options)
    remote = armik_distributed.solve_batch(a, T, q0=q0, client=client, chunk_size=5, **options)
    assert isinstance(remote, BatchResult) and len(remote) == len(T)
    for field in ("q", "success", "status_code", "position_error", "iterations", "restarts"):
        np.testing.assert_array_equal(getattr(remote, field), getattr(local, field), err_msg=field)
    assert remote.reasons == local.reasons and remote.status[3] == "unreachable"
    assert remote.solver == local.solver and remote.arm == name


def test_the_workers_run_the_armik_this_process_runs(client):
    # a worker importing another copy (a source tree put first on sys.path) would find
    # none of this one's compiled code and compile it all again
    def where() -> str:
        import armik as here

        return here.__file__

    assert set(client.run(where).values()) == {armik.__file__}


def test_each_worker_builds_the_arm_once(client):
    a = arm("ur5")
    T = _targets("ur5", 10)
    for _ in range(2):
        armik_distributed.solve_batch(a, T, client=client, chunk_size=2)
    name = armik_distributed.plugin_name(pickle.dumps(a.kinematics))
    builds = client.run(lambda dask_worker: dask_worker.plugins[name].builds)
    assert sorted(builds.values()) == [1, 1]


def test_cli_cluster_address(client, tmp_path, capsys):
    T = _targets("ur5", 8)
    np.save(tmp_path / "t.npy", T)
    out = tmp_path / "o.npz"
    address = client.scheduler.address
    argv = ["batch", "ur5", str(tmp_path / "t.npy"), "-o", str(out), "--cluster", address]
    assert main(argv + ["--chunk-size", "3"]) == 0
    assert "7/8 solved" in capsys.readouterr().out
    local = armik.Arm(model("ur5")).solve_batch(T, workers=1)
    np.testing.assert_array_equal(BatchResult.load(out).q, local.q)


@pytest.mark.parametrize("address", ["local:two", "local:0", "local:-1"])
def test_bad_local_address(address):
    with pytest.raises(InputError, match="local:N"):  # local:0: no worker, a wait forever
        armik_distributed.connect(address)


def test_a_constraint_of_ones_own_holds_on_the_cluster(client):
    """A user's constraint travels to the workers with the options, and their verdicts
    run its check: no success violates it, as on one core."""
    from tests.constraints.test_own_constraint import ELBOW, ElbowUp, _targets

    a = arm("panda")
    poses, qs = _targets(6)
    T = np.array([p.homogeneous for p in poses])
    options = dict(constraints=[ElbowUp()], iteration_budget=400)
    remote = armik_distributed.solve_batch(a, T, q0=np.array(qs), client=client, **options)
    local = a.solve_batch(T, q0=np.array(qs), workers=1, **options)
    assert not (remote.success & (remote.q[:, 3] <= ELBOW)).any()
    assert "elbow below -1" in remote.reasons.values()
    np.testing.assert_array_equal(remote.success, local.success)


def test_the_cluster_is_a_batch_backend(client):
    """``OnDask`` is a backend like any other: ``arm.solve_batch(..., backend=OnDask(client))``
    gives the local answers, collision-checked ones with their pairs."""
    a = arm("ur5")
    T = _targets("ur5", 9)
    options = dict(obstacles=[armik.Sphere(0.05, (0.0, 0.0, 2.0))], self_collision=True)
    local = a.solve_batch(T, workers=1, **options)
    remote = a.solve_batch(T, backend=armik_distributed.OnDask(client), chunk_size=4, **options)
    np.testing.assert_array_equal(remote.q, local.q)
    assert remote.reasons == local.reasons and remote.pair_names == local.pair_names
    assert remote.pair_names  # the checker's pairs, named


def test_a_default_client_that_never_connected_is_refused_by_name(monkeypatch):
    """A client whose connection failed (``Client("nonsense")``) stays Dask's default: a
    backend without a client finds it, and refuses it by name rather than failing in
    Dask's own words when the batch is sent."""
    distributed = pytest.importorskip("distributed")

    class Failed:
        status = "connecting"

        def register_plugin(self, *args, **kwargs):
            raise ValueError("missing port number in address 'nonsense'")

    monkeypatch.setattr(distributed, "get_client", lambda: Failed())
    a = arm("ur5")
    with pytest.raises(InputError, match="default Dask client is not connected"):
        a.solve_batch(_targets("ur5", 4), backend=armik_distributed.OnDask())


def test_a_robot_of_several_tips_is_sent_as_a_backend():
    """``distributed.solve_batch`` takes one arm: a robot of several tips is refused
    naming the way its own batch runs on the cluster (``backend=OnDask(client)``)."""
    from ..test_arms import dual_irb120

    robot = armik.load(dual_irb120(), tips=["l_tool0", "r_tool0"])
    targets = {tip: np.array([robot.fk(robot.middle, tip).homogeneous]) for tip in robot.tips}
    with pytest.raises(InputError, match=r"backend=distributed\.OnDask\(client\)"):
        armik_distributed.solve_batch(robot, targets, address="local:1")
