"""Golden answers: armik's public API gives today's answers bit for bit.

Guards a reorganisation of the package (or any change meant to keep the answers): the
calls of ``make_golden.compute`` (solve, solve_all, solve_batch with one worker, solve_path
and fk on planar_2link, ur5, abb_irb120, panda, kinova and scara, with every registered
solver and "auto"; full poses in several forms, positions, unreachable targets, weights,
position_only) must reproduce tests/golden/answers.json exactly: q and the errors compared
as ``float.hex()`` strings, status, solver, iterations, restarts, branch, singular,
success and reason as recorded. Numeric calls run on ``iteration_budget`` with a fixed
``seed``, so the answers do not depend on the machine's load, and the tests pin
OpenBLAS's kernels (``blas_kernels``), so they do not depend on the CPU's vector units.

When a change of answers is intended, regenerate and commit the file with the change:

    python tests/golden/make_golden.py
"""

from __future__ import annotations

import json
import os

import pytest

from .blas_kernels import CORETYPE
from .make_golden import ANSWERS, FORMAT, compute

RECORDED = json.loads(ANSWERS.read_text()) if ANSWERS.exists() else {"groups": {}}
GROUPS = list(RECORDED["groups"])
SHOWN = 12  # differences listed per group


@pytest.fixture(scope="module")
def computed() -> dict[str, list[dict]]:
    return compute()


def _float(text):
    try:
        return float.fromhex(text)
    except (TypeError, ValueError):
        return None


def differences(want, got, where: str) -> list[str]:
    """Where ``got`` differs from ``want``, one line per difference (hex floats decoded)."""
    if isinstance(want, dict) and isinstance(got, dict):
        out = []
        if "call" in want and want.get("call") != got.get("call"):
            return [f"{where}: call {got.get('call')!r}, recorded {want['call']!r}"]
        for key in sorted(set(want) | set(got)):
            if key not in got or key not in want:
                out.append(f"{where}: key {key!r} only in {'recorded' if key in want else 'new'}")
            else:
                out += differences(want[key], got[key], f"{where}.{key}")
        return out
    if isinstance(want, list) and isinstance(got, list):
        out = []
        if len(want) != len(got):
            out.append(f"{where}: {len(got)} items, recorded {len(want)}")
        for i, (w, g) in enumerate(zip(want, got)):
            label = f" ({w['call']})" if isinstance(w, dict) and "call" in w else ""
            out += differences(w, g, f"{where}[{i}]{label}")
        return out
    if type(want) is not type(got) or want != got:
        a, b = _float(want), _float(got)
        if a is not None and b is not None:
            return [f"{where}: {b!r} ({got}), recorded {a!r} ({want}), off by {b - a:.3g}"]
        return [f"{where}: {got!r}, recorded {want!r}"]
    return []


def test_answers_file():
    assert ANSWERS.exists(), f"{ANSWERS} is missing: run python tests/golden/make_golden.py"
    assert RECORDED["format"] == FORMAT


def test_same_groups(computed):
    assert list(computed) == GROUPS


@pytest.mark.parametrize("group", GROUPS)
def test_group(computed, group):
    found = differences(RECORDED["groups"][group], computed.get(group), group)
    more = f"\n... and {len(found) - SHOWN} more" if len(found) > SHOWN else ""
    pinned = os.environ.get("OPENBLAS_CORETYPE") == CORETYPE
    assert not found, (
        f"{len(found)} answers differ from {ANSWERS.name} (OpenBLAS kernels pinned to "
        f"{CORETYPE}: {pinned}; see blas_kernels.py):\n" + "\n".join(found[:SHOWN]) + more
    )
