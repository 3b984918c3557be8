"""A globally planned path (``solve_path(..., plan="global")``): a ladder graph, as
ROS-Industrial's Descartes builds it, over every solution at every waypoint.

The rungs of a waypoint are every verified branch of its closed form (``solve_all``), or
on other arms the answers ``armik.solve.rungs`` gathers (a search's, a sweep's, the 7R
sweep's samples, the numeric solver's tracks: there a break is one no path through the
answers found passes, and says so); a joint whose limits
allow more than one turn takes, at each step, the value of its branch 2 pi turns away
that lies within the limits nearest the previous rung. An edge joins two
consecutive rungs where no joint moves by more than ``max_joint_step``; dynamic
programming keeps, for every rung, the least total joint motion (the sum of the steps'
Euclidean norms) from q0, and the path is read back from the best last rung. Where no edge
leaves a waypoint's rungs, every path breaks there: the waypoint is ``discontinuous`` with
the joint and the size of the smallest possible jump, and the plan goes on from every rung
after it, at every turn within the limits. The first step is held to ``max_joint_step``
from q0 as every other; without q0 the path may start on any rung.

A step within the bound may still hide a jump between its waypoints (a wrist swinging
through half a turn near a singularity, a joint out of its limits or the pose out of reach
halfway). Each step the plan takes is judged by the rule a followed path's steps are
judged by too (``_jumps``, ``hidden_steps``): a small, straight step passes (``_chord``:
no joint over ``BEND`` of the bound, the tip of the joints moved straight within ``CHORD``
of the step's motion of the pose halfway, ``straight``: beside a singularity the solutions
halfway swing, the motion does not); any other is checked halfway, on the pose with the
translation halved and the rotation halved along its geodesic (``poses_halfway``): a
solution there must lie within
``max_joint_step`` of both ends, as it must if a waypoint were added halfway: the solver's
nearest the step's middle, or for a sweep's or a search's solver, which may miss it, one
found by numeric descents from the middle, each end and about the middle (``_descended``,
``_starts``). Where that solution bends more than ``BEND`` of the bound away from the
step's middle, both halves are checked the same way, ``DEPTH`` rounds at most. A step that
fails is taken out, with every other step onto its waypoint that fails, and the path is
planned again until every step taken passes; a waypoint that every path reaches only
through such a step is ``discontinuous``. Only the steps taken are checked, each round in
one compiled call. With a joint held (``hold=``) the halfway poses are solved as the rungs
are, the joint held (``rungs.every_answer``), one by one: the solver alone would check the
looser problem with the joint free.
Collisions, when asked for, act through the rungs: ``solve_all`` with the same options
marks a colliding branch failed, and a failed branch is no rung.
"""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pinocchio as pin

from armik import path_reasons
from armik.batch_result import BatchResult
from armik.kernel import ladder as kernel
from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings
from armik.request import Request
from armik.result import IKResult
from armik.solve.halfway import _Halfway, _loose, _nearest, searched, within
from armik.solve.ladder_breaks import broken_at, went_on_from
from armik.solve.prefer import continuous_turned, turns
from armik.solve.turning import ANY, Turning
from armik.solvers import registry
from armik.solvers.registry import SolverSpec
from armik.status import Status
from armik.targets.batch import TargetBatch

TIE = 1e-6  # with a preference: the motion's weight beside the scores, a tie-break
BEND = 0.125  # of max_joint_step: a halfway solution this far off the middle: halves checked
DEPTH = 3  # rounds of halving at most: the poses at 1/2, then 1/4 and 3/4, then the eighths
STEP_EDGE = 1e-9  # rad or m: a planned step this far over max_joint_step is on it
CHORD = 1 / 32  # of a step's tip motion: the straight joint motion's tip this far off halfway


