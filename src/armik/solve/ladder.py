"""A globally planned path (``solve_path(..., plan="global")``): a ladder graph, as
ROS-Industrial's Descartes builds it, over every solution at every waypoint.

The rungs of a waypoint are every verified branch of its closed form (``solve_all``); a
joint whose limits allow more than one turn takes, at each step, the value of its branch
2 pi turns away that lies within the limits nearest the previous rung. An edge joins two
consecutive rungs where no joint moves by more than ``max_joint_step``; dynamic
programming keeps, for every rung, the least total joint motion (the sum of the steps'
Euclidean norms) from q0, and the path is read back from the best last rung. Where no edge
leaves a waypoint's rungs, every path breaks there: the waypoint is ``discontinuous`` with
the joint and the size of the smallest possible jump, and the plan goes on from every rung
after it. The first step is held to ``max_joint_step`` from q0 as every other; without q0
the path may start on any rung.
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np

from armik import reasons
from armik.batch_result import BatchResult
from armik.errors import OptionError
from armik.model.arm_model import ArmModel
from armik.result import IKResult
from armik.solve.prefer import turns
from armik.solvers.registry import SolverSpec
from armik.status import Status

TWO_PI = 2.0 * math.pi
MAX_STATES = 4096  # rungs kept per waypoint (the cheapest), after merging equal ones


def check_plannable(spec: SolverSpec) -> None:
    """A ladder needs every solution of every waypoint: a closed form's."""
    if spec.kind == "numeric":
        raise OptionError(
            f"plan='global' needs every solution at every waypoint, which the numeric solver "
            f"{spec.name!r} does not give: use plan='follow', or on a 7-joint arm hold a "
            "joint (arm.with_locked) so that a closed form applies",
            option="plan",
            value="global",
        )


def _moves(arm: ArmModel, Q: np.ndarray, B: np.ndarray) -> np.ndarray:
    """(S, m, dof): each branch of ``B`` (m, dof) turned, joint by joint, to its value
    within the limits nearest each state of ``Q`` (S, dof); nan where none is."""
    lower, upper, no_period = arm._limit_lists
    lo, hi = np.asarray(lower), np.asarray(upper)
    periodic = ~np.asarray(no_period, dtype=bool)
    D = Q[:, None, :] - B[None, :, :]
    k = np.where(periodic, np.round(D / TWO_PI), 0.0)
    best = np.full(D.shape, np.nan)
    for shift in (0.0, -1.0, 1.0):
        C = B[None, :, :] + TWO_PI * np.where(periodic, k + shift, 0.0)
        inside = (C >= lo - 1e-12) & (C <= hi + 1e-12)
        closer = np.isnan(best) | (np.abs(C - Q[:, None, :]) < np.abs(best - Q[:, None, :]))
        best = np.where(inside & closer, C, best)
    return best


def _merge(C: np.ndarray, cost: np.ndarray, parent: np.ndarray, rung: np.ndarray):
    """Equal configurations (to 1e-9) merged, the cheapest kept; at most ``MAX_STATES``."""
    order = np.argsort(cost, kind="stable")
    keys = np.round(C[order], 9)
    _, first = np.unique(keys, axis=0, return_index=True)
    keep = order[np.sort(first)][:MAX_STATES]
    keep = keep[np.argsort(cost[keep], kind="stable")][:MAX_STATES]
    return C[keep], cost[keep], parent[keep], rung[keep]


def plan(
    arm: ArmModel,
    rungs: list[list[IKResult]],
    q0: np.ndarray | None,
    step: np.ndarray,
    out: BatchResult,
) -> None:
    """The least-motion path over ``rungs`` (each waypoint's ``solve_all`` results) from
    ``q0`` (None: from any rung of the first waypoint), into ``out``'s rows."""
    n = len(rungs)
    Q, cost = (np.empty((0, arm.dof)), np.zeros(0)) if q0 is None else (q0[None, :], np.zeros(1))
    layers: list = []  # per waypoint: (states, parent state, rung index, rungs) or None
    broken: dict[int, str] = {}
    for i in range(n):
        good = [r for r in rungs[i] if r.success]
        if not good:
            layers.append(None)  # unreachable: the path goes on from the states before
            continue
        B = np.array([np.asarray(r.q) for r in good])
        if len(Q) == 0:  # no q0, or nothing reached yet: every rung, every turn, starts one
            starts = [(np.array(c), b) for b, r in enumerate(good) for c in _variants(arm, r.q)]
            C0 = np.array([c for c, _ in starts])
            rung0 = np.array([b for _, b in starts])
            Q, cost, parent, rung = _merge(C0, np.zeros(len(C0)), np.zeros(len(C0), int), rung0)
            layers.append((Q, parent, rung, good))
            continue
        C = _moves(arm, Q, B)
        moved = np.abs(C - Q[:, None, :])
        ratio = np.nanmax(moved / step, axis=2)
        ok = ~np.isnan(C).any(axis=2) & (ratio <= 1.0)
        if not ok.any():
            broken[i] = _why(arm, moved, ratio, step, i == 0 or all(x is None for x in layers))
            ok = ~np.isnan(C).any(axis=2)
        s_idx, b_idx = np.nonzero(ok)
        new = C[s_idx, b_idx]
        new_cost = cost[s_idx] + np.linalg.norm(new - Q[s_idx], axis=1)
        Q, cost, parent, rung = _merge(new, new_cost, s_idx, b_idx)
        layers.append((Q, parent, rung, good))
    _read_back(layers, rungs, cost, broken, out)


def _variants(arm: ArmModel, q) -> list[tuple[float, ...]]:
    """``q`` and its 2 pi turns within the limits, joint by joint, combined."""
    return list(itertools.islice(itertools.product(*turns(arm, np.asarray(q))), MAX_STATES))


def _why(arm: ArmModel, moved, ratio, step, first: bool) -> str:
    ratio = np.where(np.isnan(ratio), np.inf, ratio)
    s, b = np.unravel_index(int(np.argmin(ratio)), ratio.shape)
    j = int(np.nanargmax(moved[s, b] / step))
    unit = "m" if arm.prismatic[j] else "rad"
    start = "q0 (the start)" if first else "every solution of the waypoint before"
    return (
        f"every path breaks here: from {start}, the smallest possible jump moves "
        f"{arm.joint_names[j]} by {moved[s, b, j]:.3g} {unit} (max_joint_step {step[j]:g})"
    )


def _read_back(layers, rungs, cost, broken: dict[int, str], out: BatchResult) -> None:
    state = int(np.argmin(cost)) if len(cost) else 0
    for i in range(len(layers) - 1, -1, -1):
        layer = layers[i]
        if layer is None:  # no solution at all: the waypoint's own failure
            out.put_result(i, rungs[i][0])
            out.reasons[i] = rungs[i][0].reason
            continue
        Q, parent, rung, good = layer
        r = good[int(rung[state])]
        r = dataclasses.replace(r, q=Q[state])  # a turn of 2 pi: the same verified pose
        if i in broken:
            measured = reasons.measured(
                r.position_error, r.orientation_error, out.tol_position, out.tol_orientation
            )
            r = dataclasses.replace(
                r,
                success=False,
                status=Status.DISCONTINUOUS,
                reason=f"reachable only by a jump: {broken[i]}; q is the planned answer, "
                f"verified: {measured}",
            )
        else:
            r = dataclasses.replace(r, reason=f"{r.reason}; planned over every branch")
        out.put_result(i, r)
        if not r.success:
            out.reasons[i] = r.reason
        state = int(parent[state])
