"""``armik compile``: every compiled part built into numba's cache, with how long it took
(its parser: ``commands.add_compile_command``)."""

from __future__ import annotations

import argparse
import time

from armik.precompile import compile


def cmd_compile(args: argparse.Namespace) -> int:
    names = None if args.all or not args.names else args.names
    t0 = time.perf_counter()
    took = compile(names, jobs=args.jobs, load=False)  # the command ends: nothing to load
    wall = time.perf_counter() - t0
    width = max(map(len, took), default=0)  # one column: three_parallel_general is 22
    for name, seconds in took.items():
        print(f"  {name:<{width}} {seconds:7.2f} s")
    print(f"compiled {len(took)} part{'' if len(took) == 1 else 's'} in {wall:.1f} s")
    return 0