def plan(
    arm: ArmModel,
    spec: SolverSpec,
    targets: TargetBatch,
    rungs: list[list[IKResult]],
    q0: np.ndarray | None,
    step: np.ndarray,
    opts: SolverSettings,
    out: BatchResult,
    score=None,
    reference: np.ndarray | None = None,
    turn: Turning = ANY,
    held: Request | None = None,
) -> set[str]:
    """The least-motion path over ``rungs`` (each waypoint's ``solve_all`` results for
    ``targets``, by ``spec``) from ``q0`` (None: from any turn of any rung of the first
    waypoint), every step taken checked halfway, into ``out``'s rows (the dynamic
    programming in ``armik.kernel.ladder``). With ``score``: the continuous path of the
    least summed score against ``reference``, the motion breaking ties (``TIE``). Only the
    turns ``turn`` allows: no held joint turns, and a turned rung passes the checks.
    ``held``: the path's request where it holds a joint (``hold=``): each halfway pose is
    solved as its rungs were, held (``rungs.every_answer``), not by ``spec`` alone, which
    would check the looser problem with the joint free. Returns the solvers the results it
    placed name (a held joint's rungs may come from another solver than ``spec``:
    ``armik.solve.held``)."""
    good = [[r for r in rs if r.success] for rs in rungs]
    lower, upper, no_period = arm._limit_lists
    periodic = ~np.array(no_period, dtype=bool) & turn.free(arm.dof)
    if (score is not None and score.turns_matter) or _turns_checked(arm, good, turn):
        good = [[t for r in g for t in _turns(arm, r, turn)] for g in good]  # each turn a rung
        # the limited joints' turns are rungs now (scored, checked); an unlimited one the
        # dynamic programming still turns next to the previous rung, its score as given
        periodic &= ~(np.isfinite(arm.lower) & np.isfinite(arm.upper))
    offs = np.zeros(len(rungs) + 1, dtype=np.int64)
    offs[1:] = np.cumsum([len(g) for g in good])
    B = np.array([np.asarray(r.q) for g in good for r in g]).reshape(-1, arm.dof)
    node, weight = np.zeros(len(B)), 1.0
    if score is not None:  # the score decides, the motion breaks its ties
        # a continuous joint scored at its best turn: the programming turns it next to the
        # previous rung, and a first rung without a start stays as turned here
        if reference is not None:
            B = continuous_turned(arm, B, score, reference, turn)
        node = score.many(arm, B, reference)
        weight = TIE
    start = np.zeros(arm.dof) if q0 is None else np.asarray(q0, dtype=float)
    args = (
        B, offs, start, q0 is not None, np.array(lower), np.array(upper), periodic,
        np.asarray(step, dtype=float),
    )  # fmt: skip
    half = _Halfway(spec, opts, targets, held, turn)
    (rung, Q, broken, hidden, joint, size), forbidden = _checked(arm, half, args, node, weight)
    free = periodic & np.isneginf(arm.lower) & np.isposinf(arm.upper)  # no limits: any turn
    if score is not None and score.turns_matter and free.any() and len(B):  # jumps: as scored
        _restarted(arm, Q, B[np.maximum(rung, 0)], rung >= 0, broken, free, turn)
    first = True
    placed: set[str] = set()
    for i, rs in enumerate(rungs):
        if rung[i] < 0:  # no solution: its own failure (else held to the step below)
            out.put_result(i, rs[0])
            out.reasons[i] = rs[0].reason
            placed.add(rs[0].solver)
            continue
        r = good[i][int(rung[i] - offs[i])]
        placed.add(r.solver)
        if broken[i]:
            j = int(joint[i])
            # every solution only from a complete closed form: a search, a sweep, a
            # sample of the self-motion (a swivel's too) or a numeric solver's tracks show
            # the answers found
            every = spec.kind != "numeric" and spec.complete and spec.parameter is None
            onto = _onto(i, B, offs, start, args[4:7], step)[2]
            r = broken_at(
                arm, r, j, float(size[i]), float(step[j]), bool(hidden[i]), first, every, out,
                went_on_from(i, rung, broken, q0 is not None, first, forbidden, onto),
            )  # fmt: skip
            out.reasons[i] = r.reason
        out.put_result(i, r)  # a success's reason is the row's, written when read
        out.q[i] = Q[i]  # the rung turned by 2 pi: the same pose
        if score is not None:  # measured at the answer as given (its turns included)
            out._scores[i] = score(arm, out.q[i], reference)
        first = False
    held_to_step(arm, out, None if q0 is None else start, np.asarray(step, dtype=float))
    return placed


