"""A target beyond reach answered at once, before anything is compiled or loaded.

The numeric solvers' kernel (``dls``, ``qp``: ``solvers.numeric.driver.run_numeric``)
refuses a target farther from the first joint than the arm's reach bound before its first
iteration, and the verdict then measures the seed. In a fresh process that costs numba's
compile of the kernel and the check (seconds; 18 to 45 s measured on an empty cache) or
its load from the cache (about 0.5 s) for an answer that needs neither. ``beyond_reach``
gives that very answer, field for field, in Python: the kernel's test on the same numbers
(``kernel.descent.solve_one``: the distance to ``chain.origin`` against ``chain.reach``
plus ``Settings.reach_slack``, where ``Settings.check_reach``), and the check's measure of
the seed in ``kernel.measure.pose_error``'s arithmetic, in its order. Where it cannot say
(another solver, weights, a region, a look-at), it returns None and the solve goes on as
always.

It runs for a process's first solves only (``first_use``): the first one that goes on to a
solver ends them, and from then on a solve pays one flag's read for it (the warm path is
unchanged; a far target later goes the solver's way, which answers it in microseconds once
its kernel is loaded). ``tests/solve/test_far.py`` compares its answers with the kernel
path's and checks, in a fresh process with an empty cache, that nothing is compiled or
loaded.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from armik import reasons
from armik.frozen import frozen
from armik.model.arm_model import ArmModel
from armik.problem.settings import SolverSettings
from armik.request import Request
from armik.result import IKResult
from armik.solvers import registry
from armik.solvers.answers import one
from armik.solvers.numeric.driver import DLS_STEP, settings
from armik.status import Status
from armik.targets.pose import Target, parsed
from armik.verify.measure import BatchMeasure, Measure, measures_of
from armik.verify.verdict import decide, ranked

# the solvers whose run is ``driver.run_numeric``: its kernel refuses a far target first
KERNEL_SOLVERS = ("dls", "qp")

first_use = True  # no solve has gone on to a solver in this process yet


def beyond_reach(arm: ArmModel, req: Request) -> IKResult | None:
    """The result of ``solve`` for ``req``'s target beyond the reach bound when the chosen
    solver is one the kernel's reach test answers (``KERNEL_SOLVERS``) and the options
    measure the plain pose or position; else None. Bad input raises as the solve would
    (``parsed``, ``ArmModel.seed``, the settings' checks). Returning None ends the
    process's ``first_use``."""
    global first_use
    target, q0, solver, opts, t0 = req.target, req.q0, req.solver, req.opts, req.t0
    refused = _refused(arm, target, solver, opts)
    if refused is None:
        first_use = False  # the solve goes on: its solver compiles or loads what it needs
        return None
    spec, tgt = refused
    seed = arm.seed(q0)
    q = np.ascontiguousarray(seed, dtype=float).copy()
    distance = math.dist(np.asarray(tgt.position).tolist(), arm.first_joint_origin.tolist())
    answers = one(q, Status.UNREACHABLE, reasons.unreachable(distance, arm.reach))
    m = _measure(arm, q, tgt, opts)
    return ranked(decide(arm, answers, BatchMeasure.of([m]), opts), spec.name, seed, False, t0)[0]


def _refused(arm: ArmModel, target: object, solver: str, opts: SolverSettings):
    """(the chosen solver's spec, the parsed target) when the kernel's reach test refuses
    ``target``, else None."""
    if opts.weights is not None or opts.bounds is not None:
        return None
    if type(target) is Target and target.aim is not None:  # a cone: a region
        return None
    tgt = parsed(target, arm)
    spec = registry.choose(solver, arm, tgt, opts, False)
    if spec.name not in KERNEL_SOLVERS:
        return None
    st = settings(opts, tgt.position_only, arm.dof, 1, DLS_STEP)  # check_reach: any step's
    if not st.check_reach:
        return None
    ch = arm.kernel_chain.chain
    p_t = np.ascontiguousarray(tgt.position, dtype=float)
    origin = ch.origin
    d0, d1, d2 = p_t[0] - origin[0], p_t[1] - origin[1], p_t[2] - origin[2]
    if not math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) > ch.reach + st.reach_slack:
        return None
    return spec, tgt


def _measure(arm: ArmModel, q: np.ndarray, tgt, opts: SolverSettings) -> Measure:
    """``verify.measure.measure`` of ``q`` for unweighted options without a region, its
    ``kernel.measure.pose_error`` written out in Python in the same order of operations."""
    model, data = arm.model, arm.data
    pin.forwardKinematics(model, data, arm.to_pin(q))
    T = pin.updateFramePlacement(model, data, arm.tip_frame_id)
    _, _, measure_rot = measures_of(arm, opts.weights, opts.position_only, tgt.rotation is None)
    ch = arm.kernel_chain.chain
    R_bw, p_bw = ch.base_R.tolist(), ch.base_p.tolist()
    R_w, p_w = T.rotation.tolist(), T.translation.tolist()
    p_t = np.asarray(tgt.position, dtype=float).tolist()
    R = [[0.0] * 3 for _ in range(3)]
    d = [0.0] * 3
    for a in range(3):  # T_base_tip = T_base_world T_world_tip
        pa = p_bw[a]
        for b in range(3):
            pa += R_bw[a][b] * p_w[b]
            R[a][b] = R_bw[a][0] * R_w[0][b] + R_bw[a][1] * R_w[1][b] + R_bw[a][2] * R_w[2][b]
        d[a] = p_t[a] - pa
    ori = None
    if measure_rot:
        R_t = np.asarray(tgt.rotation, dtype=float).tolist()
        M = [
            [R[0][a] * R_t[0][b] + R[1][a] * R_t[1][b] + R[2][a] * R_t[2][b] for b in range(3)]
            for a in range(3)
        ]
        sx, sy, sz = M[2][1] - M[1][2], M[0][2] - M[2][0], M[1][0] - M[0][1]
        s = 0.5 * math.sqrt(sx * sx + sy * sy + sz * sz)  # kernel.se3.rotation_angle
        ori = math.atan2(s, 0.5 * (M[0][0] + M[1][1] + M[2][2] - 1.0))
    violations = [] if arm._within(q.tolist()) else arm.limit_violations(q)
    return frozen(
        Measure,
        position_error=math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]),
        orientation_error=ori,
        violations=violations,
        tol_position=opts.tol_position,
        tol_orientation=opts.tol_orientation,
        region=False,  # ``_refused``: no region
    )
