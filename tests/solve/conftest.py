"""The solve tests' fixture: a local Dask cluster of two worker processes (``client``), one
per test process: each worker's start, imports and loads of compiled code are paid once, not
once a module (some 20 s of CPU a run)."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def client():
    distributed = pytest.importorskip("distributed", reason="Dask is the optional cluster extra")
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()