def _restarted(arm, Q, scored, reached, broken, free, turn: Turning) -> None:
    """With a score, a joint without limits (``free``) after a break where every path
    jumps: the dynamic programming turns it next to the answer before, but scored the rung
    at the turn the score ranks best (``scored``: each waypoint's rung as scored). The
    path from the break to the next one is turned by whole turns onto that rung's turn, in
    place in ``Q``: the same poses, the same steps between them, the jump there reported
    as it is, and the waypoint's score the one the plan chose it by. Kept where the turned
    rows pass ``turn``'s checks."""
    starts = np.flatnonzero(broken & reached).tolist()
    for a, b in zip(starts, [*starts[1:], len(Q)]):
        k = np.round((scored[a] - Q[a]) / (2.0 * np.pi)) * free
        if not k.any():
            continue
        rows = Q[a:b] + 2.0 * np.pi * k
        if not turn.checks or turn.keeps(arm, rows[reached[a:b]]).all():
            Q[a:b] = rows


def held_to_step(arm: ArmModel, out: BatchResult, start: np.ndarray | None, step) -> None:
    """Every success in ``out`` within ``step`` (rad or m, per joint) of the answer the path
    went on from (the last row before it that is a success or a jump; ``start`` for the
    first, None: the first is free): a success further than that, whatever the plan did, is
    ``discontinuous`` with the move in its reason. Never a silent jump."""
    prev, whence = start, "q0 (the start)"
    for i in range(len(out)):
        q = out.q[i]
        if out.success[i] and prev is not None:
            moved = np.abs(q - prev)
            if not (moved <= step + STEP_EDGE).all():  # NaN too
                j = int(np.nanargmax(moved / step))
                unit = "m" if arm.prismatic[j] else "rad"
                move = path_reasons.moved(arm.joint_names[j], moved.item(j), unit, whence, step[j])
                measured = path_reasons.row_verified(out, i)
                out.success[i] = False
                out.status_code[i] = Status.DISCONTINUOUS.code
                out.reasons[i] = path_reasons.jump(
                    path_reasons.planned_over(move), "the planned answer", measured
                )
        if out.success[i] or out.status_code[i] == Status.DISCONTINUOUS.code:
            prev, whence = q, "the previous waypoint's answer"


def _turns_checked(arm: ArmModel, good: list[list[IKResult]], turn: Turning) -> bool:
    """Whether some turn of some rung fails one of ``turn``'s checks: only then must each
    turn be a rung of its own. Where every turn passes (a check that reads no joint's turn,
    say), the plan may turn joints next to the previous rung as it does without checks."""
    if not turn.checks:
        return False
    every = [_every_turn(arm, r, turn) for g in good for r in g]
    return bool(every) and not turn.keeps(arm, np.concatenate(every)).all()


def _every_turn(arm: ArmModel, r: IKResult, turn: Turning) -> np.ndarray:
    """(M, dof): ``r`` at every combination of the turns ``turn`` lets its joints take."""
    return np.array(list(itertools.product(*turns(arm, np.asarray(r.q), turn))))


def _turns(arm: ArmModel, r: IKResult, turn: Turning) -> list[IKResult]:
    """``r`` at every combination of its joints' turns (``prefer.turns``: the values 2 pi
    apart within the limits) that passes ``turn``'s checks: the same pose, each scored
    apart (``r`` itself, verified, first)."""
    Q = _every_turn(arm, r, turn)
    if turn.checks:
        Q = Q[turn.keeps(arm, Q)]
    Q.flags.writeable = False
    return [dataclasses.replace(r, q=q) for q in Q]


