"""The numeric solvers' Python side: settings, the kernel call, answers and reasons.

The iteration itself (pose error and its exact Jacobian, damping, the bounded step, the
active set on limits, the careful Levenberg-Marquardt mode, stall detection, restarts from
a shifted Halton sequence with candidate picking, known minima, the null-space pull) is
compiled: see ``armik.kernel`` (``descent.py`` documents the iteration, ``restarts.py`` the
restarts). ``dls`` and ``qp`` differ only in their step. This module turns options and the
target's aim into the kernel's ``Settings``, calls its entry (``kernel.entry``, one per
step) for one target (``run_numeric``) or many (``run_numeric_batch``), and turns its
arrays into ``Answers``.

``pieces.py`` exposes pieces of the kernel (``Problem``, ``evaluate``, ``descend``,
``RestartSeeds``) to tests, readers and ``clik``.
"""

from __future__ import annotations

import math
import secrets
from typing import NamedTuple

import numpy as np

from armik import reasons
from armik.kernel import box_qp as backend
from armik.kernel import descent as _descent
from armik.kernel import warmup
from armik.kernel.chain import halton
from armik.kernel.descent import CAREFUL_BELOW, KNOWN_MINIMUM_RADIUS  # noqa: F401 (re-exported)
from armik.kernel.entry import ENTRIES
from armik.kernel.problem import (
    LOOK_POINT,
    LOOK_TOWARD,
    NO_CONE,
    NO_LIMIT,
    NO_LOOK,
    STEP_DLS,
    STEP_QP,
    Settings,
    pack_settings,
)
from armik.kernel.restarts import RESTART_CANDIDATES  # noqa: F401 (re-exported)
from armik.kernel.single import POSE_ENTRIES
from armik.kernel.step import backend_step
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.problem.scores import fit_posture
from armik.problem.settings import SolverSettings
from armik.solvers.answers import Answers, one
from armik.solvers.claims import claim
from armik.solvers.numeric import rails, structure
from armik.status import Status
from armik.targets.aim import Aim, cone_words
from armik.targets.batch import TargetBatch
from armik.targets.pose import Target

_EYE = np.eye(3)  # read only by the kernel
_FLOAT = np.dtype(float)
# the largest ratio of two weights the iteration steers by (``steering_weights``): at 1e3
# every one of 300 Panda and UR5 poses was solved with 1e3 on the position or the rotation
STEER_RATIO = 1e3
_CONVERGED = Status.CONVERGED
_CONVERGED_CODE = _CONVERGED.code  # read once: a property
_halton = halton  # the restart table (kept under its old name for readers and tests)


class Step(NamedTuple):
    """Which step the kernel takes: ``STEP_DLS`` or ``STEP_QP`` (with its QP backend)."""

    kind: int
    backend: int = 0


DLS_STEP = Step(STEP_DLS)


def qp_step(backend_name: str) -> Step:
    which = backend.code(backend_name)
    if which not in _WARM:
        _warm(which)
    return Step(STEP_QP, which)


_WARM: set[int] = set()


def _warm(which: int) -> None:
    """Call the backend once from compiled code, on a tiny box QP: the first call through
    ``numba.objmode`` costs ~40 ms, which would otherwise land inside one solve's budget
    (measured: one Panda target of 2000 took 47 ms against a 5 ms budget)."""
    backend_step(2.0 * np.eye(2), np.ones(2), -np.ones(2), np.ones(2), which)
    _WARM.add(which)


