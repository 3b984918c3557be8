"""Commands on many targets: ``batch`` (from a file, on every core or a Dask cluster),
``path`` (waypoints in order, followed or planned over every branch) and ``reach`` (a
reachability map)."""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from armik.errors import InputError
from armik.solve.batch import solve_batch
from armik.solve.path import solve_path
from armik.solve.reach import reachability
from armik.solve.read import read_batch, read_path
from armik.tools.cli.arms import load_arm, solve_options


def read_targets_file(path: str) -> tuple[np.ndarray, np.ndarray | None]:
    """The targets array of a .npy, .npz or .csv file, and the seeds if the file has them.

    Raises ``InputError`` with one line naming the file and the problem."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"targets file {path!r} does not exist (or is not a file)")
    suffix = p.suffix.lower()
    q0 = None
    try:
        if suffix == ".npy":
            arr = np.load(p, allow_pickle=False)
        elif suffix == ".npz":
            with np.load(p, allow_pickle=False) as z:
                names = list(z.files)
                arr = z[_targets_key(path, names)]
                q0 = z["q0"] if "q0" in names else None
        elif suffix == ".csv":
            arr = _read_csv(p)
        else:
            raise InputError(f"targets file {path!r}: give a .npy, .npz or .csv file")
    except InputError:
        raise
    except (OSError, ValueError, EOFError) as exc:
        if "allow_pickle" in str(exc):  # numpy's advice to unpickle: not armik's to relay
            raise InputError(_not_numbers(p, path)) from None
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"cannot read targets from {path!r}: {first}") from None
    if arr.ndim == 1 or arr.shape == (4, 4):  # a file of one target: a batch of one
        arr = arr[None]
    if arr.ndim == 2 and arr.shape[1] == 16:
        arr = arr.reshape(-1, 4, 4)
    return arr, q0


def _not_numbers(p: Path, path: str) -> str:
    """Why numpy would only unpickle ``p``: not numpy's file at all, or an array of Python
    objects in one (which armik does not load: unpickling runs the file's code)."""
    with p.open("rb") as f:
        start = f.read(6)
    if start == b"\x93NUMPY" or start.startswith(b"PK"):
        return (
            f"targets file {path!r} holds an array of Python objects, which armik does not "
            "load: save the targets as numbers (a float array)"
        )
    kind = p.suffix.lower()
    how = "numpy.save" if kind == ".npy" else "numpy.savez"
    return (
        f"targets file {path!r} is not a valid {kind} file (numpy's {kind} format): write "
        f"it with {how}, or give the targets as a .csv file"
    )


def _targets_key(path: str, names: list[str]) -> str:
    """The array of an .npz file that holds the targets: 'targets', or numpy's 'arr_0' of
    ``np.savez(path, array)``; ``InputError`` naming the arrays armik does not read (a
    misspelt 'q0' would otherwise leave the seeds out without a word)."""
    reads = "armik reads the targets from 'targets' and per-target seeds from 'q0'"
    others = [n for n in names if n != "q0"]
    key = "targets" if "targets" in names else "arr_0" if others == ["arr_0"] else None
    if key is None:
        raise InputError(
            f"{path!r} holds the arrays {names}: {reads}; name the targets array 'targets' "
            "(np.savez(path, targets=..., q0=...))"
        )
    unread = [n for n in others if n != key]
    if unread:
        raise InputError(
            f"{path!r} holds arrays armik does not read: {unread}; {reads}: rename them "
            "or leave them out"
        )
    return key


def _read_csv(path) -> np.ndarray:
    """The rows of numbers of a .csv file. Skipped: blank lines, lines starting with '#', a
    byte-order mark, and a first line that is a header (no field of it a number, such as
    x,y,z); any other line that is not numbers is refused by its line number in the file."""
    with open(path, newline="", encoding="utf-8-sig") as f:
        lines = [
            (n, r)
            for n, r in enumerate(csv.reader(f), start=1)
            if any(v.strip() for v in r) and not r[0].lstrip().startswith("#")
        ]
    header = None
    if lines and not any(map(_numbers, lines[0][1])):
        header, lines = lines[0][1], lines[1:]  # a header line: names, no number
    if not lines:
        line = "" if header is None else f": its one line, {','.join(header)[:80]!r}, is no"
        raise ValueError(
            f"the file holds no rows of numbers{line}{' row of numbers' if line else ''}; "
            "write one target a line, its numbers separated by commas (x,y,z)"
        )
    for n, r in lines:
        if not all(_numbers(v) and len(v.split()) == 1 for v in r):
            raise ValueError(f"line {n} is not numbers: {','.join(r)[:80]!r}; {_fix(r)}")
    widths = {len(r) for _, r in lines}
    if len(widths) > 1:
        raise ValueError(f"rows have different numbers of columns: {sorted(widths)}")
    return np.array([[float(v) for v in r] for _, r in lines], dtype=float)


def _numbers(field: str) -> bool:
    """Whether ``field`` is one number or several separated by spaces."""
    try:
        return bool([float(v) for v in field.split()])
    except ValueError:
        return False


def _fix(row: list[str]) -> str:
    """What to do about a row of a .csv file that is not numbers."""
    if any(_numbers(v) and len(v.split()) > 1 for v in row):
        return "separate the numbers with commas (x,y,z), not spaces"
    if any(not v.strip() for v in row):
        return "a field is empty: give one number in each, separated by commas"
    return "give one target a line, its numbers separated by commas (x,y,z)"


def cmd_batch(args: argparse.Namespace) -> int:
    out = _output(args.output)
    arm = load_arm(args).kinematics
    targets, q0 = read_targets_file(args.targets)
    if args.q0 is not None:
        q0 = np.array(args.q0)
    options = solve_options(args)
    if args.cluster:
        from armik.solve import distributed  # Dask: a second to import, only for a cluster

        result = distributed.solve_batch(
            arm,
            targets,
            q0=q0,
            solver=args.solver,
            address=args.cluster,
            chunk_size=args.chunk_size,
            **options,
        )
    else:
        request = read_batch(arm, targets, q0, args.solver, options)
        result = solve_batch(arm, request, args.workers, args.chunk_size)
    return _written(result, out)


def _output(path: str) -> Path:
    out = Path(path)
    if out.suffix.lower() != ".npz":
        raise InputError(f"output {path!r}: results are written as .npz; name it *.npz")
    if not out.parent.is_dir():
        raise InputError(f"output folder {str(out.parent)!r} does not exist")
    return out


def path_start(path, in_file, given) -> np.ndarray | None:
    """A path's start: ``--q0`` (``given``), else the waypoints file's 'q0' (``in_file``),
    which is one configuration; else None."""
    if given is not None:  # as on batch, --q0 in place of the file's
        return np.array(given)
    if in_file is not None and in_file.ndim != 1:
        raise InputError(
            f"{str(path)!r}: its array 'q0' has shape {in_file.shape}, but a path starts from "
            "one configuration: save q0 as one value per joint, or give --q0"
        )
    return in_file


def cmd_path(args: argparse.Namespace) -> int:
    out = _output(args.output)
    arm = load_arm(args).kinematics
    targets, q0 = read_targets_file(args.targets)
    q0 = path_start(args.targets, q0, args.q0)
    request, local = read_path(arm, targets, q0, args.solver, args.plan, solve_options(args))
    result = solve_path(arm, request, local, args.max_joint_step, args.plan)
    return _written(result, out)


def _written(result, out: Path) -> int:
    result.save(out)
    print(result.summary())
    print(f"wrote {out}")
    return 0


def cmd_reach(args: argparse.Namespace) -> int:
    out = _output(args.output)  # both paths checked before the run, not after it
    if args.plot and not Path(args.plot).parent.is_dir():
        raise InputError(f"plot folder {str(Path(args.plot).parent)!r} does not exist")
    if args.plot:  # the map's figure: a missing matplotlib said now, not after the run
        try:
            import matplotlib  # noqa: F401  (first: its submodules may be loaded already)
            from matplotlib.figure import Figure
        except ImportError:
            raise InputError(
                '--plot draws with matplotlib, which is not installed: pip install "armik[plot]"'
            ) from None
        kind = Path(args.plot).suffix[1:].lower()
        kinds = Figure().canvas.get_supported_filetypes()
        if not kind:  # matplotlib writes name.png: the file said written is the one written
            args.plot = str(Path(args.plot).with_suffix(".png"))
        elif kind not in kinds:
            raise InputError(
                f"--plot {args.plot!r}: matplotlib writes no .{kind} file: name it .png, or "
                f"one of {', '.join('.' + k for k in sorted(kinds))}"
            )
    arm = load_arm(args).kinematics
    client = None
    if args.cluster:
        from armik.solve import distributed  # Dask: a second to import, only for a cluster

        client = distributed.connect(args.cluster)
    try:
        m = reachability(
            arm,
            args.resolution,
            args.orientations,
            solver=args.solver,
            workers=args.workers,
            seed=args.seed,
            client=client,
            timeout=args.timeout,
        )
    finally:
        if client is not None:
            distributed.close(client)
    print(m.summary())
    print(f"wrote {m.save(out)}")
    if args.plot:
        print(f"wrote {m.plot(args.plot)}")
    return 0
