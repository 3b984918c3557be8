"""``armik compile``: every compiled part built into numba's cache, with how long it took."""

from __future__ import annotations

import argparse
import time

from armik.precompile import PARTS, compile


def add_compile_command(command) -> None:
    c = command(
        "compile",
        "compile armik's kernels for this machine into numba's cache, once (a first call "
        "then loads them in milliseconds)",
        "armik compile --all",
        cmd_compile,
    )
    c.add_argument("names", nargs="*", metavar="PART", help=f"parts: {', '.join(PARTS)}")
    c.add_argument("--all", action="store_true", help="every part (the default)")
    c.add_argument(
        "--jobs", type=int, default=None, help="processes compiling at once (default: one per core)"
    )


def cmd_compile(args: argparse.Namespace) -> int:
    names = None if args.all or not args.names else args.names
    t0 = time.perf_counter()
    took = compile(names, jobs=args.jobs)
    wall = time.perf_counter() - t0
    for name, seconds in took.items():
        print(f"  {name:<15} {seconds:7.2f} s")
    print(f"compiled {len(took)} parts in {wall:.1f} s")
    return 0
