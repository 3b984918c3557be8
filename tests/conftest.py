"""Shared fixtures and the one table of tolerances the tests use."""

from __future__ import annotations

import functools
import os
import tempfile
import time
import warnings
from pathlib import Path

from tests.golden.blas_kernels import pin_openblas

BLAS_PINNED = pin_openblas()  # before numpy loads OpenBLAS: the golden answers need it

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402
import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

# The same examples on every run: a property test that drew a new failing example on one
# CI run and not the next would make landing a matter of chance. ARMIK_FUZZ=1 explores.
settings.register_profile("fixed", derandomize=True, database=None)
settings.register_profile("explore")
settings.load_profile("explore" if os.environ.get("ARMIK_FUZZ") == "1" else "fixed")

# The compile notice goes to stderr whenever a kernel is compiled, which in a test run
# depends on the numba cache and the order of the tests: off here, on where it is tested.
os.environ["ARMIK_COMPILE_NOTICE"] = "0"
# A first call compiles, as numba does, instead of running as Python while a helper process
# compiles (kernel.tier): the tests' solves run the compiled code's iterations in their
# budgets; tests/kernel/test_tier.py runs the Python forms.
os.environ["ARMIK_FIRST_CALLS"] = "compile"
# where a notice keeps the compile times it measured: not the user's file
os.environ["ARMIK_COMPILE_TIMES"] = os.path.join(tempfile.mkdtemp(), "compile-seconds.json")

import armik  # noqa: E402
from armik.model.arm_model import ArmModel  # noqa: E402

#: Tolerances, in one place (m, rad).
TOL = {
    "closed_form": 1e-12,  # analytic answers against the textbook formula
    "fk_exact": 1e-9,  # two FK implementations of the same URDF
    "solve": 1e-6,  # the default verification tolerance
    "fd_jacobian": 1e-6,  # finite differences, central, h = 1e-6
}

ALL_ROBOTS = armik.robots()
SPATIAL = ["panda", "ur5", "ur10", "kinova", "xarm7", "z1"]


@functools.cache
def arm(name: str) -> armik.Arm:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return armik.load(name)


def model(name: str) -> ArmModel:
    """The arm model of bundled robot ``name`` (``arm(name).kinematics``): what the
    modules below the facade take."""
    return arm(name).kinematics


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(1234)


@pytest.fixture(scope="session")
def after_parts():
    """What solves add to the compiled functions in a new process after some parts of
    ``armik compile`` (``tests/kernel/after_parts.py``)."""
    from tests.kernel.after_parts import After

    after = After()
    yield after
    after.close()


def frame_position(arm, q, frame: str) -> np.ndarray:
    """The position of ``frame`` at ``q`` in the arm's base frame (Pinocchio's FK)."""
    m = arm.kinematics
    pin.forwardKinematics(arm.model, m.data, m.to_pin(q))
    placed = pin.updateFramePlacement(arm.model, m.data, arm.model.getFrameId(frame))
    return (m.T_base_world * placed).translation.copy()


def write_urdf(tmp_path, text: str, name: str = "robot.urdf"):
    path = tmp_path / name
    path.write_text(text)
    return path


def load_text(tmp_path, text: str, name: str = "robot.urdf", **kw) -> armik.Arm:
    """The arm a URDF's text describes, read from a file as a user's would be."""
    return armik.load(write_urdf(tmp_path, text, name), **kw)


def two_link_urdf(
    *,
    l1: float = 1.0,
    l2: float = 0.8,
    origin: str = "0 0 0",
    rpy: str = "0 0 0",
    limits2: tuple[float, float] = (-3.14159, 3.14159),
    tool: str = "0 0 0",
    axis: str = "0 0 1",
) -> str:
    """A 2R arm whose axes are along ``axis``; the links run along x."""
    lo2, hi2 = limits2
    return f"""<?xml version="1.0"?>
<robot name="two_link">
  <link name="world"/><link name="base"/><link name="l1"/><link name="l2"/><link name="tip"/>
  <joint name="mount" type="fixed"><parent link="world"/><child link="base"/>
    <origin xyz="{origin}" rpy="{rpy}"/></joint>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0"/><axis xyz="{axis}"/>
    <limit lower="-3.14159" upper="3.14159" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="{l1} 0 0"/><axis xyz="{axis}"/>
    <limit lower="{lo2}" upper="{hi2}" effort="1" velocity="1"/></joint>
  <joint name="tool" type="fixed"><parent link="l2"/><child link="tip"/>
    <origin xyz="{tool_xyz(l2, tool)}"/></joint>
</robot>"""


def tool_xyz(l2: float, tool: str) -> str:
    dx, dy, dz = (float(v) for v in tool.split())
    return f"{l2 + dx} {dy} {dz}"


TOUR = "test_a_tour_of_every_option_compiles_each_kernel_once"
# Files the tour writes when it starts (its process id) and when it ends: named once by the
# first process (the xdist controller), inherited by the workers it starts.
TOUR_DONE = os.environ.setdefault(
    "ARMIK_TEST_TOUR_DONE", os.path.join(tempfile.mkdtemp(), "tour-done")
)
TOUR_STARTED = TOUR_DONE + ".pid"
TOUR_START_WAIT = 120.0  # s: a worker waits no longer for the tour to start


