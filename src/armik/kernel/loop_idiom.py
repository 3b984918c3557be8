"""LLVM's loop-idiom pass off while armik's code compiles: it took most of the compile time.

LLVM's ``LoopIdiomRecognize`` turns loops of stores into ``memset``/``memcpy`` calls. On a
large inlined function it compares every candidate store with every instruction of its
loop, and on the 6R closed forms built from the subproblems (SP5, SP6 inlined into the
family's kernel) that took 163 of the 164 s of LLVM's optimisation of
``three_parallel_general.kernel`` (``NUMBA_LLVM_PASS_TIMINGS=1``; 143 s of CPU for its
first call, 18 s with the pass off). The pass changes how stores are emitted, never
arithmetic: the answers are the same bits.

The option is LLVM's own (``-disable-loop-idiom-all``), global to the process, so it is on
only while an armik function compiles (numba's "numba:compile" events, outermost first;
numba compiles one function at a time, under its global lock) and off again after: other
numba code in the process compiles as it would without armik.
"""

from __future__ import annotations

import llvmlite.binding as llvm
from numba.core import event

OPTION = "-disable-loop-idiom-all"


def _armik(ev: event.Event) -> bool:
    dispatcher = ev.data.get("dispatcher") if isinstance(ev.data, dict) else None
    module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
    return module == "armik" or module.startswith("armik.")


class _Off(event.Listener):
    """Sets the option when an armik function starts compiling outside any other armik
    compile, clears it when that one ends."""

    def __init__(self) -> None:
        self.depth = 0

    def on_start(self, ev: event.Event) -> None:
        if _armik(ev):
            self.depth += 1
            if self.depth == 1:
                llvm.set_option("armik", OPTION)

    def on_end(self, ev: event.Event) -> None:
        if _armik(ev):
            self.depth -= 1
            if self.depth == 0:
                llvm.set_option("armik", OPTION + "=false")


OFF = _Off()
event.register("numba:compile", OFF)
