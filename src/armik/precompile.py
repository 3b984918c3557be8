"""``armik.compile``: build every compiled part into numba's on-disk cache ahead of time.

Each part is compiled at its first call otherwise (a few seconds each, announced on
stderr); after ``armik compile`` a new process loads them from the cache instead. A part is
compiled by calling it the way users do, on bundled arms, with the variants options select
(weights, position targets, solve_all, batches, paths), so what is cached is exactly what
those calls load.

numba compiles on one core, so the parts are shared out to one process per core: on two
cores in two fixed lists that share little compiled code (``_HALVES``), on more longest
first, the numeric solvers' parts, which share most of their compiled code, to one process
one after another (``_TOGETHER``). The calling process then runs every part itself
(``load``): from the cache that takes a fraction of a second. Processes saving the same
function at once keep each other's entries (``compiled_cache.Entries``).
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from typing import Any

import numpy as np
from pinocchio import SE3

from armik.arm import Arm
from armik.constraints.collision import checker
from armik.constraints.limits import JointLimits
from armik.constraints.shapes import Box, HalfSpace, Sphere
from armik.errors import OptionError, listing
from armik.kernel.tier import compiling
from armik.loading import load, load_string
from armik.model.random_arms import random_urdf
from armik.problem.tasks import Axis, Position
from armik.solve.progress import make_progress

# a few iterations suffice to compile
_BUDGET: dict[str, Any] = {"iteration_budget": 200, "seed": 0}


def _pose(arm: Arm, seed: int):
    return arm.fk(arm.random_q(np.random.default_rng(seed)))


def _numeric(solver: str) -> Callable[[], None]:
    def run() -> None:
        # 6 and 7 joints, continuous joints; the SCARA's slides and parallel axes: the
        # batch FK its rails and heights place restarts with, a target beyond its heights
        # measured where it is refused
        for name in ("ur5", "panda", "kinova", "scara"):
            arm = load(name)
            T = _pose(arm, 1)
            arm.solve(T.translation * 10, solver=solver, **_BUDGET)
            arm.solve(T, solver=solver, **_BUDGET)
            arm.solve(T.translation, solver=solver, **_BUDGET)
            arm.solve(T, solver=solver, weights=(1, 1, 1, 1, 1, 0), **_BUDGET)
            arm.solve(T, solver=solver, position_only=True, **_BUDGET)
            # a region: the pose entry with the region's code (a plain target's has none)
            arm.solve(T, solver=solver, bounds=(0.01,) * 3 + (0.1,) * 3, **_BUDGET)
            arm.solve_all(T, solver=solver, max_solutions=2, **_BUDGET)
        # options that are data, not code: none may compile anything new
        _from_a_result(arm, T, solver, **_BUDGET)
        arm.solve(T, solver=solver, timeout=0.01, max_restarts=0, seed=1)
        arm.solve(T, solver=solver, tol_position=1e-4, tol_orientation=1e-3, **_BUDGET)
        arm.solve(T, solver=solver, nullspace_gain=0.0, max_iterations=20, **_BUDGET)

    return run


def _clik() -> None:
    for name in ("ur5", "kinova"):  # continuous joints too
        arm = load(name)
        arm.solve(_pose(arm, 1), solver="clik", max_iterations=5)


def _continuous() -> None:
    """Joint values to Pinocchio's on an arm with continuous joints (the Kinova): every
    call on such an arm starts there."""
    arm = load("kinova")
    arm.fk(arm.middle.copy())


def _random_arm(kind: str):
    """A random arm of ``kind`` (``armik.model.random_arms``), for families no bundled arm
    belongs to."""
    return load_string(random_urdf(kind, np.random.default_rng(0)), base="world", tip="tool")


def _closed_form(
    robot: str, solver: str, batch: bool = False, locked: dict | None = None
) -> Callable[[], None]:
    """``batch``: a ``solve_batch`` too (the family's compiled ``kernel_many``, which the
    ``batch`` part compiles for the UR5's family); ``locked``: joints of the
    bundled arm locked (``load(robot, locked=...)``)."""

    def run() -> None:
        _continuous()
        arm = _random_arm(robot[7:]) if robot.startswith("random:") else load(robot, locked=locked)
        T = _pose(arm, 2)
        target = T.translation[:2] if solver == "planar2r" else T
        arm.solve(target, solver=solver)
        arm.solve(target, q0=arm.middle + 0.1, solver=solver)
        [r.branch for r in arm.solve_all(target, solver=solver)]  # results read: made whole
        # the general path, where the prepared one steps aside (a constraint, obstacles)
        arm.solve(target, solver=solver, constraints=[JointLimits()])
        [r.branch for r in arm.solve_all(target, solver=solver, constraints=[JointLimits()])]
        # a target out of reach: its verdict measured by the FK check
        far = 10 * target if solver == "planar2r" else SE3(T.rotation, 10 * T.translation)
        arm.solve(far, solver=solver)
        [r.status for r in arm.solve_all(far, solver=solver)]
        if solver != "planar2r":
            _from_a_result(arm, T, solver)
        if batch:
            poses = np.array([_pose(arm, s).homogeneous for s in range(2)])
            arm.solve_batch(poses, solver=solver, workers=1, progress=False)

    return run


def _in_turn(*parts: Callable[[], None]) -> Callable[[], None]:
    def run() -> None:
        for part in parts:
            part()

    return run


def _from_a_result(arm: Arm, T, solver: str, **options) -> None:
    """Solves seeded from an earlier answer (read-only arrays, as a path passes them) and
    a read-only 4x4 target: the same compiled code as any other seed and target."""
    r = arm.solve(T, solver=solver, **options)
    H = T.homogeneous
    H.flags.writeable = False
    arm.solve(H, q0=r.q, solver=solver, **options)
    arm.solve_all(H, q0=r.q, solver=solver, **options)


def _hold() -> None:
    """``hold=`` on the Panda: joint 7 (the swept closed form at one value) and joint 1
    (the general 6R search on the locked arm), at two values each: a held value is data."""
    arm = load("panda")
    T = _pose(arm, 4)
    q0 = arm.middle.copy()
    q0.flags.writeable = False  # a read-only seed, as a result's q is
    for joint in ("panda_joint7", "panda_joint1"):
        for value in (0.1, 0.2):
            arm.solve(T, hold={joint: value})
            arm.solve_all(T, hold={joint: value})
        arm.solve(T, q0=q0, hold={joint: None})
        arm.solve_all(T, q0=q0, hold={joint: None})


def _swivel(robot: str) -> None:
    """``swivel=`` on an SRS arm: every branch at one swivel angle (``armik.solve.parameter``)."""
    arm = load(robot)
    T = _pose(arm, 4)
    arm.solve_all(T, swivel=0.3)
    arm.solve(T, swivel=-0.2)


def _batch() -> None:
    for robot, solver in (("ur5", "dls"), ("ur5", "qp"), ("ur5", "three_parallel")):
        arm = load(robot)
        poses = np.array([_pose(arm, s).homogeneous for s in range(4)])
        options = _numeric_only(solver)
        arm.solve_batch(poses, solver=solver, workers=1, progress=False, **options)
        q0 = arm.solve_batch(poses, solver=solver, workers=1, progress=False, **options).q
        q0.flags.writeable = False
        arm.solve_batch(poses, q0=q0, solver=solver, workers=1, progress=False, **options)


def _numeric_only(solver: str) -> dict:
    return _BUDGET if solver in ("dls", "qp") else {}


def _path() -> None:
    arm = load("ur5")
    q = arm.random_q(np.random.default_rng(3))
    poses = [arm.fk(q + 0.01 * k) for k in range(3)]
    arm.solve_path(poses, q, **_BUDGET)
    arm.solve_path(poses, q, plan="global", **_BUDGET)  # the plan's ladder
    # the other bundled families' rungs: every branch of each waypoint in one call
    for robot in ("planar_2link", "abb_irb120"):
        arm = load(robot)
        q = arm.random_q(np.random.default_rng(3))
        poses = [arm.fk(q + 0.01 * k) for k in range(3)]
        line = [T.translation[:2] for T in poses] if robot == "planar_2link" else poses
        arm.solve_path(line, q, plan="global")


def _tasks_part() -> None:
    """Tasks on two frames of the Panda (the tip's position and axis, the elbow's position):
    the task solver's compiled descent; and on the tip alone (a position, with an axis):
    the numeric solver's entry such a list lowers to, as ``dls``' part builds it."""
    _continuous()
    arm = load("panda")
    T = arm.fk(arm.middle)
    tasks = [Position(T.translation), Axis((0, 0, 1), T.rotation[:, 2], 0.05)]
    arm.solve(tasks[:1])
    arm.solve(tasks)
    arm.solve([*tasks, Position((0.0, 0.0, 0.5), bounds=(0.2,) * 3, frame="panda_link4")])


def _fk_batch() -> None:
    _continuous()
    arm = load("ur5")
    arm.fk_batch(arm.random_q(0, n=2))


def _collisions() -> None:
    arm = load("ur5")
    scene = [HalfSpace((0, 0, 1), 0.0), Box((0.2, 0.2, 0.2), (0.5, 0.0, 0.3))]
    arm.min_distance(arm.middle, scene, self_collision=True)
    # a batch's answers checked at once (``Checker.distances``)
    checker(arm.kinematics, tuple(scene), True).distances(arm.random_q(0, n=2))


def _servo() -> None:
    _continuous()
    arm = load("ur5")
    q = np.array([0.3, -1.2, 1.4, -1.5, -1.5, 0.2])
    T = arm.fk(q)
    near = Sphere(0.04, tuple(T.translation + np.array([0.0, 0.08, 0.0])))  # rows: the step's
    servo = arm.servo(q, obstacles=[near])
    servo.step(T)  # a pose: its table written by the tick; a position: by the parser
    servo.step(T.translation)
    shared = load("panda", tips=["panda_link4", "panda_hand"])  # one step over the union
    q = shared.middle
    shared.servo(q).step({tip: shared.fk(q, tip) for tip in shared.tips})


PARTS: dict[str, Callable[[], None]] = {
    "dls": _numeric("dls"),
    "qp": _numeric("qp"),
    "clik": _clik,
    "planar2r": _closed_form("planar_2link", "planar2r"),
    "spherical": _closed_form("abb_irb120", "spherical", batch=True),
    "three_parallel": _closed_form("ur5", "three_parallel"),
    "spherical_general": _closed_form("random:spherical", "spherical_general", batch=True),
    "three_parallel_general": _closed_form(
        "random:three_parallel_free", "three_parallel_general", batch=True
    ),
    "spherical_shoulder": _closed_form(
        "panda", "spherical_shoulder", batch=True, locked={"panda_joint7": 0.3}
    ),
    # one part: both families share the search's compiled zero finder (search_zeros)
    "search_1d": _in_turn(
        _closed_form("random:two_parallel", "two_parallel", batch=True),
        _closed_form("random:two_intersecting", "two_intersecting", batch=True),
    ),
    "swept": _closed_form("panda", "swept"),
    "srs": _in_turn(_closed_form("kuka_iiwa14", "srs", batch=True), lambda: _swivel("kuka_iiwa14")),
    "general_6r": _closed_form("ur5", "general_6r"),
    "elimination_6r": _closed_form("random:two_parallel", "elimination_6r"),
    "hold": _hold,
    "batch": _batch,
    "path": _path,
    "fk_batch": _fk_batch,
    "tasks": _tasks_part,
    "collisions": _collisions,
    "servo": _servo,
}


# s, roughly, from an empty cache on one core (measured 2026-12-02, `armik compile --all`;
# search_1d, tasks and the general 6R families again on 2026-12-06, after LLVM's loop-idiom
# pass went off for armik's code (``kernel.loop_idiom``), scaled to dls's 45 s): the order
# tasks go to the processes in (longest first, so that the processes finish together); a
# new part defaults to 10
_COST = {
    "dls": 45,
    "qp": 45,
    "search_1d": 50,
    # the servo's tick (measured 2026-12-06: 38-41 s on a loaded machine; its one entry for
    # a pose and a table then took 17 % less CPU, 39 s against 47)
    "servo": 29,
    "tasks": 30,
    "batch": 16,
    "spherical_general": 13,
    "spherical": 13,
    "general_6r": 11,
    "three_parallel_general": 9,
    "swept": 8,
}
# Parts one process compiles one after another: they share most of their compiled code,
# which the later ones then find in memory (qp after dls compiles its own step only).
_TOGETHER = (("dls", "qp", "batch", "hold", "path"),)
# On two processes (two cores, the common case), every part in one of two lists: the split
# whose longer half compiles least, from each part's compiled functions and their compile
# times measured alone on an empty cache, evened out on `armik compile --all`'s two
# processes (2026-12-07: 50.4 and 52.7 s of CPU, 53.9 s of wall time; how it got there:
# docs/compile-time.md). Each list's order puts first what the other half needs too and
# last what needs the other half's code, which is then loaded from the cache: swept's held
# target before hold, the closed forms' kernels before batch, the task solver after dls,
# whose region rows and linear algebra it finds in memory.
_HALVES = (
    (
        "dls",
        "qp",
        "swept",
        "spherical_shoulder",
        "servo",
        "planar2r",
        "clik",
        "collisions",
        "fk_batch",
        "batch",
        "tasks",
        "srs",
    ),
    (
        "spherical",
        "three_parallel",
        "path",
        "spherical_general",
        "three_parallel_general",
        "search_1d",
        "elimination_6r",
        "hold",
        "general_6r",
    ),
)


def compile(
    names: Sequence[str] | None = None,
    *,
    progress: bool | None = None,
    jobs: int | None = None,
    load: bool = True,
) -> dict:
    """Compile the parts ``names`` (default: every part, ``PARTS``) into numba's cache and
    return how long each took (s): compiling where the cache lacked them, loading where it
    had them. ``jobs``: processes compiling at once (default: one per core). ``progress``:
    a bar on stderr (default: when stderr is a terminal). ``load``: once other processes
    compiled them, load the parts here too, so that this process's calls run them at once
    (``armik compile``, which ends then, does not). Raises ``OptionError`` for an unknown
    name, listing the parts, or a ``jobs`` that is not a positive int."""
    if names is None:
        names = list(PARTS)
    names = _names(names)
    unknown = [n for n in names if n not in PARTS]
    if unknown:
        raise OptionError(
            f"unknown part {unknown[0]!r} to compile; parts: {listing(PARTS)}",
            option="names",
            value=unknown[0],
        )
    if jobs is None:
        jobs = os.cpu_count() or 1
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise OptionError(
            f"jobs must be a positive int (processes compiling at once), got {jobs!r}",
            option="jobs",
            value=jobs,
        )
    with compiling(), _no_notice():  # compiled here, not as Python (``kernel.tier``)
        return _compile(names, jobs, make_progress(progress, len(names), "compile"), load)


def _names(names: object) -> list[str]:
    """``names`` as a list of names: one name, or a list of them; ``OptionError`` naming
    the value otherwise (a number, bytes, a list holding a list)."""
    if isinstance(names, str):
        return [names]
    listed: list | None = None
    if not isinstance(names, (bytes, bytearray, memoryview)):
        try:
            listed = list(names)  # type: ignore[call-overload]
        except TypeError:
            pass
    if listed is None or not all(isinstance(n, str) for n in listed):
        raise OptionError(
            f"names must be a part's name or a list of them (str), got {names!r}; parts: "
            f"{listing(PARTS)}",
            option="names",
            value=names,
        )
    return listed


@contextlib.contextmanager
def _no_notice() -> Iterator[None]:
    """No compile notice while the parts compile here, as in the processes (``_quiet``):
    the times printed and the bar say it, and a notice's "`armik compile ...` builds it
    ahead of time" is what is running."""
    before = os.environ.get("ARMIK_COMPILE_NOTICE")
    os.environ["ARMIK_COMPILE_NOTICE"] = "0"
    try:
        yield
    finally:
        if before is None:
            del os.environ["ARMIK_COMPILE_NOTICE"]
        else:
            os.environ["ARMIK_COMPILE_NOTICE"] = before


def _compile(names: Sequence[str], jobs: int, bar, load: bool) -> dict:
    if jobs > 1 and len(names) > 1 and _spawn_starts():
        took = _in_processes(names, min(jobs, len(names)), bar)
        for name in names:  # from the cache now
            if name not in took:  # a process that died (killed, out of memory): here
                took[name] = _timed(name)
            elif load:
                PARTS[name]()
    else:
        took = {}
        for i, name in enumerate(names):
            took[name] = _timed(name)
            bar(i + 1, len(names))
    bar.close()
    return {name: took[name] for name in names}


def _timed(name: str) -> float:
    t0 = time.perf_counter()
    PARTS[name]()
    return time.perf_counter() - t0


def _quiet() -> None:
    os.environ["ARMIK_COMPILE_NOTICE"] = "0"  # the progress bar tells it; notices would mix in
    os.environ["ARMIK_COMPILE_HELPER"] = "0"  # the cores are taken by the other processes


def _spawn_starts() -> bool:
    """Whether a spawned process can start: it runs the main script again when it has a
    file, and a script read from stdin (``python -``) names one that does not exist
    (``python -c`` and an interactive session name none: they start)."""
    path = getattr(sys.modules.get("__main__"), "__file__", None)
    return path is None or os.path.isfile(path)


def _in_processes(names: Sequence[str], jobs: int, bar) -> dict[str, float]:
    """The parts' times, compiled in ``jobs`` processes; a part whose process died is left
    out (the caller compiles it)."""
    tasks = _tasks(names, jobs)
    # spawned, not forked: a fork copies numba's and the threads' state mid-flight
    context = multiprocessing.get_context("spawn")
    took: dict[str, float] = {}
    with ProcessPoolExecutor(jobs, mp_context=context, initializer=_quiet) as pool:
        futures = [pool.submit(_timed_each, task) for task in tasks]
        for future in as_completed(futures):
            try:
                took.update(future.result())
            except BrokenProcessPool:
                continue
            bar(len(took), len(names))
    return took


def _tasks(names: Sequence[str], jobs: int) -> list[tuple[str, ...]]:
    """``names`` as the processes' tasks, longest first: on two processes those of each of
    ``_HALVES`` in one task, in its order; else (or when that leaves one task: ``armik
    compile dls qp swept``) the parts of a ``_TOGETHER`` group in one task, in the group's
    order; every other part alone; every part alone when that still leaves fewer tasks
    than ``jobs`` processes (``armik compile dls qp``)."""
    tasks = _grouped(names, _HALVES) if jobs == 2 else []
    if len(tasks) < jobs:
        tasks = _grouped(names, _TOGETHER)
    if len(tasks) < jobs:
        tasks = [(n,) for n in names]
    return sorted(tasks, key=lambda t: -sum(_COST.get(n, 10) for n in t))


def _grouped(names: Sequence[str], groups: Sequence[tuple[str, ...]]) -> list[tuple[str, ...]]:
    """``names`` in the ``groups`` they belong to (in each group's order), every other one
    alone."""
    left = list(names)
    tasks = []
    for group in groups:
        task = tuple(n for n in group if n in left)
        if task:
            tasks.append(task)
            left = [n for n in left if n not in task]
    return tasks + [(n,) for n in left]


def _timed_each(task: tuple[str, ...]) -> dict[str, float]:
    return {name: _timed(name) for name in task}
