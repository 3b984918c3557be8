"""What numba's dispatch costs from Python: per array argument, and per array returned.

Empty compiled functions taking 4 or 8 float arrays, returning an int, a new array, or
writing into an array the caller passes (after ``np.empty``, as ``sixr_answers.pose_runner`` does);
best of 7 timeit runs. These costs are why the prepared runners pass packed arrays
(``sixr.flat``, ``kernel.check.check_frame``) and write into the caller's buffer.

    python benchmarks/dispatch.py
"""

from __future__ import annotations

import os
import timeit

import numpy as np
from numba import njit

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs


@njit
def four(a, b, c, d):
    return 1


@njit
def eight(a, b, c, d, e, f, g, h):
    return 1


@njit
def returns_array(a, b, c, d):
    return np.empty(6)


@njit
def writes_into(a, b, c, d, out):
    out[0] = 1.0
    return 1


def best(fn, number: int = 100_000) -> float:
    return min(timeit.repeat(fn, number=number, repeat=7)) / number * 1e6


def main() -> None:
    x = np.zeros(6)
    for fn, args in ((four, (x,) * 4), (eight, (x,) * 8), (returns_array, (x,) * 4)):
        fn(*args)
    writes_into(x, x, x, x, x)
    t4 = best(lambda: four(x, x, x, x))
    t8 = best(lambda: eight(x, x, x, x, x, x, x, x))
    ret = best(lambda: returns_array(x, x, x, x))
    into = best(lambda: writes_into(x, x, x, x, np.empty(6)))
    print(f"4 array arguments, int returned: {t4:.3f} us")
    print(f"8 array arguments, int returned: {t8:.3f} us ({(t8 - t4) / 4 * 1e3:.0f} ns an array)")
    print(f"4 arguments, a new array returned: {ret:.3f} us (+{ret - t4:.3f} us)")
    print(f"4 arguments, np.empty passed in and written: {into:.3f} us (+{into - t4:.3f} us)")


if __name__ == "__main__":
    main()
