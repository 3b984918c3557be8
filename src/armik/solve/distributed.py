"""Batches beyond one machine, on a Dask cluster (``pip install "armik[cluster]"``).

Why Dask: ``dask.distributed`` is a pure-Python wheel that starts in a second on a laptop
(``LocalCluster``) and connects to a running scheduler by its address
(``tcp://host:8786``) with the same code; it has the two things a batch of IK solves needs
and nothing heavier: per-worker state (a ``WorkerPlugin``) and chunked maps whose results
come back in order. Ray would do the same job with a larger install and a slower start.

How it runs: the arm travels once per worker, as its recipe (an ``Arm`` pickles as the
source, base, tip, locked joints, tip offset and limit overrides that rebuild it). A
``WorkerPlugin`` registered under the recipe's digest rebuilds the arm when the worker starts
(and on workers that join later), so a worker reads the URDF and builds the Pinocchio model
once, not once per chunk. The runner is a batch backend (``OnDask``, see
``armik.solve.backends``): the local ``solve_batch`` cuts the batch into its chunk jobs
(``armik.solve.batch.Chunk``), which go out without the arm, run on the workers
(verification included) and come back as ``BatchResult``s, put into their rows as every
backend's are. A batch with no compiled form (task lists, ``prefer=``, ``hold=``) goes out as
chunks of rows (``armik.solve.batch_rows``), each row solved there as ``solve`` solves it.
The answers are those of the local ``solve_batch`` with the same options, read once on the
client.

Every worker must be able to import armik and read the arm's URDF: bundled arms always can;
a URDF path must exist on every worker's machine. A solver the client registered that is
not armik's own travels too (``SolverOnWorker``), registered on each worker as it starts.
"""

from __future__ import annotations

import hashlib
import pickle
from collections.abc import Iterator, Sequence
from functools import lru_cache
from typing import TYPE_CHECKING, cast

import numpy as np

from armik.batch_result import BatchResult
from armik.errors import ArmikError, InputError, OptionError
from armik.model.arm_model import ArmModel, model_of
from armik.solve.batch import Chunk, batch_seeds
from armik.solve.batch import solve_batch as local_solve_batch
from armik.solve.batch_rows import RowsChunk, solve_rows
from armik.solve.progress import ProgressArg
from armik.solve.read import read_batch
from armik.solvers import registry
from armik.solvers.registry import SolverSpec

DEFAULT_CHUNK = 2048  # targets per task: a task should take tens of milliseconds at least


def _import_distributed():
    try:
        import distributed
    except ImportError:  # pragma: no cover - the extra is installed for the tests
        raise ArmikError(
            'the cluster runner needs Dask: pip install "armik[cluster]" '
            '(or pip install "dask[distributed]")'
        ) from None
    return distributed


def _plugin_base():
    try:
        from distributed import WorkerPlugin
    except ImportError:  # pragma: no cover
        return object
    return WorkerPlugin


if TYPE_CHECKING:
    from distributed import WorkerPlugin as _PluginBase
else:
    _PluginBase = _plugin_base()


class ArmOnWorker(_PluginBase):
    """Per-worker state: one arm, rebuilt from its recipe when the worker starts."""

    def __init__(self, blob: bytes, name: str) -> None:
        self.blob = blob
        self.name = name
        self.arm: ArmModel | None = None
        self.builds = 0

    def setup(self, worker=None) -> None:
        self.arm = pickle.loads(self.blob)
        self.builds += 1


class SolverOnWorker(_PluginBase):
    """A solver registered in the client's process that armik does not register itself (a
    family of the user's: CONTRIBUTING's recipe), registered on each worker as it starts
    (and on workers that join later): a chunk looks its solver up by name there."""

    def __init__(self, spec: SolverSpec) -> None:
        self.spec = spec

    def setup(self, worker=None) -> None:
        if self.spec.name not in registry.solvers():
            registry.register(self.spec)


def _own_solvers() -> list[SolverSpec]:
    """The registered solvers that come from outside armik: a chunk names one, and "auto"
    (a row-by-row batch's rows choose on the workers) may choose one."""
    specs = [registry.get(name) for name in registry.solvers()]
    return [s for s in specs if not getattr(s.run, "__module__", "").startswith("armik.")]


def plugin_name(blob: bytes) -> str:
    return "armik-arm-" + hashlib.sha1(blob).hexdigest()[:16]


@lru_cache(maxsize=8)
def _arm_from_blob(blob: bytes) -> ArmModel:  # when a task runs outside a Dask worker
    return pickle.loads(blob)


def _worker_arm(name: str, blob: bytes) -> ArmModel:
    try:
        from distributed import get_worker

        plugin = cast("ArmOnWorker | None", get_worker().plugins.get(name))  # ours, by name
    except (ImportError, ValueError):
        plugin = None
    if plugin is not None and plugin.arm is not None:
        return plugin.arm
    return _arm_from_blob(blob)


def _run_job(name: str, blob: bytes, job: Chunk) -> BatchResult:
    """One task: a batch's chunk (``armik.solve.batch.Chunk``, sent without its arm) on this
    worker's copy of the arm."""
    return job._replace(arm=_worker_arm(name, blob))()


