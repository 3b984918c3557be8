"""Processes that compiled only some parts (``armik compile PART``), then solve as a user of
those parts does: which compiled functions those solves add (``After.new``). Every compiled
function they call was built by the parts, so nothing new is loaded from the cache (with
an empty cache: nothing compiles at the first solve).

Each case runs in a process of its own, nothing compiled or loaded when its parts start. One
process imports numba, armik and every module whose compiled functions count, as a new
process does before its parts, and forks a child for each case there: the children start
where a new process would, without importing it all again (1.2 s of CPU a case)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import textwrap

FORKS = textwrap.dedent(
    """
    import importlib, json, os, pkgutil, sys, traceback
    import numpy as np
    import pinocchio as pin
    from numba.core.registry import CPUDispatcher
    import armik
    from armik import precompile
    from armik.constraints.limits import JointLimits

    modules = []
    for info in pkgutil.walk_packages(armik.__path__, "armik."):
        if not info.name.startswith(("armik.view", "armik.tools")):
            modules.append(importlib.import_module(info.name))

    def signatures():
        return {
            (f"{m.__name__}.{name}", str(s))
            for m in modules
            for name, v in vars(m).items()
            if isinstance(v, CPUDispatcher) and v.py_func.__module__ == m.__name__
            for s in v.signatures
        }

    def case(parts, uses):
        for part in parts.split():
            precompile.PARTS[part]()
        built = signatures()
        exec(uses, {**globals(), "B": {"iteration_budget": 50}})
        return sorted({name for name, _ in signatures() - built})

    for line in sys.stdin:
        parts, uses = json.loads(line)
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:  # the case, then out at once: the parent's exit handlers are not its
            code = 1
            try:
                print("NEW " + json.dumps(case(parts, uses)), flush=True)
                code = 0
            except BaseException:
                traceback.print_exc()
            sys.stderr.flush()
            os._exit(code)
        _, status = os.waitpid(pid, 0)
        print("EXIT " + json.dumps(os.waitstatus_to_exitcode(status)), flush=True)
    """
)


class After:
    """The forking process (started at the first case), for the cases of one test process."""

    def __init__(self) -> None:
        self._process: subprocess.Popen | None = None
        self._stderr = tempfile.TemporaryFile(mode="w+")

    def new(self, parts: str, uses: str) -> list[str]:
        """The compiled functions (module.name) that running ``uses`` (Python, with armik,
        np, pin, JointLimits and ``B``, an iteration budget) added in a new process after
        the parts ``parts`` (names separated by spaces)."""
        process = self._started()
        assert process.stdin is not None and process.stdout is not None
        process.stdin.write(json.dumps([parts, uses]) + "\n")
        process.stdin.flush()
        new = None
        for line in process.stdout:
            if line.startswith("NEW "):
                new = json.loads(line[4:])
            elif line.startswith("EXIT "):
                assert json.loads(line[5:]) == 0, self._errors()
                assert new is not None
                return list(new)
        raise AssertionError(f"the forking process ended: {self._errors()}")

    def close(self) -> None:
        if self._process is not None:
            assert self._process.stdin is not None
            self._process.stdin.close()
            self._process.wait()
        self._stderr.close()

    def _started(self) -> subprocess.Popen:
        if self._process is None:
            environ = {**os.environ, "ARMIK_FIRST_CALLS": "compile", "ARMIK_COMPILE_HELPER": "0"}
            environ["PYTHONPATH"] = os.pathsep.join(sys.path)
            self._process = subprocess.Popen(
                [sys.executable, "-c", FORKS],
                env=environ,
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=self._stderr,
                text=True,
            )
        return self._process

    def _errors(self) -> str:
        self._stderr.seek(0)
        return self._stderr.read()[-3000:]
