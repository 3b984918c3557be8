"""Compiling ahead of time (``armik.compile``), the notice a compiling first call gives, and
options that are data: a tour of every option compiles each kernel for one signature."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import armik
from armik import precompile
from armik.errors import OptionError
from armik.kernel import task_rows
from armik.tools.cli import main
from tests.conftest import TOUR_DONE, TOUR_STARTED
from tests.kernel import seeded_cache

SMALL = textwrap.dedent(
    """
    import numpy as np
    from armik.kernel.measure import split_pose
    split_pose(np.eye(4))
    """
)


TOUR = textwrap.dedent(
    """
    import importlib, json, pkgutil, sys
    from pathlib import Path
    from numba.core.registry import CPUDispatcher
    import armik
    from armik import precompile
    took = armik.compile(load=False)
    Path(sys.argv[1]).touch()  # compiled: the other test workers start (tests/conftest.py)
    for part in precompile.PARTS.values():  # each loaded here, as armik.compile() loads them
        part()
    counts = {}
    for package in ("armik.kernel", "armik.solvers.closed_form", "armik.constraints"):
        for info in pkgutil.iter_modules(sys.modules[package].__path__):
            module = importlib.import_module(f"{package}.{info.name}")
            for name, value in vars(module).items():
                if isinstance(value, CPUDispatcher) and value.py_func.__module__ == module.__name__:
                    counts[f"{module.__name__}.{name}"] = len(value.signatures)
    print(json.dumps({"parts": list(took), "counts": counts}))
    """
)


def test_a_tour_of_every_option_compiles_each_kernel_once():
    # In a process of its own (the test run's other calls do not count), from the shared
    # cache: every part, with the variants options and inputs select (weights, position
    # targets, budgets, tolerances, read-only seeds and targets).
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["PYTHONPATH"] = os.pathsep.join(sys.path)
    Path(TOUR_STARTED).write_text(str(os.getpid()), encoding="utf-8")
    try:
        done = subprocess.run(
            [sys.executable, "-c", TOUR, TOUR_DONE],
            env=env,
            capture_output=True,
            text=True,
            check=True,
        )
    finally:  # the other test workers wait for this (tests/conftest.py)
        Path(TOUR_DONE).touch()
    got = json.loads(done.stdout.strip().splitlines()[-1])
    assert got["parts"] == list(precompile.PARTS)
    counts = got["counts"]
    # the entries called from Python (their callees are compiled into them)
    for entry in (
        "armik.kernel.single.solve_pose_dls",
        "armik.kernel.single.solve_pose_qp",
        "armik.kernel.entry.solve_targets_dls",
        "armik.kernel.entry.solve_targets_qp",
        "armik.kernel.measure.placement_check",
        "armik.kernel.fk_many.fk_many",
        "armik.solvers.closed_form.three_parallel.solve_into",
        "armik.solvers.closed_form.spherical_wrist.kernel_many",
        "armik.solvers.closed_form.swept_7r.held_rows",
        "armik.constraints.bounds.ordered_bounds",
        "armik.constraints.bounds.ordered_bounds_many",
        "armik.solvers.closed_form.general_6r.kernel",
        "armik.kernel.task_rows.descend",
    ):
        assert counts[entry] == 1, entry
    assert {name: n for name, n in counts.items() if n > 1} == {}


def _run(code: str, cache, **env) -> subprocess.CompletedProcess:
    environ = {**os.environ, "NUMBA_CACHE_DIR": str(cache), **env}
    environ["PYTHONPATH"] = os.pathsep.join(sys.path)
    return subprocess.run(
        [sys.executable, "-c", code], env=environ, capture_output=True, text=True, check=True
    )


def test_a_compiling_first_call_says_so_once_and_a_cached_one_says_nothing(tmp_path):
    first = _run(SMALL, tmp_path / "cache", ARMIK_COMPILE_NOTICE="1")
    assert "armik: compiling the forward-kinematics check for this machine" in first.stderr
    assert first.stderr.count("armik: compiling") == 1
    again = _run(SMALL, tmp_path / "cache", ARMIK_COMPILE_NOTICE="1")  # a new process: cached
    assert "armik: compiling" not in again.stderr
    quiet = _run(SMALL, tmp_path / "other", ARMIK_COMPILE_NOTICE="0")
    assert "armik: compiling" not in quiet.stderr


def test_compile_command_and_bad_names(capsys):
    assert main(["compile", "clik"]) == 0
    out = capsys.readouterr().out
    assert "clik" in out and "compiled 1 part in" in out
    assert main(["compile", "nothing"]) == 2
    assert "unknown part 'nothing'" in capsys.readouterr().err
    with pytest.raises(OptionError, match="unknown part 'warp'.*parts: 'dls'"):
        armik.compile(["dls", "warp"])


# the packages of armik's compiled functions that the parts call
COMPILED = ("armik.kernel", "armik.solvers.closed_form", "armik.constraints")

PARALLEL = textwrap.dedent(
    """
    import json
    import armik
    print(json.dumps(sorted(armik.compile(["planar2r", "fk_batch"], jobs=2))))
    """
)


# The same parts in a new process, on one: what numba compiled there, where it found nothing
# in the cache to load (armik.compile gives no notice of its own parts: the notice cannot say)
LOADED = textwrap.dedent(
    """
    import json
    import numba.core.event as ev
    import armik

    compiled = []

    class Compiled(ev.Listener):
        def on_start(self, event):
            compiled.append(event.data["dispatcher"].py_func.__qualname__)

        def on_end(self, event):
            pass

    ev.register("numba:compile", Compiled())
    armik.compile(["planar2r", "fk_batch"], jobs=1)
    print(json.dumps(compiled))
    """
)


def test_compiling_in_two_processes_fills_the_cache_a_new_process_loads(tmp_path):
    # each part's own kernels (and the joint values' conversion both call) compile in the
    # two processes; what else they call is loaded from the suite's entries where it has them
    cache = tmp_path / "cache"
    own = {"planar2r_kernel", "fk_many", "coordinates"}
    seeded_cache.seed(cache, lambda d, module: module.rpartition(".")[2] in own, COMPILED)
    done = _run(PARALLEL, cache, ARMIK_COMPILE_NOTICE="1")
    assert json.loads(done.stdout.strip().splitlines()[-1]) == ["fk_batch", "planar2r"]
    again = _run(LOADED, cache)
    assert json.loads(again.stdout.strip().splitlines()[-1]) == []


def test_compiling_from_a_script_on_stdin_compiles_in_its_own_process(tmp_path):
    """A spawned process runs the main script again, which ``python -`` has no file of: the
    parts compile in the calling process, where a broken process pool was raised."""
    environ = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    done = subprocess.run(
        [sys.executable, "-"],
        input=PARALLEL,
        env=environ,
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(done.stdout.strip().splitlines()[-1]) == ["fk_batch", "planar2r"]


@pytest.mark.parametrize("jobs", [0, -1, 1.5, True, "2"])
def test_bad_jobs_are_refused_with_the_value(jobs):
    with pytest.raises(OptionError, match=f"jobs must be a positive int.*got {jobs!r}"):
        armik.compile(["clik"], jobs=jobs)


OBJMODE = textwrap.dedent(
    """
    import numpy as np
    from armik.kernel.step import backend_step
    print(backend_step(2.0 * np.eye(2), np.ones(2), -np.ones(2), np.ones(2), 0))
    """
)


def test_an_objmode_block_lifted_from_the_cache_is_not_announced(tmp_path):
    # the QP backend's objmode block is lifted again in every process (a fraction of a
    # second); from the cache, the notice must not announce a compilation of the solvers
    _run(OBJMODE, tmp_path / "cache", ARMIK_COMPILE_NOTICE="1")
    again = _run(OBJMODE, tmp_path / "cache", ARMIK_COMPILE_NOTICE="1")
    assert "[0.5 0.5]" in again.stdout
    assert "armik: compiling" not in again.stderr


def test_the_numeric_parts_compile_in_one_process_when_there_are_tasks_enough():
    from armik.precompile import _HALVES, PARTS, _tasks

    tasks = _tasks(list(PARTS), 2)  # two processes: the two halves, each part once
    assert sorted(tasks) == sorted(_HALVES)
    assert sorted(n for t in tasks for n in t) == sorted(PARTS)
    assert tasks[0][:2] == ("dls", "qp") or tasks[1][:2] == ("dls", "qp")  # dls first
    tasks = _tasks(list(PARTS), 3)
    assert sorted(n for t in tasks for n in t) == sorted(PARTS)  # each part once
    assert ("dls", "qp", "batch", "hold", "path") in tasks  # one after another, dls first
    assert _tasks(["qp", "dls"], 2) in ([("dls",), ("qp",)], [("qp",), ("dls",)])
    assert _tasks(["qp", "dls", "swept"], 2) == [("dls", "qp"), ("swept",)]


def test_every_compiled_module_has_its_own_line_in_the_notice():
    """Each module with compiled functions is named by a part of its own (not the catch-all
    "armik's compiled code"), and each part's prefix names a module that exists."""
    import importlib
    import pkgutil

    from numba.core.registry import CPUDispatcher

    from armik.kernel import notice

    compiled = set()
    for info in pkgutil.walk_packages(armik.__path__, "armik."):
        if info.name.endswith("__main__"):
            continue  # running it is the CLI
        module = importlib.import_module(info.name)
        if any(
            isinstance(v, CPUDispatcher) and v.py_func.__module__ == info.name
            for v in vars(module).values()
        ):
            compiled.add(info.name)
    assert "armik.solvers.closed_form.search_zeros" in compiled
    # the searches' entry, first to compile at their first call, names them
    assert notice.part_of("armik.solvers.closed_form.search_zeros")[0] == (
        "the one-dimensional searches"
    )
    for name in sorted(compiled):
        what, _ = notice.part_of(name)
        assert what != "armik's compiled code", f"{name} has no part in notice.PARTS"
    for prefix, _, _ in notice.PARTS:
        assert any(m == prefix or m.startswith(prefix + ".") for m in compiled), prefix


