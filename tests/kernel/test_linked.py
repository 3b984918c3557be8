"""A function never called from Python (``no_cpython_wrapper``) is linked into its callers,
whose module passes optimise it (``armik.kernel.linked``): its own module is not optimised
whole a second time, and the caller still solves its system to 1e-12."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

LINKED = textwrap.dedent(
    """
    import json
    import numpy as np
    from armik.kernel import linalg
    H = np.array([[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]])
    g = np.array([1.0, 2.0, -1.0])
    free = np.ones(3, dtype=np.int64)
    L, x = np.zeros((3, 3)), np.zeros(3)
    linalg.cholesky_solve(H, g, free, L, x)
    def passes(f):
        timings = f.get_metadata(f.signatures[0])["llvm_pass_timings"]
        return sorted({r.name for r in timings.list_longest_first() if "Module" in r.name})
    print(json.dumps({
        "callee": passes(linalg.cholesky_factor),
        "entry": passes(linalg.cholesky_solve),
        "error": float(np.abs(H @ x - g).max()),
    }))
    """
)


def test_a_function_never_called_from_python_is_optimised_in_its_callers_only(tmp_path):
    environ = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "NUMBA_LLVM_PASS_TIMINGS": "1"}
    environ["PYTHONPATH"] = os.pathsep.join(sys.path)
    environ["ARMIK_FIRST_CALLS"] = "compile"
    done = subprocess.run(
        [sys.executable, "-c", LINKED], env=environ, capture_output=True, text=True, check=True
    )
    got = json.loads(done.stdout.strip().splitlines()[-1])
    assert got["callee"] == []  # linked into cholesky_solve, optimised there
    assert "Module passes (full optimization)" in got["entry"]
    assert got["error"] < 1e-12
