"""The solve tests' fixture: a local Dask cluster of two worker processes, one per module that
asks for it (``client``). Not one a session: its workers would outlive their modules, and the
tests that count a run's child processes (``test_forked.py``) would count them."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed", reason="Dask is the optional cluster extra")
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()