def test_compiled_functions_make_no_c_callback_wrapper():
    # A function numba compiles is wrapped for calls from Python and, unless told not to,
    # for calls through a C function pointer, which armik never makes: that wrapper was a
    # fifth of the code LLVM optimised for the closed forms. Functions inlined where they are
    # called (inline="always") are never compiled alone.
    import importlib
    import pkgutil

    from numba.core.registry import CPUDispatcher

    wrapped = []
    for package in ("armik.kernel", "armik.solvers.closed_form", "armik.servo"):
        for info in pkgutil.iter_modules(importlib.import_module(package).__path__):
            module = importlib.import_module(f"{package}.{info.name}")
            for name, value in vars(module).items():
                if isinstance(value, CPUDispatcher) and value.py_func.__module__ == module.__name__:
                    options = value.targetoptions
                    if options.get("inline", "never") != "always":
                        if not options.get("no_cfunc_wrapper"):
                            wrapped.append(f"{module.__name__}.{name}")
    assert wrapped == []


# The task solver's rows alone (``task_rows.stacked``: ``_stack``, which ``descend`` calls,
# with every FK caller in it), compiled in a process of its own: the dispatchers it compiles
# or loads as their callees are typed there, and count their signatures
STACKED_ALONE = textwrap.dedent(
    """
    import armik
    from armik.kernel import fk
    from armik.kernel.task_rows import stacked
    from armik.solve.task_table import task_table
    from armik.solve.tasks import frame_ids
    arm = armik.load("panda")
    q = arm.middle
    T = arm.fk(q, "panda_link4").inverse() * arm.fk(q)
    tasks = (armik.Relative("panda_hand", "panda_link4", T),)
    table = task_table(arm.kinematics, tasks, frame_ids(arm.kinematics, tasks))
    stacked(*table.chains, table.R_t, table.p_t, table.params, table.ints, q)
    print(len(fk.forward.signatures), len(fk.jacobian_local.signatures))
    """
)