class OnDask:
    """A batch backend (``armik.solve.backends``): the chunks as tasks on the cluster of
    ``client`` (None: the current default client, found when the batch runs), the arm sent
    once per worker (``ArmOnWorker``), the results in the order of the jobs."""

    def __init__(self, client=None) -> None:
        self.client = client

    def __call__(self, jobs: Sequence[Chunk | RowsChunk], workers: int) -> Iterator[BatchResult]:
        client = self.client if self.client is not None else _default_client()
        _connected(client, "the Dask client given")
        if not jobs:
            return
        blob = pickle.dumps(jobs[0].arm)
        name = plugin_name(blob)
        client.register_plugin(ArmOnWorker(blob, name), name=name)
        for own in _own_solvers():  # a user's solver: registered there too
            client.register_plugin(SolverOnWorker(own), name=f"armik-solver-{own.name}")
        # each chunk without its arm (the plugin's copy runs it): a few bytes, not the model
        bare = [job._replace(arm=None) for job in jobs]  # type: ignore[arg-type]
        _travels(bare[0])  # every job holds the batch's request: its options, constraints
        futures = [client.submit(_run_job, name, blob, job, pure=False) for job in bare]
        try:
            for f in futures:
                yield f.result()
                f.release()
        finally:  # an error or Ctrl-C: the tasks not yet run are dropped
            client.cancel([f for f in futures if not f.done()])


def _travels(job: Chunk | RowsChunk) -> None:
    """``ArmikError`` naming what stops ``job`` from pickling as Dask pickles it: the
    request a job holds travels to the workers, a user's constraint with a lock or an open
    file in it too, where Dask's own ``TypeError`` said only "Could not serialize"."""
    import cloudpickle  # type: ignore[import-untyped]  # Dask's own pickler: installed with it

    try:
        cloudpickle.dumps(job)
    except Exception as exc:  # noqa: BLE001 - whatever the pickler raises, named below
        raise ArmikError(
            f"the batch cannot go to the Dask cluster: its jobs do not pickle "
            f"({type(exc).__name__}: {exc}); the targets, options and constraints travel to "
            "the workers, so each must pickle (a constraint holding a lock, an open file or "
            "a connection cannot): drop that from it, or run the batch here (backend= "
            '"processes" or "threads")'
        ) from None


def _default_client():
    distributed = _import_distributed()
    try:
        client = distributed.get_client()
    except ValueError:
        raise InputError(
            "no Dask client: pass client= or address= (e.g. tcp://host:8786 or local:2)"
        ) from None
    return _connected(client, "the default Dask client")  # a failed one stays the default


def _connected(client, which: str):
    """``client``, or ``InputError`` when it is not connected (closed, or its connection
    failed), where Dask raised its own ``RuntimeError: IOLoop is closed``."""
    status = getattr(client, "status", "running")
    if status != "running":
        raise InputError(
            f"{which} is not connected (status {status!r}): pass a running client= "
            "or address= (e.g. tcp://host:8786 or local:2)"
        )
    return client


def connect(address: str):
    """A Dask client for ``address``: a scheduler (``tcp://host:8786``) or ``local`` /
    ``local:N`` for a new cluster of N worker processes on this machine (default: one per
    core). Raises ``InputError`` when the scheduler cannot be reached."""
    distributed = _import_distributed()
    if address == "local" or address.startswith("local:"):
        count = address.partition(":")[2]
        if count and not (count.isdigit() and int(count) > 0):  # local:0 would wait forever
            raise InputError(f"cluster address {address!r}: give local or local:N (N >= 1 workers)")
        cluster = distributed.LocalCluster(
            n_workers=int(count) if count else None,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
        )
        return distributed.Client(cluster)
    try:
        return distributed.Client(address, timeout=10)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(
            f"cannot reach a Dask scheduler at {address!r} ({exc}): start one with "
            "'dask scheduler' and 'dask worker ADDRESS', or pass local:N"
        ) from None


def close(client) -> None:
    """Close a client from ``connect`` and, for ``local``, the cluster it started."""
    cluster = client.cluster
    client.close()
    if cluster is not None:
        cluster.close()


def solve_batch(
    arm: object,
    targets: object,
    q0: object = None,
    solver: str = "auto",
    *,
    client=None,
    address: str | None = None,
    chunk_size: int | None = None,
    progress: ProgressArg = None,
    **options: object,
) -> BatchResult:
    """``armik.solve.batch.solve_batch`` on a Dask cluster; the same arguments and answers.

    ``client``: a ``distributed.Client``; or ``address`` (see ``connect``); or neither, to
    use the current default client. ``chunk_size``: targets per task (2048).
    """
    if hasattr(arm, "tips") and hasattr(arm, "chain"):  # an armik.Arms: its own batch
        raise InputError(
            f"distributed.solve_batch takes one arm, got {arm!r}: a robot of several tips "
            "runs its batch on the cluster as a backend, robot.solve_batch(targets, "
            "backend=distributed.OnDask(client))"
        )
    arm = model_of(arm)
    request = read_batch(arm, targets, q0, solver, options)  # refused here, not on workers
    chunk = DEFAULT_CHUNK if chunk_size is None else chunk_size
    if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1:
        raise OptionError(
            f"chunk_size must be a whole number >= 1, got {chunk_size!r}",
            option="chunk_size",
            value=chunk_size,
        )
    own = connect(address) if client is None and address is not None else None
    on_dask = OnDask(client if own is None else own)
    try:
        if request.rows is not None:  # no compiled form: each row's request, as locally
            seeds = batch_seeds(arm, request.q0, len(request.rows))
            return solve_rows(arm, request, seeds, progress, on_dask, int(chunk))
        return local_solve_batch(arm, request, 1, int(chunk), progress, on_dask)
    finally:
        if own is not None:
            close(own)
