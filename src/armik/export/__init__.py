"""``armik.export``: an arm's closed form as a self-contained C99 solver (``N_ik.h``,
``N_ik.c``; with ``ikfast=True`` also ``N_ikfast.cpp``, IKFast 61's interface).

The C is written from the same family description the Python solver runs on (its
``classify``), one module a family: ``three_parallel``, ``spherical_wrist``,
``three_parallel_general``, ``spherical_general``, ``spherical_shoulder`` (read from the
tip as a spherical wrist), ``planar2r``, and ``swept_7r`` (a 7R arm with joint 7 held:
``N_ik`` takes its value); ``solver_file`` adds what every family shares
(2 pi shifts, limits, the verdict, the order), ``c_source`` the subproblems SP1-SP4,
``c_roots`` and ``c_subproblems_56`` SP5 and SP6. An arm whose ``solve_all`` is not one of
those closed forms (and not a 7R arm ``swept_7r`` holds) is refused with a ``SolverError``
saying why each family does not apply, and naming a search ``solve_all`` would run.
"""

from __future__ import annotations

import math
import os
import re
import secrets
from collections.abc import Callable
from pathlib import Path

from armik.errors import OptionError, SolverError
from armik.export import ikfast as ikfast_file
from armik.export import (
    planar2r,
    solver_file,
    spherical_general,
    spherical_shoulder,
    spherical_wrist,
    swept_7r,
    three_parallel,
    three_parallel_general,
)
from armik.model.arm_model import ArmModel, model_of
from armik.model.geometry import axis_lines
from armik.solve.read import options as read_options
from armik.solvers import registry

# solver name -> the family's C rows, in the order a refusal lists them
FAMILIES: dict[str, Callable] = {
    "three_parallel": three_parallel.rows,
    "spherical": spherical_wrist.rows,
    "three_parallel_general": three_parallel_general.rows,
    "spherical_general": spherical_general.rows,
    "spherical_shoulder": spherical_shoulder.rows,
    "planar2r": planar2r.rows,
    "swept": swept_7r.rows,  # a 7R arm with joint 7 held: N_ik takes its value
}
HELD_FAMILY = "swept"  # not solve_all's choice: the family of hold= on joint 7
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def family(arm: ArmModel) -> str:
    """The exported family of ``arm``: the solver ``solve_all`` chooses, when it is one
    ``FAMILIES`` writes. ``SolverError`` otherwise, with each family's reason (``armik
    info``'s)."""
    try:
        chosen = registry.choose("auto", arm, every=True).name
    except SolverError:
        chosen = None
    if chosen in FAMILIES:
        return chosen
    if registry.why_not(HELD_FAMILY, arm) is None:
        return HELD_FAMILY
    why = "; ".join(f"{name}: {registry.why_not(name, arm)}" for name in FAMILIES)
    spec = registry.get(chosen) if chosen is not None else None
    if spec is not None and not spec.complete:  # armik info: "(every solution, a search)"
        chosen_text = f"{chosen!r}, every solution by a search ({spec.summary}), not exported"
    else:
        chosen_text = repr(chosen)
    raise SolverError(
        f"arm {arm.name!r} has no closed form to export (solve_all chooses {chosen_text}): {why}",
        solver=str(chosen),
        candidates=list(FAMILIES),
    )


