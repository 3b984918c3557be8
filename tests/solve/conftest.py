"""The solve tests' fixture: a local Dask cluster of two worker processes (``client``), one
a test process, started by the first test that asks for it and kept to the end of the run:
its workers start Python, import armik and load the compiled solvers once, not once a
module. Tests that count their own child processes (``test_forked.py``) leave its workers
out."""

from __future__ import annotations

import pytest

# Dask's diagnostics, sampled less often on the suite's cluster: the workers' profiler (every
# 10 ms), the event loops' watchdog (20 ms) and the system and memory monitors took 2 s of CPU
# every 30 s the cluster sat idle, 0.4 s so; it sits idle from its first test to the end of
# the run. None of them is what a test checks.
QUIET = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.worker.memory.monitor-interval": "1s",
}


@pytest.fixture(scope="session")
def client():
    distributed = pytest.importorskip("distributed", reason="Dask is the optional cluster extra")
    import dask

    with dask.config.set(QUIET):  # the workers take the configuration they start with
        cluster = distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        )
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()