def _checked(arm, half: _Halfway, args: tuple, node, weight):
    """``kernel.plan(*args, forbidden, node, weight)`` where no step taken hides a jump: the
    steps taken are checked, and where one fails, every other step onto its waypoint too;
    those that fail are forbidden and the path planned again, until the steps taken pass,
    each at the turn taken (at its limit a joint may leave it halfway at one turn, not at
    another). Returns the plan and the forbidden edges' codes."""
    B, offs, start, _, lower, upper, periodic, step = args
    forbidden: set[int] = set()
    clean: set[tuple[int, bytes]] = set()  # (edge code, the step's start as taken)

    def fresh(code: np.ndarray, Qa: np.ndarray) -> np.ndarray:
        keys = zip(code.tolist(), Qa)
        return np.array([c not in forbidden and (c, q.tobytes()) not in clean for c, q in keys])

    while True:
        got = kernel.plan(*args, np.array(sorted(forbidden), dtype=np.int64), node, weight)  # type: ignore[call-arg]
        rung, Q, broken = got[:3]
        i, _, code = _steps(rung, broken, len(B))
        Qa = Q[i - 1]  # never from q0: ``_steps`` leaves that move to the bound
        new = fresh(code, Qa).astype(bool).reshape(-1)
        i, code, Qa = i[new], code[new], Qa[new]
        jumped = _jumps(arm, half, i, Qa, Q[i], step)
        clean.update(zip(code[~jumped].tolist(), (q.tobytes() for q in Qa[~jumped])))
        if not jumped.any():
            return got, forbidden
        forbidden.update(code[jumped].tolist())
        for w in np.unique(i[jumped]).tolist():  # the other ways onto the waypoint
            Qa, Qb, code = _onto(w, B, offs, start, (lower, upper, periodic), step)
            new = fresh(code, Qa).astype(bool).reshape(-1)
            at = np.full(int(new.sum()), w)
            bad = _jumps(arm, half, at, Qa[new], Qb[new], step)
            forbidden.update(code[new][bad].tolist())
            clean.update(zip(code[new][~bad].tolist(), (q.tobytes() for q in Qa[new][~bad])))


def _onto(w: int, B, offs, start, limits, step):
    """(q before, q at ``w``, edge code) of every step onto waypoint ``w`` within the
    bound, each angle turned nearest the one before (kept where that is within the
    limits, as the plan turns it)."""
    lower, upper, periodic = limits
    if w == 0:
        a, Qa = np.array([-1]), start[None]
    else:
        a = np.arange(offs[w - 1], offs[w])
        Qa = B[a]
    b = np.arange(offs[w], offs[w + 1])
    d = B[b][None] - Qa[:, None]
    d[..., periodic] -= 2.0 * np.pi * np.round(d[..., periodic] / (2.0 * np.pi))
    Qb = Qa[:, None] + d
    ok = (np.abs(d) <= step).all(axis=2) & ((Qb >= lower) & (Qb <= upper)).all(axis=2)
    ka, kb = np.nonzero(ok)
    return Qa[ka], Qb[ka, kb], (a[ka] + 1) * len(B) + b[kb]


def _steps(rung: np.ndarray, broken: np.ndarray, n_rungs: int):
    """(waypoint, rung before it, edge code) of each step the plan takes between adjacent
    waypoints: not onto a waypoint where every path breaks (a jump, reported), nor
    across one without a solution (reported as its own failure)."""
    before = np.concatenate(([-1], rung[:-1]))
    take = (rung >= 0) & ~broken
    take[1:] &= rung[:-1] >= 0
    take[:1] = False  # the move from q0 (where the arm is, no pose of the path): bound only
    i = np.flatnonzero(take)
    return i, before[i], (before[i] + 1) * n_rungs + rung[i]  # kernel.edge_code


def _jumps(arm, half: _Halfway, i, Qa, Qb, step, a=None) -> np.ndarray:
    """Whether a jump hides in each step ``Qa[k]`` -> ``Qb[k]`` onto waypoint ``i[k]`` > 0
    from the waypoint before (the move from q0 is held to the step alone): the rule both
    plans judge their steps by. None where the straight joint motion keeps the tip on the path
    (``_chord``); else checked halfway (``BEND``, ``DEPTH``), every step of a round in one
    call of the solver."""
    if not len(i) or _loose(arm, step):  # every flip within the bound: none hides
        return np.zeros(len(i), dtype=bool)
    targets, a = half.targets, i - 1 if a is None else a  # ``a``: the rows stepped from
    Pa, Pb = targets.positions[a], targets.positions[i]
    rotations = targets.rotations
    Ra = Rb = None
    if rotations is not None:
        Ra, Rb = rotations[a], rotations[i]
    jumped = np.zeros(len(i), dtype=bool)
    which = np.arange(len(i))
    for _ in range(DEPTH):
        curved = ~_chord(arm, Qa, Qb, Rb is not None, step)  # a small straight motion
        if not curved.any():
            break
        which, Qa, Qb, Pa, Pb = which[curved], Qa[curved], Qb[curved], Pa[curved], Pb[curved]
        if Ra is not None and Rb is not None:
            Ra, Rb = Ra[curved], Rb[curved]
        P, R = poses_halfway(Pa, Ra, Pb, Rb)
        middle = 0.5 * (Qa + Qb)
        q = _nearest(arm, half, P, R, middle)
        near = within(q, Qa, Qb, step)
        searched(arm, half, P, R, q, near, middle, (Qa, Qb, step))  # where it may miss one
        far = ~near  # NaN (no solution) too
        jumped[which[far]] = True
        bend = np.max(np.abs(q - middle) / step, axis=1)
        closer = (bend > BEND) & ~far
        closer &= ~jumped[which]
        if not closer.any():
            break
        which = np.concatenate((which[closer], which[closer]))
        Qa, Qb = np.vstack((Qa[closer], q[closer])), np.vstack((q[closer], Qb[closer]))
        Pa, Pb = np.vstack((Pa[closer], P[closer])), np.vstack((P[closer], Pb[closer]))
        if R is not None and Ra is not None and Rb is not None:
            Ra, Rb = (
                np.concatenate((Ra[closer], R[closer])),
                np.concatenate((R[closer], Rb[closer])),
            )
    return jumped


