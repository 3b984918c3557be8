"""The CPU time of the calling thread, readable from compiled code (the solve budget).

``thread_cpu_ns()`` calls ``clock_gettime(CLOCK_THREAD_CPUTIME_ID)`` through an LLVM
declaration resolved by name at link time, so functions that use it stay cacheable (a
ctypes pointer would not). Other threads' work does not count against it: the same seeded
solve stops at the same point whether one thread or eight are solving, up to the timing
noise of the thread itself. A read costs about 0.5 us here (a system call), so the descent
reads it every few iterations only.

Windows has no ``clock_gettime``: there the C runtime's ``clock()`` is used, which counts
wall time since the process started (untested on Windows).
"""

from __future__ import annotations

import sys

from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

CLOCK_THREAD_CPUTIME_ID = 16 if sys.platform == "darwin" else 3  # macOS; Linux and BSDs


def _codegen_posix(context, builder, signature, args):
    i64 = ir.IntType(64)
    timespec = ir.LiteralStructType([i64, i64])
    fnty = ir.FunctionType(ir.IntType(32), [ir.IntType(32), timespec.as_pointer()])
    fn = cgutils.get_or_insert_function(builder.module, fnty, "clock_gettime")
    ts = cgutils.alloca_once(builder, timespec)
    builder.call(fn, [ir.Constant(ir.IntType(32), CLOCK_THREAD_CPUTIME_ID), ts])
    sec = builder.load(cgutils.gep_inbounds(builder, ts, 0, 0))
    nsec = builder.load(cgutils.gep_inbounds(builder, ts, 0, 1))
    return builder.add(builder.mul(sec, ir.Constant(i64, 1_000_000_000)), nsec)


def _codegen_windows(context, builder, signature, args):
    i64 = ir.IntType(64)
    fnty = ir.FunctionType(ir.IntType(32), [])
    ticks = builder.call(cgutils.get_or_insert_function(builder.module, fnty, "clock"), [])
    return builder.mul(builder.sext(ticks, i64), ir.Constant(i64, 1_000_000))  # ms -> ns


@intrinsic
def _clock_ns(typingctx):
    return types.int64(), (_codegen_windows if sys.platform == "win32" else _codegen_posix)


@njit(cache=True, nogil=True, inline="always")
def thread_cpu_ns():
    """CPU time of the calling thread (ns)."""
    return _clock_ns()
