"""``armik`` pickles by its name wherever it is imported (``armik/__init__.py``): a user's
function of a script that reads it, pickled by value (cloudpickle: a process pool's, Dask's),
travels without ``armik.solve.distributed`` imported first."""

from __future__ import annotations

import subprocess
import sys

import pytest

SCRIPT = """
import pickle, sys
import cloudpickle
import armik

def cost(q):  # a user's prefer= cost of a script: pickled by value, with its armik
    return float(q[0]) + (armik.Status.CONVERGED.value == "converged")

blob = cloudpickle.dumps(cost)
assert "armik.solve.distributed" not in sys.modules
print(pickle.loads(blob)([1.0]), pickle.loads(pickle.dumps(armik)) is armik)
"""


def test_a_scripts_function_reading_armik_pickles_by_value():
    pytest.importorskip("cloudpickle")
    proc = subprocess.run(
        [sys.executable, "-c", SCRIPT], capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["2.0", "True"]