def export(
    arm: object,
    name: str,
    out: str | Path | None = None,
    ikfast: bool = False,
    tol_position: float | None = None,
    tol_orientation: float | None = None,
) -> dict[str, str]:
    """The C solver of ``arm`` (an ``Arm`` or its model) as {file name: text}:
    ``name_ik.h``, ``name_ik.c`` and, with ``ikfast``, ``name_ikfast.cpp``; written into the
    directory ``out`` (created if missing) when given. ``tol_position`` (m) and
    ``tol_orientation`` (rad): how far a solution's FK may miss its target (armik's
    verification tolerances by default, 1e-6 m and 1e-6 rad, as ``solve_all`` verifies).

    Files of the same names in ``out`` are replaced, all of them or none: each is written
    to a temporary file beside it and renamed once every one is written; a folder the
    export created is removed when writing fails.

    Raises ``OptionError`` when ``name`` is not a C identifier or one C reserves, a
    tolerance is not a number of at least 1e-12 (``tolerances.MIN_TOLERANCE``), ``out``
    is not a path or ``ikfast`` not a bool, ``SolverError`` when the arm's ``solve_all`` is not an
    exported closed form, ``OptionError`` when ``out`` is a file or cannot be written."""
    model = model_of(arm)
    _check_name(name)
    path = os.fspath(out) if isinstance(out, (str, os.PathLike)) else None
    if out is not None and not isinstance(path, str):  # a bytes path is no folder here
        raise OptionError(
            f"out must be a folder's path (a str or a Path) or None, got {out!r}",
            option="out",
            value=out,
        )
    if path is not None and "\0" in path:  # no file system takes one
        raise OptionError(
            f"out={path!r} holds a null character, which no path can: give a folder's "
            "path without one",
            option="out",
            value=out,
        )
    if not isinstance(ikfast, bool):
        raise OptionError(
            f"ikfast must be True or False, got {ikfast!r}", option="ikfast", value=ikfast
        )
    tolerances = {"tol_position": tol_position, "tol_orientation": tol_orientation}
    # below tolerances.MIN_TOLERANCE refused there, as every route refuses it
    opts = read_options({k: v for k, v in tolerances.items() if v is not None})
    rows_of = FAMILIES[family(model)]
    ax = axis_lines(model)
    rows = rows_of(model, ax)
    c_text = solver_file.source(name, model, ax, rows, opts)
    header = solver_file.header(
        name, model.dof, rows.max_rows, rows.summary, opts.tol_position, opts.tol_orientation,
        rows.held,
    )  # fmt: skip
    files = {
        f"{name}_ik.h": header,
        f"{name}_ik.c": c_text,
    }
    if ikfast:
        limits = (
            (float(model.lower[rows.held]), float(model.upper[rows.held]))
            if rows.held is not None
            else (-math.inf, math.inf)
        )
        files[f"{name}_ikfast.cpp"] = ikfast_file.source(name, c_text, rows.held, limits)
    if out is not None:
        _write(Path(out), files)
    return files


def _check_name(name: object) -> None:
    """``OptionError`` unless ``name`` is a C identifier that is not reserved: no leading
    underscore (the header's macros are the name in upper case, and ``_X``... is the
    compiler's) and no ``__`` (C++ reserves it anywhere, and the header is read as C++)."""
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise OptionError(
            f"name must be a C identifier (letters, digits, _), got {name!r}",
            option="name",
            value=name,
        )
    if name.startswith("_") or "__" in name:
        raise OptionError(
            f"name {name!r} is reserved in C or C++ (a leading underscore, whose upper "
            "case names the header's macros, or a double underscore): give a name that "
            "starts with a letter and has no '__'",
            option="name",
            value=name,
        )


def _write(folder: Path, files: dict[str, str]) -> None:
    """``files`` written into ``folder`` (created if missing), all or none: each to a
    temporary file in ``folder``, renamed onto its name once all are written; an existing
    file of one of those names that is not a writable regular file refuses the whole
    export before anything is written, and a failure removes the temporaries and the
    folders this call created. ``OptionError`` naming the path when it cannot be written."""
    created = [p for p in (folder, *folder.parents) if not p.exists()]
    written: dict[Path, Path] = {}
    try:
        folder.mkdir(parents=True, exist_ok=True)
        for file in files:
            target = folder / file
            if target.exists() and not (target.is_file() and os.access(target, os.W_OK)):
                raise PermissionError(13, "not a file it can replace", str(target))
        for file, text in files.items():
            temporary = folder / f".{file}.{os.getpid()}.{secrets.token_hex(4)}.tmp"
            # O_EXCL: a new file, with the mode (umask applied) open() gives any file
            fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            written[folder / file] = temporary
            with os.fdopen(fd, "w", encoding="utf-8") as stream:  # not the locale's
                stream.write(text)
        for target, temporary in written.items():
            os.replace(temporary, target)
    except OSError as exc:
        for temporary in written.values():
            temporary.unlink(missing_ok=True)
        for path in created:  # deepest first: only those this call made, if still empty
            try:
                path.rmdir()
            except OSError:
                break
        raise OptionError(
            f"out={str(folder)!r} cannot hold the exported files "
            f"({exc.strerror or exc}{': ' + repr(exc.filename) if exc.filename else ''}): "
            "give a folder, new or existing, that you can write to; nothing was written",
            option="out",
            value=str(folder),
        ) from None
