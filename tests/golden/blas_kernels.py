"""One set of OpenBLAS kernels on every x86-64 machine, for answers equal to the last bit.

numpy's OpenBLAS is built with DYNAMIC_ARCH: it picks its kernels by the CPU when it is
loaded, and an AVX-512 machine's (SkylakeX, Sapphire Rapids) sum in another order than an
AVX2 machine's (Haswell). armik's Python side multiplies small matrices through numpy, so
the golden answers (tests/golden) then differ in their last bits and, for a numeric solve
that runs out of iterations or a tie between two solutions, beyond. Pinned to the Haswell
kernels, the answers recorded on an AVX2 machine are reproduced bit for bit on an
AVX-512 one (measured there: 0 of the values differ, 372 without the pin). The pin is set
only on a CPU that has AVX2 and FMA (those kernels need them) and only before numpy is
loaded: OpenBLAS reads it once.
"""

from __future__ import annotations

import os
import sys

CORETYPE = "Haswell"


def pin_openblas() -> bool:
    """Set ``OPENBLAS_CORETYPE`` (unless it is set) where the Haswell kernels run; whether
    OpenBLAS will use it (numpy not loaded yet)."""
    if "numpy" in sys.modules:
        return os.environ.get("OPENBLAS_CORETYPE") == CORETYPE
    try:
        with open("/proc/cpuinfo") as f:
            flags = next((line.split() for line in f if line.startswith("flags")), [])
    except OSError:  # not Linux: numpy's wheels use other BLAS builds there
        return False
    if "avx2" in flags and "fma" in flags:
        os.environ.setdefault("OPENBLAS_CORETYPE", CORETYPE)
    return os.environ.get("OPENBLAS_CORETYPE") == CORETYPE
