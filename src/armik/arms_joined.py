"""One result for a robot of several tips (``armik.Arms``) from each chain's own: the
joints side by side, a success only when every tip is verified, the reason naming each
tip that failed, the errors the distances to the targets with what a region or weights
measured beside them (``measured``), and the nearest of the chains' closest pairs where
they checked collisions (``min_distance``, ``closest_pair``), as one arm's result has
them."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from armik import reasons
from armik.arms_options import chain_constraints
from armik.arms_tasks import by_tip
from armik.result import IKResult
from armik.status import Status


def joined(tips, results: dict[str, IKResult], seeds, elapsed: float) -> IKResult:
    """One result over every joint from each tip's (``results``; a tip not solved keeps its
    seed): a success when every tip's is, the first failing tip's status, the worst errors,
    each tip's errors and result in ``extra``."""
    # one pass over the tips, on each result's fields read once: this runs on every solve
    # of a cell, beside two closed-form solves of a few microseconds each
    parts, failed, errors = [], [], {}
    solvers: dict[str, None] = {}  # the solvers' names, in order, once each
    iterations = restarts = 0
    position: float | None = None  # None: no tip's target holds a position
    orientation, singular = None, False
    measured = False  # some tip's request measured other than its distances (a region)
    near = None  # the closest pair some tip's collision check found: (distance, pair)
    for tip in tips:
        r = results.get(tip)
        if r is None:
            parts.append(seeds[tip])
            continue
        d = r.__dict__
        parts.append(d["q"])
        solvers[d["solver"]] = None
        if not d["success"]:
            failed.append(tip)
        pos, ori = d["position_error"], d["orientation_error"]
        errors[tip] = (pos, ori)
        iterations += d["iterations"]
        restarts += d["restarts"]
        if pos is not None and (position is None or pos > position):
            position = pos
        if ori is not None and (orientation is None or ori > orientation):
            orientation = ori
        singular = singular or d["singular"]
        extra = d["extra"]
        measured = measured or "measured" in extra
        if "min_distance" in extra and (near is None or extra["min_distance"] < near[0]):
            near = (extra["min_distance"], extra.get("closest_pair"))
    q = np.concatenate(parts)
    q.setflags(write=False)  # a result's q is read-only; setflags is the cheaper spelling
    out = IKResult._from_fields(
        {
            "q": q,
            "success": not failed,
            "status": results[failed[0]].status if failed else _CONVERGED,
            "_reason": (_reason, (results, failed)),  # written on first read, as prepared's
            "solver": "+".join(solvers),
            "iterations": iterations,
            "position_error": position,
            "orientation_error": orientation,
            "time": elapsed,
            "branch": None,
            "singular": singular,
            "restarts": restarts,
        }
    )
    out.__dict__["extra"] = {"errors": errors, "results": results}
    if measured:  # beside the true distances, what the verdicts measured: the worst tip's
        out.__dict__["extra"]["measured"] = _measured(results.values())
    if near is not None:  # each chain checked its own links: the robot's, the nearest
        out.__dict__["extra"].update(min_distance=near[0], closest_pair=near[1])
    return out


def _measured(results) -> tuple[float, float | None]:
    """The worst of what each result's verdict measured (its distances where it measured
    them alone), as one result's ``measured`` over several tasks."""
    position, orientation = 0.0, None
    for r in results:
        pos, ori = r.measured or (r.position_error, r.orientation_error)
        position, orientation = max(position, pos), worse(orientation, ori)
    return position, orientation


_CONVERGED = Status.CONVERGED


def _reason(results: dict[str, IKResult], failed: list[str]) -> str:
    """A joined result's reason: each failing tip's, else the solver of each tip."""
    if failed:
        return "; ".join(f"{t}: {results[t].status.value}: {results[t].reason}" for t in failed)
    return "every tip verified: " + "; ".join(f"{t} by {r.solver}" for t, r in results.items())


def worse(a: float | None, b: float | None) -> float | None:
    """The larger of two errors, either of which may be unmeasured (None)."""
    return b if a is None else a if b is None else max(a, b)


def by_tip_errors(tips, measured, true) -> tuple[dict[str, tuple], list[str]]:
    """({tip: (position, orientation)}, the tips not within their tasks) from the tasks of
    a solve over every joint, each given by its tip (``tips``: one a task, an elbow's task
    counted in its tip's, as a chain solved alone counts it), ``measured`` by the verdict
    (``task_errors``) and ``true``: their centres' distances, the worse of a tip's tasks."""
    errors: dict[str, tuple] = {}
    failed: list[str] = []
    for tip, e, d in zip(tips, measured, true):
        if tip in errors:  # a tip's second task: its worse errors
            pos, ori = errors[tip]
            errors[tip] = (worse(pos, d.position), worse(ori, d.orientation))
        else:
            errors[tip] = (d.position, d.orientation)
        if not e.within and tip not in failed:
            failed.append(tip)
    return errors, failed


def left_out(arms: Any, options: dict, targets: object) -> list[tuple[str, Any]]:
    """(tip, constraint) of each constraint given by tip (``constraints={tip: [...]}``) on
    chains that share no joint whose tip ``targets`` leave out: no chain's solve checks
    it, and that chain keeps q0's values (``held``, ``held_rows`` check them)."""
    own = chain_constraints(options, arms.tips) if "constraints" in options else None
    if not own or arms._union is not None:
        return []
    tips = by_tip(arms._chains, targets)
    solved = set(tips) if isinstance(tips, Mapping) else set(arms.tips)
    return [(tip, c) for tip, given in own.items() if tip not in solved for c in given]


def held(arms: Any, r: IKResult, checks: list[tuple[str, Any]]) -> IKResult:
    """``r``, or where a constraint of a tip left out (``left_out``) fails at its values in
    ``r.q``, the failure its check says, naming the tip."""
    if not r.success or not checks:
        return r
    for tip, c in checks:
        arm, q = arms._chains[tip], np.asarray(r.q, dtype=float)[arms._columns[tip]]
        found = c.at(arm, q).check(arm, q[None, :])
        if not found.ok[0]:
            why = reasons.left_out_fails(tip, found.why(0))
            return dataclasses.replace(r, success=False, status=found.status, reason=why)
    return r


def held_rows(arms: Any, out: Any, checks: list[tuple[str, Any]]) -> None:
    """``held`` on every successful row of ``out`` (a joined ``BatchResult``), in place."""
    for tip, c in checks:
        arm, cols = arms._chains[tip], arms._columns[tip]
        rows = np.flatnonzero(out.success)
        if not len(rows):
            return
        Q = np.ascontiguousarray(out.q[rows][:, cols])
        found = c.at(arm, Q[0]).check(arm, Q)
        for k in np.flatnonzero(~found.ok).tolist():
            i = int(rows[k])
            out.success[i] = False
            out.status_code[i] = found.status.code
            out.reasons[i] = reasons.left_out_fails(tip, found.why(k))