def test_the_task_solver_compiles_the_fk_once(tmp_path):
    # a frame's placement in another's (``task_rows._in_reference``) is written to a
    # C-ordered rotation as every other caller's: a strided one compiled the FK and its
    # Jacobian a second time, in every process that compiles the task solver. The rows
    # compile there; the rest (the FK, the region's rows, the descent ``task_table`` loads)
    # is loaded from the suite's entries where it has them: a callee loaded for a caller
    # compiled is a signature of its dispatcher as a compiled one is (a strided rotation's
    # a second one, whether compiled or loaded)
    rows = {task_rows.stacked, task_rows._stack, task_rows._in_reference}
    seeded_cache.seed(tmp_path, lambda d, module: d in rows)
    environ = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "ARMIK_COMPILE_HELPER": "0"}
    environ["PYTHONPATH"] = os.pathsep.join(sys.path)
    done = subprocess.run(
        [sys.executable, "-c", STACKED_ALONE],
        env=environ,
        capture_output=True,
        text=True,
        check=True,
    )
    assert done.stdout.split() == ["1", "1"]


_SOLVES = """
for name in ARMS:
    arm = armik.load(name)
    T = arm.fk(arm.random_q(0))
    far = pin.SE3(T.rotation, 10 * T.translation)
    for target in TARGETS(T, far):
        arm.solve(target, solver=SOLVER, **B)
        [r.status for r in arm.solve_all(target, solver=SOLVER, **B)]
        # a constraint of the user's: the general path, where the prepared one steps aside
        arm.solve(target, solver=SOLVER, constraints=[JointLimits()], **B)
"""
_NUMERIC = ("ur5", "panda", "kinova", "scara", "planar_3link", "so101")
_POSES = "lambda T, far: (T, far)"
_CLOSED = {
    "planar2r": (("planar_2link",), "lambda T, far: (T.translation[:2], far.translation[:2])"),
    "spherical": (("abb_irb120",), _POSES),
    "three_parallel": (("ur5", "z1"), _POSES),
    "swept": (("panda",), _POSES),
    "srs": (("kuka_iiwa14",), _POSES),
    # a target out of reach on the Kinova measures a read-only answer: its joint values'
    # conversion (``ArmModel.to_pin``) is the kernel a writable one compiled
    "spherical_general": (("kinova",), _POSES),
}