# The suite's longest tests (several seconds each on two busy cores, most of them a Python
# of their own, a compile, a browser or mypy), by node id or its start: after the tour, before
# the rest. pytest-xdist's worksteal gives each worker one run of the list and a worker that
# runs out takes the tail of the other's; with these at the head, the last tests on either core
# are short ones, and no long one started late keeps one core alone at the end.
# tests/test_suite_order.py checks that each still names a test.
LONG = (
    "tests/view/test_browser.py::",  # all of it: one module-scoped browser page
    "tests/kernel/test_warmup.py::test_cold_first_solve_loads_the_helpers_step",
    "tests/kernel/test_compile.py::test_compiling_in_two_processes_fills_the_cache_a_new",
    "tests/test_types.py::test_mypy_reports_no_error",
    "tests/test_examples.py::test_examples_run",
    "tests/test_compiled_cache.py::test_a_cache_filled_for_one_copy_of_the_sources_serves",
    "tests/kernel/test_compile.py::test_a_compiling_first_call_says_so_once_and_a_cached",
    "tests/kernel/test_compile.py::test_an_objmode_block_lifted_from_the_cache_is_not",
    "tests/view/test_cli_view.py::",
    "tests/kernel/test_tier.py::test_a_first_call_runs_as_python_and_the_next_loads_the",
)


def pytest_collection_modifyitems(session, config, items) -> None:
    """The tour of every option (tests/kernel/test_compile.py) compiles every kernel into
    numba's cache, one process per core: run first, the rest of the suite loads what it
    compiled instead of compiling it again on one core. The ``LONG`` tests next, in their
    order there; the rest as collected."""
    tour = [item for item in items if item.name == TOUR]
    long = [item for start in LONG for item in items if item.nodeid.startswith(start)]
    first = tour + [item for item in long if item not in tour]
    chosen = set(first)
    items[:] = first + [item for item in items if item not in chosen]


def pytest_runtest_setup(item) -> None:
    """Under pytest-xdist, the workers that did not take the tour wait for it to have
    compiled (it loads and counts what it compiled after): its processes take every core,
    and a test run beside them would compile again the kernels they are compiling
    (measured: docs/compile-time.md)."""
    if not hasattr(item.config, "workerinput") or item.name == TOUR:
        return
    if not any(other.name == TOUR for other in item.session.items):
        return  # the tour is not in this run
    t0 = time.monotonic()
    while not os.path.exists(TOUR_DONE):
        running = _tour_running()
        if running is False or (running is None and time.monotonic() - t0 > TOUR_START_WAIT):
            return  # its worker died, or it never started
        time.sleep(0.2)


def _tour_running() -> bool | None:
    """Whether the process running the tour is alive; None before it started."""
    try:
        pid = int(Path(TOUR_STARTED).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # alive, another user's
        return True
    return True


RESULT_FIELDS = (  # every IKResult field but q, time and extra
    "success",
    "status",
    "reason",
    "solver",
    "iterations",
    "position_error",
    "orientation_error",
    "branch",
    "singular",
    "restarts",
)


def assert_same_result(fast, general) -> None:
    """A prepared solve's result equal to the general path's, field for field, q bit for
    bit and read-only."""
    assert np.array_equal(fast.q, general.q), (fast.q, general.q)
    for name in RESULT_FIELDS:
        assert getattr(fast, name) == getattr(general, name), name
    assert not fast.q.flags.writeable


def decided_by_verdicts(r) -> bool:
    """Whether result ``r`` is a row of the general verdict's ``Verdicts`` (its words
    written by them, now or on first read), not the prepared path's claimed answer."""
    written = r.__dict__.get("_reason")
    return written is None or type(getattr(written[0], "__self__", None)).__name__ == "Verdicts"


def whole_placements(model, data, names, q) -> None:
    """Pinocchio's placements of every frame of the whole URDF's ``model`` into ``data``, at
    the joints ``names`` set to ``q`` (an ``Arms`` configuration) and the rest neutral: what
    a robot of several tips is checked against."""
    full = pin.neutral(model)
    for name, value in zip(names, q):
        full[model.joints[model.getJointId(name)].idx_q] = value
    pin.framesForwardKinematics(model, data, full)


@pytest.fixture
def aimless():
    """dls registered again as "aimless", below every bundled solver: it claims its seed
    converged whatever the target, as a solver that ignores an aim would (the verdict's
    check of the aim on every route, ``tests/verify/test_aim_measured.py``)."""
    import dataclasses

    from armik.solvers import registry
    from armik.solvers.answers import one
    from armik.status import Status

    def run(arm, target, q0, opts, all_solutions):
        return one(np.array(q0, dtype=float), Status.CONVERGED, "claimed")

    spec = dataclasses.replace(
        registry.get("dls"), name="aimless", priority=1, run=run, prepare_pose=None,
        run_batch=None,
    )  # fmt: skip
    registry.register(spec)
    yield spec
    registry.unregister("aimless")
