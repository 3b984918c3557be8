"""The solve tests' fixture: a local Dask cluster of two worker processes (``client``), one
a test process, started by the first test that asks for it and kept to the end of the run:
its workers start Python, import armik and load the compiled solvers once, not once a
module. Tests that count their own child processes (``test_forked.py``) leave its workers
out."""

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