def _uses(solver: str, arms, targets: str, batch: bool = False) -> str:
    code = f"ARMS = {arms!r}\nSOLVER = {solver!r}\nTARGETS = {targets}\n" + _SOLVES
    if batch:
        code += (
            "    H = np.array([arm.fk(arm.random_q(s)).homogeneous for s in range(2)])\n"
            "    arm.solve_batch(H, solver=SOLVER, workers=1, progress=False)\n"
        )
    return code


_AFTER = [
    *[
        (s, _uses(s, _NUMERIC, "lambda T, far: (T, T.translation, far, far.translation)"))
        for s in ("dls", "qp")
    ],
    ("clik", _uses("clik", _NUMERIC, _POSES).replace("[r.status", "# [r.status")),
    *[(s, _uses(s, arms, targets)) for s, (arms, targets) in _CLOSED.items()],
    *[
        (f"{s} batch", _uses(s, arms, targets, batch=True))
        for s, (arms, targets) in _CLOSED.items()
    ],
    (
        "fk_batch",
        "for n in ('kinova', 'scara', 'ur5'):\n    a = armik.load(n)\n"
        "    Q = a.random_q(0, n=3)\n    a.fk_batch(Q)\n"
        "    Q.flags.writeable = False\n    a.fk_batch(Q)\n",
    ),
    (
        "dls planar2r spherical three_parallel swept path",
        "for n in ('planar_2link', 'abb_irb120', 'ur5', 'panda'):\n    a = armik.load(n)\n"
        "    q = a.random_q(1)\n    line = [a.fk(q + 0.01 * k) for k in range(3)]\n"
        "    if n == 'planar_2link':\n        line = [T.translation[:2] for T in line]\n"
        "    a.solve_path(line, q, **B)\n    a.solve_path(line, q, plan='global', **B)\n",
    ),
    (
        "tasks",
        "a = armik.load('kinova')\nT = a.fk(a.middle)\n"
        "a.solve([armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2], 0.05),"
        " armik.Position(a.fk(a.middle, 'j2s6s200_link_4').translation, bounds=(0.1,) * 3,"
        " frame='j2s6s200_link_4')])\n",
    ),
    ("servo", "a = armik.load('kinova')\na.servo(a.middle).step(a.fk(a.middle))\n"),
]


@pytest.mark.parametrize(("parts", "uses"), _AFTER, ids=[p for p, _ in _AFTER])
def test_a_part_compiled_alone_builds_everything_its_solves_call(after_parts, parts, uses):
    # `armik compile dls` did not build the batch FK that a SCARA's rails and heights place
    # restarts with (about 3 s at its first solve), nor the FK check of a target out of
    # reach; a closed form's part not the check of its unreachable answers; no part the
    # joint values of an arm with continuous joints (each case a process of its own:
    # tests/kernel/after_parts.py)
    assert after_parts.new(parts, uses) == []
