"""Commands that measure armik: ``bench`` and ``compare``."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from armik.errors import InputError
from armik.model.catalogue import SPATIAL_ARMS
from armik.tools import bench as bench_mod
from armik.tools import compare, compare_plots


def cmd_bench(args: argparse.Namespace) -> int:
    notes: list[str] = []
    rows = bench_mod.run(
        _names(args.arms or list(SPATIAL_ARMS)),
        _names(args.solvers or list(bench_mod.DEFAULT_SOLVERS)),
        n=args.n,
        budget=args.budget,
        seed=args.seed,
        tol=args.tol,
        repeats=args.repeats,
        show_progress=not args.json,
        peers=_names(args.peers),
        notes=notes,
        tip=args.tip,
    )
    if args.json:
        print(as_json([r.as_dict() for r in rows]))
    else:
        passes = f" x {args.repeats} passes (other solver seeds)" if args.repeats > 1 else ""
        print(
            f"N = {args.n} targets per arm{passes}, budget {args.budget * 1e3:g} ms, tolerance "
            f"{args.tol:g} m / rad, seeds from mid-limits, sampling seed {args.seed}"
        )
        print(bench_mod.table(rows))
        for line in bench_mod.ratios(rows) + notes:
            print(line)
    return 0


def _names(values: list[str]) -> list[str]:
    """Names given as separate words or comma-separated ("dls qp" or "dls,qp")."""
    return [name for value in values for name in value.split(",") if name]


def cmd_compare(args: argparse.Namespace) -> int:
    if args.speed and args.plot:
        raise InputError(
            "--speed times the closed forms only and draws no figure: give --speed or --plot"
        )
    if args.speed:
        notes: list[str] = []
        rows = compare.speed(n=args.n, seed=args.seed, notes=notes)
        if args.json:
            print(as_json(rows))
        else:
            print("\n".join([compare.speed_table(rows), *notes]))
        return 0
    if args.plot:  # before the run, not after it: matplotlib and a folder to write in
        compare_plots.need_matplotlib("--plot")
        try:
            Path(args.plot).mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(
                f"--plot {args.plot!r} cannot be the figures' folder ({exc.strerror or exc}): "
                "give a folder, new or existing, that you can write to"
            ) from None
    report = compare.run(n=args.n, seed=args.seed)
    if args.json:
        print(as_json(report.as_dict()))
    else:
        print(report.text())
    if args.plot:
        for path in compare_plots.plot(report, args.plot):
            print(f"wrote {path}")
    return 0


def as_json(value: object) -> str:
    """``value`` as JSON that every reader takes: a figure with nothing to measure (no
    reachable target in a small ``-n``: a median of none, NaN) is null, not ``NaN``."""
    return json.dumps(_finite(value), indent=2, allow_nan=False)


def _finite(value: object) -> object:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return value
