"""Building an exported solver with the machine's C compiler and loading it with ctypes."""

from __future__ import annotations

import ctypes
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import armik

CFLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Wshadow", "-Werror"]
CXXFLAGS = ["-std=c++14", "-O2", "-Wall", "-Wextra", "-Wshadow", "-Werror"]
HERE = Path(__file__).parent
_P = ctypes.POINTER(ctypes.c_double)


def compilers() -> tuple[str, str]:
    cc, cxx = shutil.which("cc"), shutil.which("c++")
    if cc is None or cxx is None:
        pytest.skip("no C or C++ compiler (cc, c++) on this machine")
    return cc, cxx


def run(*argv: str) -> None:
    done = subprocess.run(argv, capture_output=True, text=True)
    assert done.returncode == 0, f"{' '.join(argv)}\n{done.stdout}{done.stderr}"


class Solver:
    """An exported solver ``name`` built as a shared library in ``folder``: ``ik(T)`` ->
    its solutions (n, dof), ``fk(q)`` -> 4x4, ``ik_count(T)`` -> the return value; with a
    held joint (``held``: its index) both take its value after ``T``."""

    def __init__(
        self, arm: armik.Arm, name: str, folder: Path, ikfast: bool = False, **tolerances: float
    ) -> None:
        cc, cxx = compilers()
        self.files = armik.export(arm, name, folder, ikfast=ikfast, **tolerances)
        self.dof, self.name = arm.dof, name
        c = folder / f"{name}_ik.c"
        if ikfast:  # the IKFast file as MoveIt's plugin includes it, beside N_ik.c
            obj = folder / f"{name}_ik.o"
            run(cc, *CFLAGS, "-fPIC", "-c", str(c), "-o", str(obj))
            harness = folder / "harness.cpp"
            harness.write_text(
                (HERE / "ikfast_harness.cpp")
                .read_text()
                .replace("NAME", name)
                .replace("UPPER", name.upper())
                .replace(
                    "NFREE", "0" if "_IK_HELD_JOINT" not in self.files[f"{name}_ik.h"] else "1"
                )
            )
            lib = folder / "libikfast.so"
            run(
                cxx, *CXXFLAGS, "-shared", "-fPIC", f"-I{HERE}", f"-I{folder}",
                str(harness), str(obj), "-o", str(lib), "-lm",
            )  # fmt: skip
        else:
            lib = folder / f"lib{name}.so"
            run(cc, *CFLAGS, "-shared", "-fPIC", str(c), "-o", str(lib), "-lm")
        self.lib = ctypes.CDLL(str(lib))
        self._ik = getattr(self.lib, f"{name}_ik")
        self._ik.restype = ctypes.c_int
        held = re.search(r"#define \w+_IK_HELD_JOINT (\d+)", self.files[f"{name}_ik.h"])
        self.held = int(held.group(1)) if held else None
        if self.held is not None:
            self._ik.argtypes = [_P, ctypes.c_double, _P]
        self._fk = getattr(self.lib, f"{name}_fk")
        found = re.search(r"#define \w+_IK_MAX_SOLUTIONS (\d+)", self.files[f"{name}_ik.h"])
        assert found
        self.max = int(found.group(1))

    def ik_count(self, T: np.ndarray, held: float | None = None) -> tuple[int, np.ndarray]:
        T = np.ascontiguousarray(T, dtype=float).reshape(16)
        Q = np.full((self.max, self.dof), np.nan)
        if self.held is None:
            n = self._ik(T.ctypes.data_as(_P), Q.ctypes.data_as(_P))
        else:
            assert held is not None, "this solver takes the held joint's value"
            n = self._ik(T.ctypes.data_as(_P), float(held), Q.ctypes.data_as(_P))
        return n, Q

    def ik(self, T: np.ndarray, held: float | None = None) -> np.ndarray:
        n, Q = self.ik_count(T, held)
        assert 0 <= n <= self.max
        return Q[:n].copy()

    def fk(self, q: np.ndarray) -> np.ndarray:
        q = np.ascontiguousarray(q, dtype=float)
        T = np.empty(16)
        self._fk(q.ctypes.data_as(_P), T.ctypes.data_as(_P))
        return T.reshape(4, 4)