def _chord(arm: ArmModel, Qa, Qb, rotations: bool, step: np.ndarray) -> np.ndarray:
    """Whether each step ``Qa[k]`` -> ``Qb[k]`` is small and straight: no joint moves by
    more than ``BEND`` of ``step``, and the straight joint motion keeps the tip on its way
    (``straight``: a rotation weighed by the arm's reach; ``rotations`` False: positions
    only)."""
    small = (np.abs(Qb - Qa) <= BEND * step).all(axis=1)
    if not small.any():
        return small
    Qa, Qb = Qa[small], Qb[small]
    reach = (arm.reach if np.isfinite(arm.reach) else 1.0) if rotations else None
    small[small] = straight(_tips(arm, np.vstack((Qa, Qb, 0.5 * (Qa + Qb)))), reach)
    return small


def straight(H: np.ndarray, reach: float | None) -> np.ndarray:
    """Whether each of n straight joint motions keeps its placement on its way: ``H``
    (3n, 4, 4, Pinocchio's FK) the placements at the motions' starts, at their ends, then
    halfway along them; each halfway placement within ``CHORD`` of its motion of the pose
    halfway between its ends' (``poses_halfway``; a rotation weighed at ``reach``, None:
    positions only). A small such step (a finely sampled path) hides no jump beside a
    singularity where the solutions halfway swing: the placement stays as near the path
    as anywhere else; a flip, or a line out of the workspace between waypoints, moves the
    placement off it."""
    n = len(H) // 3
    R, p = H[:, :3, :3], H[:, :3, 3]
    P, Rh = poses_halfway(p[:n], R[:n], p[n : 2 * n], None if reach is None else R[n : 2 * n])
    off = np.linalg.norm(p[2 * n :] - P, axis=1)
    size = np.linalg.norm(p[n : 2 * n] - p[:n], axis=1)
    if reach is not None and Rh is not None:  # both turns in one call: off, then the step's
        turns = _angle(np.concatenate((Rh, R[:n])), np.concatenate((R[2 * n :], R[n : 2 * n])))
        off = off + reach * turns[:n]
        size = size + reach * turns[n:]
    return np.asarray(off <= CHORD * size + STEP_EDGE)  # the same pose: no motion


def _tips(arm: ArmModel, Q: np.ndarray) -> np.ndarray:
    """(N, 4, 4): the tip's placement at each row of ``Q`` by Pinocchio's FK."""
    model, data, fid = arm.model, arm.data, arm.tip_frame_id
    rows = Q if model.nq == arm.dof else [arm.to_pin(q) for q in Q]
    H = np.empty((len(Q), 4, 4))
    for k, qp in enumerate(rows):
        pin.forwardKinematics(model, data, qp)
        H[k] = pin.updateFramePlacement(model, data, fid).homogeneous
    return H


def _angle(Ra: np.ndarray, Rb: np.ndarray) -> np.ndarray:
    """The angle (rad) of each rotation from ``Ra[k]`` to ``Rb[k]``, exact near zero."""
    D = np.einsum("kji,kjl->kil", Ra, Rb) - np.eye(3)
    f = np.linalg.norm(D.reshape(len(D), 9), axis=1) / (2.0 * np.sqrt(2.0))
    return np.asarray(2.0 * np.arcsin(np.minimum(f, 1.0)))