def packed_settings(
    arm: ArmModel,
    opts: SolverSettings,
    position_only: bool,
    max_found: int,
    step: Step,
    aim: Aim | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """``settings`` as the kernel entry takes them, kept per arm (``PACKED``): a loop of
    solves whose options differ only in ``seed`` builds them once. Settings that differ only
    in their budget (``timeout``, ``iteration_budget``, ``max_restarts``: what restarts
    with collisions leave of it, new each time) patch the remembered ints. ``aim``: the
    target's (``Target.aim``), its point or direction written in per call."""
    budget = (opts.timeout, opts.max_restarts, opts.iteration_budget)
    sight = None if aim is None else aim.sight
    key = (
        opts.tol_position,
        opts.tol_orientation,
        opts.max_iterations,
        opts.position_only,
        opts.weights,
        opts.bounds,
        None if aim is None else aim.shape,  # which sight, not where: written in per call
        opts.nullspace_gain,
        opts.posture,
        position_only,
        max_found,
        step,
    )
    kept = arm._derived.get(PACKED)  # read as a dict, not through a call: every solve
    if kept is None:
        kept = PACKED(arm)
    found = kept.get(key)
    if found is None:
        packed = pack_settings(settings(opts, position_only, arm.dof, max_found, step, aim))
        if len(kept) > 512:
            kept.clear()
        kept[key] = (budget, packed)
        return packed if sight is None else _looking(packed, sight)
    remembered, packed = found
    if budget == remembered:
        return packed if sight is None else _looking(packed, sight)
    sf, si = packed if sight is None else _looking(packed, sight)
    si = si.copy()
    si[_MAX_RESTARTS] = int(opts.max_restarts)
    si[_TIMEOUT_NS] = _timeout_ns(opts.timeout)
    budget_its = opts.iteration_budget
    si[_ITERATION_BUDGET] = NO_LIMIT if budget_its is None else int(budget_its)
    return sf, si


def _looking(packed: tuple[np.ndarray, np.ndarray], sight: tuple[float, float, float]):
    """``packed`` with this call's look-at point or direction (a copy: the remembered
    settings are shared by threads)."""
    sf = packed[0].copy()
    sf[_LOOK_POINT] = sight
    return sf, packed[1]


# slots of ``problem.pack_settings``' floats and ints (``unpack`` reads them back)
_WEIGHTS, _BOUNDS, _LOOK_POINT = slice(0, 6), slice(11, 17), slice(21, 24)
_MAX_RESTARTS, _TIMEOUT_NS, _ITERATION_BUDGET = 3, 5, 6
# an arm's packed settings, (budget, (floats, ints)) under what else they are built from
PACKED: Derived[dict[tuple, tuple]] = Derived("packed numeric settings", lambda _: {})


def _timeout_ns(timeout: float) -> int:
    return min(int(timeout * 1e9), 2**62)


def steering_weights(w: np.ndarray) -> np.ndarray:
    """The weights the iteration steers by: ``w`` scaled to a smallest positive weight of 1,
    so that the lightest rows stay well above the damping's floor (LAMBDA_MIN), and a ratio
    above STEER_RATIO brought down to STEER_RATIO by a power (their order and zeros kept).
    Beyond it the heavy rows' curvature swamps the light ones': the damping and the stall
    test see only the heavy rows, and a reachable full pose went unsolved (1e6 on the
    rotation: 4 of 300 Panda poses after 1000 restarts each)."""
    w = w / w[w > 0.0].min()
    top = float(w.max())
    if top > STEER_RATIO:
        w = w ** (math.log(STEER_RATIO) / math.log(top))
    return w


def settings(
    opts: SolverSettings,
    position_only: bool,
    dof: int,
    max_found: int,
    step: Step,
    aim: Aim | None = None,
):
    """The kernel's ``Settings`` for these options, target kind (its ``aim`` too) and arm
    size."""
    # only the ratios matter to the task: the smallest measured weight is 1, so that the
    # lightest rows stay well above the damping's floor (LAMBDA_MIN)
    w = steering_weights(opts.weight_vector(position_only))
    full_task = opts.weights is None and not (opts.position_only or position_only)
    region = opts.bounds is not None or aim is not None
    bounds = np.array(opts.region_bounds)
    cone = None if aim is None else aim.cone
    # rows a bound frees do not count as task rows (a cone's rotation counts 2: a direction);
    # a box lets a far target come closer
    measured = w * np.isfinite(bounds)
    if cone is not None:
        n_task = int(np.count_nonzero(measured[:3])) + 2
    else:
        n_task = 6 if full_task and not region else int(np.count_nonzero(measured))
    reach_slack = float(opts.tol_position) + float(np.linalg.norm(bounds[:3]))
    return Settings(
        w,
        full_task or bool((w == 1.0).all()),
        bool(w[:3].any()),
        0.5 * opts.tol_position,
        0.5 * opts.tol_orientation,
        float(opts.nullspace_gain) if dof > n_task else 0.0,
        int(opts.max_iterations),
        int(opts.max_restarts),
        int(max_found),
        _timeout_ns(opts.timeout),
        NO_LIMIT if opts.iteration_budget is None else int(opts.iteration_budget),
        int(step.kind),
        int(step.backend),
        bool(w[:3].all()) and bool(np.isfinite(bounds[:3]).all()),
        reach_slack,
        1.0 / float(w.max()),
        bool((w[:3] == 0.0).any() and (w[3:] == 0.0).any() and w[:3].any()),
        region,
        bounds,
        NO_CONE if cone is None else float(cone[3]),
        np.array((0.0, 0.0, 1.0) if cone is None else cone[:3]),
        NO_LOOK if aim is None else _LOOKS[aim.point is None, aim.toward is None],
        np.array((0.0, 0.0, 0.0) if aim is None or aim.sight is None else aim.sight),
        *_posture(opts, dof),
    )


# the kernel's sight under (no point, no direction)
_LOOKS = {(False, True): LOOK_POINT, (True, False): LOOK_TOWARD, (True, True): NO_LOOK}


def _posture(opts: SolverSettings, dof: int) -> tuple[np.ndarray, np.ndarray]:
    """(reference, weights) of the null-space pull's posture (``Options.posture``), or two
    empty arrays (the pull toward q0); an ``OptionError`` for a posture of another arm."""
    if opts.posture is None:
        return np.empty(0), np.empty(0)
    q_ref, weights = opts.posture
    fit_posture(len(q_ref), dof, option="secondary")
    w = np.array(weights, dtype=float)
    # the largest weight 1: the pull's strength is nullspace_gain's, the weights its shares
    return np.array(q_ref, dtype=float), w / w.max() if w.max() > 0.0 else w


def solve_seed(opts: SolverSettings) -> int:
    """The restart seed of a solve: ``opts.seed``, or a fresh random one when it is None."""
    return secrets.randbits(63) if opts.seed is None else int(opts.seed)


def run_numeric(
    arm: ArmModel,
    target: Target,
    q0: np.ndarray,
    opts: SolverSettings,
    all_solutions: bool,
    step: Step,
) -> Answers:
    """Descend from q0, then from restart seeds until solved, out of budget or restarts."""
    max_found = opts.max_solutions if all_solutions else 1
    aim = target.aim
    sf, si = packed_settings(arm, opts, target.position_only, max_found, step, aim)
    # C-ordered, writable float64 rows (numba compiles anew for any other layout): views of
    # the inputs when they are such arrays already (the kernel only reads them), else copies.
    R_t = _c_float(_EYE if target.rotation is None else target.rotation)[None]
    p_t = _c_float(target.position)[None]
    q0 = _c_float(q0)
    out_q = np.empty((1, max_found, arm.dof))
    info = np.empty((1, 5), dtype=np.int64)
    err = np.empty((1, 2))
    seeds = np.empty(1, dtype=np.uint64)
    seeds[0] = solve_seed(opts)  # (a third of np.array([seed], dtype=np.uint64)'s cost)
    bounded = arm._derived.get(structure.BOUNDED)
    if bounded is None:
        bounded = structure.BOUNDED(arm)
    if bounded and aim is None and opts.weights is None and opts.bounds is None:
        turned = target.rotation is not None and not opts.position_only
        why = structure.beyond(arm, R_t[0] if turned else None, p_t[0], opts, sf)
        if why is not None:
            return one(q0.copy(), Status.UNREACHABLE, why)
    if step.kind not in warmup.PREPARED:  # a warm process: nothing to prepare
        warmup.prepare(step.kind)
    region = opts.bounds is not None or aim is not None
    entry = ENTRIES[step.kind]
    rails_ = arm._derived.get(rails.UNLIMITED)
    if rails_ is None:
        rails_ = rails.UNLIMITED(arm)
    flat = rails.toward(arm, p_t[0], q0, rails_) if len(rails_) else arm.kernel_chain.flat
    entry(*flat, sf, si, R_t, p_t, q0[None], seeds, out_q, info, err)
    return kernel_answers(
        arm, target.position, q0, opts, sf, info[0], out_q[0], err[0], region, aim
    )


def converged_reason(restarts: int) -> str:
    return reasons.CONVERGED.format(restarts)


def kernel_answers(
    arm: ArmModel, position, q0, opts: SolverSettings, sf, info, out_q, err, region: bool, aim=None
) -> Answers:
    """The answers of one target from the kernel's outputs (see ``descent.solve_one``);
    ``region``: the target has one (bounds or an aim); ``aim``: its aim, or None."""
    claim, found, iterations, restarts, out_of_budget = info.tolist()
    if claim == _descent.CONVERGED:
        reason = converged_reason(restarts)
        return Answers(
            q=out_q[:found],
            claim=np.full(found, _CONVERGED_CODE, dtype=np.int8),
            iterations=np.full(found, iterations, dtype=np.int64),
            restarts=np.full(found, restarts, dtype=np.int64),
            reasons=(reason,) * found,
        )
    if claim == _descent.UNREACHABLE:
        distance = math.dist(np.asarray(position).tolist(), arm.first_joint_origin.tolist())
        return one(q0.copy(), Status.UNREACHABLE, reasons.unreachable(distance, arm.reach))
    why = _not_converged(opts, sf, bool(out_of_budget), restarts, err, region, cone_words(aim))
    return one(out_q[0], Status.NOT_CONVERGED, why, iterations=iterations, restarts=restarts)


def pose_runner(
    arm: ArmModel,
    opts: SolverSettings,
    step: Step,
    position_only: bool = False,
    aim: Aim | None = None,
):
    """``run_pose(H, q0, seed)`` for ``armik.solve.prepared``: one plain 4x4 pose ``H`` (base frame)
    from ``q0`` through the kernel's single-pose entry; with ``position_only``, H holds a
    position target (its rotation the identity, which the settings then ignore). Returns
    None when ``H`` or ``q0`` is not plain, for a rotation the arm's structure never takes
    (``run_numeric`` refuses it), or for ``every`` (nothing was solved: take the general
    path); for a converged claim (q, iterations, restarts, branch, singular, reason
    function, its arguments); else the answers for the general verdict. ``aim``: every
    target's (its shape; each call's point or direction is ``run_pose``'s ``point``)."""
    dof = arm.dof
    sf, si = packed_settings(arm, opts, position_only, 1, step, aim)
    warmup.prepare(step.kind)  # once per plan
    region = opts.bounds is not None or aim is not None
    entry = POSE_ENTRIES[step.kind]
    packed, kind, halton_ = arm.kernel_chain.flat
    unlimited = rails.UNLIMITED(arm)
    on_rails = len(unlimited) > 0  # read once: no call in a warm solve
    converged_code = _descent.CONVERGED
    # a target the arm's structure bounds, plainly measured: refused by ``run_numeric``
    bounded = structure.BOUNDED(arm)
    bounded = bounded and aim is None and opts.weights is None and opts.bounds is None
    turned = not (position_only or opts.position_only)

    def run_pose(H: np.ndarray, q0: np.ndarray, seed: int, every: bool = False, point=None):
        if every:  # solve_all: the general path (max_solutions descents)
            return None
        if bounded and structure.beyond(arm, H[:3, :3] if turned else None, H[:3, 3], opts, sf):
            return None  # the general path: H and q0 read there, the rotation refused
        s = sf
        if point is not None:  # this call's look-at point or direction (``packed_settings``)
            s = sf.copy()
            s[_LOOK_POINT] = point
        out_q = np.empty((1, dof))
        info = np.empty(5, dtype=np.int64)
        err = np.empty(2)
        chain = packed
        if on_rails:  # restarts along a rail without limits: toward the target
            chain = rails.toward(arm, H[:3, 3], np.asarray(q0, dtype=float), unlimited)[0]
        if not entry(chain, kind, halton_, s, si, H, q0, seed, out_q, info, err):
            return None
        if info[0] == converged_code:
            restarts = int(info[3])
            got = (out_q[0], int(info[2]), restarts, None, False, converged_reason, (restarts,))
            return claim(got)
        return kernel_answers(arm, H[:3, 3], q0, opts, sf, info, out_q, err, region, aim)

    run_pose.one_only = True  # type: ignore[attr-defined]  # solve_all: the general path
    return run_pose


def _c_float(a) -> np.ndarray:
    """``a`` itself when it is a C-ordered, writable float64 array, else such a copy."""
    if type(a) is np.ndarray and a.dtype == _FLOAT:
        flags = a.flags
        if flags.c_contiguous and flags.writeable:
            return a
    return np.array(a, dtype=float, order="C")


def _not_converged(
    opts: SolverSettings, sf: np.ndarray, out_of_budget: bool, restarts: int, err, region, cone
) -> str:
    if not out_of_budget and opts.max_restarts == 0:
        why = "one descent from q0 (max_restarts=0: no restarts)"
    elif not out_of_budget:
        why = f"the restart limit (max_restarts={opts.max_restarts})"
    else:
        why = reasons.budget(opts.timeout, opts.iteration_budget, f"{restarts} restarts")
    # each part where a weight measures it and a finite bound holds it (an aim: the cone)
    kept = sf[_WEIGHTS] * np.isfinite(sf[_BOUNDS]) if region else sf[_WEIGHTS]
    pos, ori = err[0] if kept[:3].any() else None, err[1]
    if not (kept[3:].any() or cone is not None):
        ori = None
    if region:  # the kernel measured the distances outside the region
        return reasons.not_converged(why, reasons.best_outside(pos, ori, cone))
    return reasons.not_converged(why, reasons.best_errors(pos, ori))


def run_numeric_batch(
    arm: ArmModel,
    targets: TargetBatch,
    q0: np.ndarray,
    opts: SolverSettings,
    step: Step,
    seeds: np.ndarray | None = None,
) -> Answers:
    """N solves in one kernel call (GIL released): row i is what ``run_numeric`` returns
    first for target i from q0[i] with restart seed ``seeds[i]`` (default: every target
    uses ``opts.seed``, as a loop of ``solve`` with the same options would)."""
    n_targets, dof = len(targets.positions), arm.dof
    # C-ordered, writable float64 copies: numba compiles anew for any other layout.
    q0 = np.array(q0, dtype=float).reshape(n_targets, dof)
    if seeds is None:
        seeds = np.full(n_targets, solve_seed(opts), dtype=np.uint64)
    else:
        seeds = np.array(seeds).astype(np.uint64)
    aim = targets.aim
    sf, si = packed_settings(arm, opts, targets.rotations is None, 1, step, aim)
    if targets.rotations is None:
        R_t = np.broadcast_to(np.eye(3), (n_targets, 3, 3)).copy()
    else:
        R_t = np.array(targets.rotations, dtype=float)
    p_t = np.array(targets.positions, dtype=float)
    bounded = arm._derived.get(structure.BOUNDED)
    if bounded is None:
        bounded = structure.BOUNDED(arm)
    unlimited = arm._derived.get(rails.UNLIMITED)
    if unlimited is None:
        unlimited = rails.UNLIMITED(arm)
    region = opts.bounds is not None or aim is not None
    if bounded or len(unlimited):
        refusals = _refusals(arm, targets, opts, sf, R_t, p_t) if bounded else {}
        if refusals or len(unlimited):
            rows = [i for i in range(n_targets) if i not in refusals]
            got = rails.batch_kernel(
                arm, sf, si, R_t[rows], p_t[rows], q0[rows], seeds[rows], step.kind
            )
            return _worded(arm, opts, sf, p_t, q0, rows, got, refusals, region, aim)
    out_q = np.empty((n_targets, 1, dof))
    info = np.empty((n_targets, 5), dtype=np.int64)
    err = np.empty((n_targets, 2))
    kc = arm.kernel_chain
    if step.kind not in warmup.PREPARED:  # a warm process: nothing to prepare
        warmup.prepare(step.kind)
    entry = ENTRIES[step.kind]
    entry(*kc.flat, sf, si, R_t, p_t, q0, seeds, out_q, info, err)
    if (info[:, 0] == _descent.NOT_CONVERGED).any():  # in the single solve's words
        got = (out_q, info, err)
        return _worded(arm, opts, sf, p_t, q0, range(n_targets), got, {}, region, aim)
    return Answers(
        q=out_q[:, 0],
        claim=info[:, 0].astype(np.int8),
        iterations=info[:, 2].copy(),
        restarts=info[:, 3].copy(),
    )


def _worded(arm: ArmModel, opts, sf, p_t, q0, rows, got, refusals, region: bool, aim) -> Answers:
    """A batch's answers, the kernel's (``got``: out_q, info, err) for ``rows``, the others
    refused (``refusals``: {row: why}, q0 kept); where a row failed, every row in words: a
    solved one's as the single solve's (``kernel_answers``), a success's the verdict's."""
    out_q, info, err = got
    n = len(p_t)
    q, claim = q0.copy(), np.full(n, Status.UNREACHABLE.code, dtype=np.int8)
    iterations, restarts = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
    words = dict(refusals)
    failed = bool(refusals) or bool((info[:, 0] == _descent.NOT_CONVERGED).any())
    for k, i in enumerate(rows):
        if failed:
            one_ = kernel_answers(
                arm, p_t[i], q0[i], opts, sf, info[k], out_q[k], err[k], region, aim
            )
            words[i] = "" if one_.claimed(0) else one_.reason(0)
        q[i], claim[i], iterations[i], restarts[i] = out_q[k, 0], info[k, 0], info[k, 2], info[k, 3]
    reasons_ = tuple(words[i] for i in range(n)) if failed else None
    return Answers(q=q, claim=claim, iterations=iterations, restarts=restarts, reasons=reasons_)


def _refusals(arm: ArmModel, targets: TargetBatch, opts, sf, R_t, p_t) -> dict[int, str]:
    """{row: why} of a batch's targets beyond what the arm's structure allows
    (``structure.refusals``); empty for another target kind."""
    if targets.aim is not None or opts.weights is not None or opts.bounds is not None:
        return {}
    turned = targets.rotations is not None and not opts.position_only
    return structure.refusals(arm, R_t if turned else None, p_t, opts, sf)