def every(arm: ArmModel, solver: str, targets: TargetBatch, opts) -> SolverSpec:
    """The solver of every solution at a path's waypoints, as ``solve_all`` chooses it (a
    search where one is not complete); with "auto" on a 7R arm whose joint 7 can be held,
    its sweep; a numeric solver the user names gives them itself."""
    first = targets.target(0) if len(targets) else None
    spec = registry.choose(solver, arm, first, opts, True)
    if spec.kind == "numeric" and solver == "auto":
        swept = (
            s
            for s in registry.sweeps()
            if (s.declines(opts, target=first) or s.why_not(arm, first, opts)) is None
        )
        spec = next(swept, spec)
    return spec


def hidden_steps(arm, out: BatchResult, targets: TargetBatch, step, half, went=None) -> None:
    """A followed path's steps judged as the global plan judges the steps it takes
    (``_jumps``): each success from the answer the path went on from (the row before it,
    ``went``: a success or a jump where None; not the move from q0, held to the step
    alone); a step that hides a jump makes its success ``discontinuous``. ``half``:
    (solver, opts, held, turn), the poses halfway solved as the global plan solves them
    (``every``), only where a step is not small and straight (``_chord``)."""
    if went is None:  # as one arm's path goes on: from a success or a jump
        went = out.success | (out.status_code == Status.DISCONTINUOUS.code)
    i, a = judged_from(out, went)
    if not len(i):
        return
    Qa, Qb = out.q[a], out.q[i]
    step = np.asarray(step, dtype=float)
    curved = ~_chord(arm, Qa, Qb, targets.rotations is not None, step)
    if not curved.any():
        return
    i, a, Qa, Qb = i[curved], a[curved], Qa[curved], Qb[curved]
    solver, opts, held, turn = half
    by = _Halfway(every(arm, solver, targets, opts), opts, targets, held, turn)
    jumped = _jumps(arm, by, i, Qa, Qb, step, a)
    for k in i[jumped].tolist():
        measured = path_reasons.row_verified(out, k)  # its verdict's measure, a success's
        out.success[k] = False
        out.status_code[k] = Status.DISCONTINUOUS.code
        hidden = path_reasons.hidden_step("the previous waypoint's answer")
        out.reasons[k] = path_reasons.jump(hidden, "the followed answer", measured)


def judged_from(out: BatchResult, went: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(i, a): each success ``i`` after a success or a jump, and the row ``a`` its step is
    judged from, the last the path went on from (``went``) before it, across the jumps it
    did not go on from; none from q0 (held to the step alone) or after a failed row."""
    n = len(out.success)
    passed = out.success | (out.status_code == Status.DISCONTINUOUS.code)
    last = np.maximum.accumulate(np.where(went, np.arange(n), -1))
    i = np.flatnonzero(out.success[1:] & passed[:-1]) + 1
    a = last[i - 1]
    return i[a >= 0], a[a >= 0]


def poses_halfway(Pa, Ra, Pb, Rb):
    """The poses halfway: the translations' mean, the rotations halfway along their
    geodesic (positions only when ``Rb`` is None)."""
    P = 0.5 * (Pa + Pb)
    if Rb is None:
        return P, None
    D = np.einsum("kji,kjl->kil", Ra, Rb)  # Ra^T Rb: a turn by t about u
    c = np.sqrt(np.maximum(1.0 + np.trace(D, axis1=1, axis2=2), 0.0)) / 2.0  # cos(t / 2)
    # D's quaternion is (c, sin(t / 2) u), with 2 sin(t) u read off D; half the turn's is
    # (1 + c, sin(t / 2) u), normalised
    v = np.stack((D[:, 2, 1] - D[:, 1, 2], D[:, 0, 2] - D[:, 2, 0], D[:, 1, 0] - D[:, 0, 1]), 1)
    v /= 4.0 * np.maximum(c, 1e-3)[:, None]
    norm = np.sqrt(2.0 + 2.0 * c)
    w, (x, y, z) = (1.0 + c) / norm, (v / norm[:, None]).T
    H = np.stack(
        (1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
         2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
         2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)),
        axis=1,
    ).reshape(-1, 3, 3)  # fmt: skip
    for k in np.flatnonzero(c < 1e-3):  # t near pi: u from the log, not from sin(t)
        H[k] = pin.exp3(0.5 * pin.log3(D[k]))
    return P, np.einsum("kij,kjl->kil", Ra, H)
