"""Solves prepared once per arm, solver and options: the common inputs in few steps.

Most of what ``solve`` does does not depend on the target: choosing the solver, building
its settings, finding what the check measures. A ``Plan`` does it once per (arm, solver
name, options other than ``seed``, target kind) and keeps it. For a target given as a
``pinocchio.SE3`` or a C-ordered float64 4x4 array (a position target: a float64 array of
3, held as a 4x4 with the identity rotation that the settings ignore; on a planar arm whose
runner says ``takes_xy``, also a float64 array of 2, (x, y) in the arm's plane, placed in
the base frame as the parser places it and handed to the runner as given), and ``q0`` None
or a float64 array of one value per joint, the plan hands the 4x4 to the solver's compiled
runner (``SolverSpec.prepare_pose``), which checks in compiled code that the pose and seed
are what the parser and ``ArmModel.seed`` would pass unchanged, then solves. Pinocchio computes
the answer's tip placement and compiled code measures it in place
(``armik.kernel.measure.placement_check``), as ``verify.measure.measure`` does; a target
with a region (bounds, a cone) on a numeric solver is measured by ``armik.verify.region``,
as there. The result is the one the general path builds, field for field
(tests/solve/test_prepared.py); its reason text is written on first read. The verdict
is ``armik.verify.verdict``'s: ``claimed_verdict`` for a runner's claimed answers from the
compiled measure, ``decide`` for the rest.

Anything else (another input form, a seed outside the limits, an answer the check refuses,
a claim other than converged, collisions asked for) goes the general way:
``armik.solve.single`` and ``armik.verify.verdict``; when the check refuses a closed form's
first answer, its every row goes there, nearest first.
"""

from __future__ import annotations

import secrets
import time

import numpy as np
import pinocchio as pin

from armik.errors import SolverError
from armik.kernel.measure import (
    check_frame,
    fk_check_frame,
    fk_checks,
    placement_check,
    pose_checks,
)
from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.problem.settings import SolverSettings
from armik.reasons import Cone
from armik.result import IKResult
from armik.solvers import registry
from armik.solvers.answers import Answers
from armik.solvers.claims import Claim
from armik.targets.aim import Aim, cone_words
from armik.targets.pose import Target, parse_target
from armik.verify.distances import fields_apart, frees_position
from armik.verify.judged import Judged
from armik.verify.measure import BatchMeasure, measures_of
from armik.verify.region import region_error
from armik.verify.verdict import (
    claimed_rows,
    claimed_verdict,
    decide,
    finish,
    numbered,
    seed_distance,
)
from armik.verify.verdicts import failure_rank, tied

_FLOAT, _SE3 = np.dtype(float), pin.SE3
_NO_PLAN = object()  # remembered: this solver and options have no plan
_IDENTITY = np.eye(4)  # copied for a position target (a copy costs an eighth of np.eye)
_SIGHTLESS = (None, None)  # a cone's (point, direction) where the target has no aim
_ALONG = Cone(0.0)  # the words of an ``armik.Axis`` lowered to a pose: its axis' angle


def plan_for(
    arm: ArmModel,
    solver: str,
    key: tuple,
    opts: SolverSettings,
    position: bool = False,
    every: bool = False,
    aim: Aim | None = None,
) -> Plan | None:
    """The plan of ``arm`` for ``solver``, the options whose ``solve._options`` key is
    ``key`` and full poses (or positions, with ``position``) with ``aim`` (its shape is in
    ``key``: ``armik.solve.read``), for one answer or, with ``every``, every solution
    ("auto" may choose apart: ``registry.choose``); None when the solver has no runner or
    does not apply to that kind of target."""
    # a registration may change what "auto" chooses: plans of each generation apart. The
    # arm's store read as a dict, not through a call: this runs on every solve.
    plans = arm._derived.get(_PLANS)
    if plans is None or plans["generation"] != registry.generation:
        plans = arm._derived[_PLANS] = {"generation": registry.generation}
    plan = plans.get((solver, key, position, every))
    if plan is None:
        plan = _build(arm, solver, opts, position, every, aim)
        if len(plans) > 64:
            plans = arm._derived[_PLANS] = {"generation": registry.generation}
        plans[(solver, key, position, every)] = plan
    return None if plan is _NO_PLAN else plan


_PLANS: Derived[dict] = Derived("prepared solves", lambda _: {})  # read as a key, not called


def kind_of(position: bool, aim: Aim | None = None) -> Target:
    """A target of the kind and aim every target of a plan, a batch or a path has: what
    the registry's choice reads of them."""
    return Target(np.zeros(3), None if position else np.eye(3), aim=aim)


def _build(arm: ArmModel, solver: str, opts, position: bool, every: bool, aim: Aim | None):
    try:
        spec = registry.choose(solver, arm, kind_of(position, aim), opts, every)
    except SolverError:  # the general path raises it, with its message
        return _NO_PLAN
    if spec.prepare_pose is None:
        return _NO_PLAN
    plan = Plan(arm, spec, opts, position, aim)
    return _NO_PLAN if plan.run_pose is None else plan  # a runner declined: the general path


class Plan:
    """One arm, one solver, one set of options (all but ``seed``); see the module."""

    def __init__(
        self,
        arm: ArmModel,
        spec: registry.SolverSpec,
        opts: SolverSettings,
        position: bool = False,
        aim: Aim | None = None,
    ) -> None:
        self.arm = arm
        self.spec, self.solver = spec, spec.name
        self.complete = spec.complete  # its solve_all misses no solution (``SolverSpec``)
        self.position = position  # targets are positions (x, y, z), not full poses
        # a solver of cones takes the targets' aim (its shape: the point is each call's)
        self.run_pose = spec.prepare_pose(arm, opts, position, *(() if aim is None else (aim,)))
        # a runner of one answer (a numeric one): ``solve_all`` takes the general path
        self.every = not getattr(self.run_pose, "one_only", False)
        # a runner that also takes (x, y) targets in a planar arm's plane: those too
        self.plane = None
        p = arm.plane
        # (a plane along two base axes: there (x, y) are its coordinates, ``Plane.from_base``)
        if position and getattr(self.run_pose, "takes_xy", False) and p is not None and _along(p):
            self.plane = (*p.origin.tolist(), *p.x.tolist(), *p.y.tolist())
        self.model, self.frame = arm.model, arm.tip_frame_id
        self.direct = arm.model.nq == arm.dof  # q is Pinocchio's configuration itself
        self.shape = (arm.dof,)
        self.middle = arm.middle
        w, weighted, measure_rot = measures_of(arm, opts.weights, opts.position_only, position)
        self.measured = check_frame(  # what the compiled check measures against
            arm.T_base_world.rotation,
            arm.T_base_world.translation,
            w,
            int(weighted) | (2 if measure_rot else 0),
            arm.lower,
            arm.upper,
        )
        # an aim is measured, a position target's too: the angle outside its cone
        self.measure_rot = measure_rot or aim is not None
        # several answers of one target: measured by the compiled FK, as the general
        # verdict measures them (``verify.measure.measure_many``)
        self.flat = arm.kernel_chain.flat
        self.fk_measured = fk_check_frame(w, self.measured[18], arm.lower, arm.upper)
        # a 6R closed form's words of its packed rows, their ``Answers``
        # (``armik.solvers.closed_form.sixr_answers.pose_runner``)
        self.words = getattr(self.run_pose, "words", None)
        self.answers = getattr(self.run_pose, "answers", None)
        # measured apart (weights, a region): the distances themselves too, for the result
        # (``armik.verify.distances``): unweighted, or a region's (``region_error``'s)
        self.apart = None
        self.weighted = opts.weights is not None
        # the true distances measure the rotation of a full pose, whatever its weights
        self.apart_rot = aim is not None or not (opts.position_only or position)
        region = opts.bounds is not None or aim is not None
        if self.weighted and not region:
            w, _, _ = measures_of(arm, None, opts.position_only, position)
            flags = 2 if self.apart_rot else 0
            self.apart = check_frame(
                arm.T_base_world.rotation, arm.T_base_world.translation, w, flags, arm.lower,
                arm.upper,
            )  # fmt: skip
            self.fk_apart = fk_check_frame(w, flags, arm.lower, arm.upper)  # several answers
        # a region (bounds, a cone): measured by ``verify.region``, as the general path does
        self.region = (opts.region_bounds, w, aim and aim.cone) if region else None
        self.cone = cone_words(aim)  # what a success's words name
        # an Axis or a LookAt alone holds no position (``distances.holds_no_position``):
        # the bounds free it here, the call's target says whether it is one
        self.frees_position = frees_position(opts, aim)
        plain = opts.weights is None and opts.bounds is None  # (and leave out)
        self.free = (False, False) if plain else opts.left_free(position, aim is not None)
        self.tol_p, self.tol_r = opts.tol_position, opts.tol_orientation
        # its every row solved, measured and judged in one compiled call
        judging = getattr(self.run_pose, "judging", None)
        self.judged = None
        if judging is not None and self.apart is None and self.region is None:
            self.judged = judging(self.flat, self.fk_measured, self.tol_p, self.tol_r)
            self.judged_results = Judged(arm, self.judged.finish, self.words, self.solver,
                                         self.tol_p, self.tol_r, measure_rot)  # fmt: skip

    def _plain(self, target: object, q0: object):
        """(H, q0, xy) for the runner when both are plain in type and shape, else None; xy:
        a planar arm's (x, y) target as two floats (H holds it in the base frame), else
        None."""
        kind = type(target)
        xy = None
        if kind is Target and target.planar_xy is None:  # parsed at the door already
            if (target.rotation is None) != self.position:
                return None
            if self.position:
                target = target.position
            else:
                H = _IDENTITY.copy()
                H[:3, :3], H[:3, 3] = target.rotation, target.position
                target = H
            kind = np.ndarray
        if self.position:
            if not (kind is np.ndarray and target.dtype == _FLOAT and target.flags.c_contiguous):
                return None
            shape = target.shape
            if shape != (3,) and (shape != (2,) or self.plane is None):
                return None
            H = _IDENTITY.copy()  # the rotation is not measured: the identity, as parsed
            if shape == (3,):
                H[0, 3], H[1, 3], H[2, 3] = target.tolist()
            else:
                xy = x, y = target.tolist()
                o0, o1, o2, a0, a1, a2, b0, b1, b2 = self.plane
                # ``Plane.to_3d``'s arithmetic (``from_base``'s on a plane along two base
                # axes), as the parser places it (a non-finite or
                # too distant one fails the runner's check: the general path refuses it)
                H[0, 3] = o0 + x * a0 + y * b0
                H[1, 3] = o1 + x * a1 + y * b1
                H[2, 3] = o2 + x * a2 + y * b2
        elif kind is _SE3:
            H = target.homogeneous  # a fresh C-ordered 4x4
        elif (
            kind is np.ndarray
            and target.dtype == _FLOAT
            and target.shape == (4, 4)
            and target.flags.c_contiguous
        ):
            # only read; a read-only array is copied (compiled code would be compiled again
            # for read-only arrays)
            H = target if target.flags.writeable else target.copy()
        else:
            return None
        if q0 is None:
            return H, self.middle, xy  # only read
        if (
            type(q0) is np.ndarray
            and q0.dtype == _FLOAT
            and q0.shape == self.shape
            and q0.flags.c_contiguous
        ):
            return H, (q0 if q0.flags.writeable else q0.copy()), xy  # a result's q is read-only
        seed = _seed_copy(q0, self.shape)
        return None if seed is None else (H, seed, xy)

    def solve(
        self, target: object, q0: object, opts: SolverSettings, seed: int | None, t0: float
    ) -> IKResult | None:
        """The result of ``solve`` for a plain ``target`` and ``q0``, or None (general path).
        ``seed`` is this call's (``opts`` may carry another: only the rest is read)."""
        plain = self._plain(target, q0)
        if plain is None:
            return None
        H, q0, xy = plain
        if seed is None:
            seed = secrets.randbits(63)
        # this call's point or direction: the plan is shared by points; an ``armik.Axis``
        # lowered to a pose: its axis, what the orientation distance measures
        aim = along = None
        if type(target) is Target:
            aim, along = target.aim, target.along
        sight = None if aim is None else aim.point if aim.point is not None else aim.toward
        if xy is not None:
            got = self.run_pose(H, q0, seed, False, xy)
        elif sight is not None:
            got = self.run_pose(H, q0, seed, False, sight)
        else:
            got = self.run_pose(H, q0, seed)
        if got is None:
            return None
        if type(got) is not Claim:  # claims other than converged: the general verdict
            return self._finish(got, H, q0, opts, t0, False, xy, target)[0]
        q = got.q
        data, R_w, p_w = self.arm.tip_views()  # this thread's
        pin.forwardKinematics(self.model, data, q if self.direct else self.arm.to_pin(q))
        pin.updateFramePlacement(self.model, data, self.frame)  # into R_w, p_w
        region = self.region
        apart = None  # measured apart: the distances too, for the result
        if region is None:
            pos, ori, inside = placement_check(self.measured, R_w, p_w, H, q)
            if self.apart is not None:  # before the verdict makes q read-only
                apart = placement_check(self.apart, R_w, p_w, H, q)
        else:
            T_bw = self.arm.T_base_world
            pos, ori, *apart = region_error(
                T_bw,
                R_w,
                p_w,
                H[:3, :3],
                H[:3, 3],
                *region,
                *_SIGHTLESS if aim is None else (aim.point, aim.toward),
                True,
                along,
            )
            inside = self.arm._within(q.tolist())
        ori = ori if self.measure_rot else None
        fields = claimed_verdict(
            self.arm, got, pos, ori, inside, self.tol_p, self.tol_r, region is not None, self.cone,
            self.free,
        )  # fmt: skip
        if fields is None or not fields["success"]:  # the next row may pass: every row
            answers = self._refused(got, H, q0, seed, xy)
            return self._finish(answers, H, q0, opts, t0, False, xy, target)[0]
        fields["solver"], fields["time"] = self.solver, time.perf_counter() - t0
        if apart is None:
            return IKResult._from_fields(fields)
        no_position = self.frees_position and (along is not None or sight is not None)
        d_pos, d_ori = None if no_position else apart[0], apart[1]
        said = None  # the words of the distance where it is an axis' angle (``axis_words``)
        if along is not None or sight is not None:
            said = self.cone if aim is not None else _ALONG
        d_ori = d_ori if self.apart_rot else None
        kept = fields_apart(fields, d_pos, d_ori, self.weighted, said)
        r = IKResult._from_fields(fields)
        r.extra["measured"] = kept
        return r

    def _refused(self, got: Claim, H: np.ndarray, q0: np.ndarray, seed, xy) -> Answers:
        """The answers for the general verdict when the check refuses the runner's answer
        ``got``: a closed form's every row, nearest first (the next may pass), else the
        claim alone."""
        every = (
            self.run_pose(H, q0, seed, True) if xy is None else self.run_pose(H, q0, seed, True, xy)
        )
        return got.answers() if every is None else every  # None: a numeric runner

    def solve_all(
        self, target: object, q0: object, opts: SolverSettings, seed: int | None, t0: float
    ):
        """The results of ``solve_all`` for a plain ``target`` and ``q0``, or None."""
        plain = None if self.region is not None else self._plain(target, q0)
        if plain is None:  # a region's answers: the general path measures them
            return None
        H, q0, xy = plain
        if self.judged is not None and xy is None:  # a 6R closed form: judged as solved
            got = self.judged(H, q0)
            if got is None:
                return None
            rows, n, verdict = got
            if verdict >= 0:
                return self.judged_results.solutions(rows, n, time.perf_counter() - t0)
            got = self.answers(rows[:n, :11], H)  # a row the general verdict decides
        else:
            seed = secrets.randbits(63) if seed is None else seed
            got = (
                self.run_pose(H, q0, seed, True)
                if xy is None
                else self.run_pose(H, q0, seed, True, xy)
            )
        if got is None:
            return None
        Q = got.q  # read-only: the results' q are its rows
        measured = self._measured(Q, H)
        verified, failed = [], []  # the results' fields; failed: (rank key, fields)
        unclaimed = False
        tol_p, tol_r, rot, solver = self.tol_p, self.tol_r, self.measure_rot, self.solver
        rows = measured.tolist()
        for i, fields in enumerate(claimed_rows(self.arm, got, rows, tol_p, tol_r, rot)):
            if fields is not None:  # its verdict without a Measure, where that decides
                fields["solver"] = solver
                if fields["success"]:
                    verified.append(fields)
                else:  # outside the limits
                    failed.append((_rank_key(fields), fields))
                continue
            pos, ori, inside = rows[i]
            m = BatchMeasure(
                np.array([pos]),
                np.array([ori if rot else np.nan]),
                np.array([inside > 0.0]),
                tol_p,
                tol_r,
                rot,
            )
            fields = {**decide(self.arm, got.take([i]), m, opts).fields(0), "solver": solver}
            if fields["success"]:  # claimed unreached (a boundary case), verified all the same
                verified.append(fields)
                unclaimed = True
                continue
            failed.append((_rank_key(fields), fields))
        # verified answers nearest q0 first (the runner's order; a verified answer it did
        # not claim is ranked among them), then the others ranked as ``verdict.ranked`` ranks
        # them (a stable sort on the same key)
        if unclaimed:  # as near q0 to ``sixr.TIE``: the runner's order, as the C's
            keys = [(seed_distance(f["q"], q0),) for f in verified]
            order = tied(sorted(range(len(keys)), key=keys.__getitem__), keys, self.arm.dof)
            verified = [verified[i] for i in order]
        failed.sort(key=lambda pair: pair[0])
        if failed:
            verified += [fields for _, fields in failed]
        labels = numbered([fields["branch"] for fields in verified])
        elapsed = time.perf_counter() - t0
        for fields, label in zip(verified, labels):
            fields["time"], fields["branch"] = elapsed, label
        if self.apart is None:  # (a region's answers take the general path)
            return [IKResult._from_fields(fields) for fields in verified]
        return self._apart(verified, H)

    def _measured(self, Q: np.ndarray, H: np.ndarray) -> np.ndarray:
        """Each answer's (position error, orientation error, > 0 within the limits), as the
        general verdict measures them: one answer by Pinocchio's FK, several by the
        compiled FK (``verify.measure.measure_many``)."""
        out = np.empty((len(Q), 3))
        if len(Q) < 2:
            pose_checks(self.measured, self._placements(Q), H, Q, out)
        else:
            packed, kind, halton = self.flat
            fk_checks(packed, kind, halton, self.fk_measured, H, np.array(Q), out)
        return out

    def _apart(self, verified: list[dict], H: np.ndarray) -> list[IKResult]:
        """Results of ``verified`` fields measured apart (weights): each with its
        distances to ``H`` beside what its verdict measured (``armik.verify.distances``)."""
        Q = np.array([fields["q"] for fields in verified]).reshape(len(verified), -1)
        distances = np.empty((len(verified), 3))  # by the compiled FK that measured them
        packed, kind, halton = self.flat
        fk_checks(packed, kind, halton, self.fk_apart, H, Q, distances)
        out = []
        for fields, (pos, ori, _) in zip(verified, distances.tolist()):
            kept = fields_apart(fields, pos, ori if self.apart_rot else None, self.weighted, None)
            r = IKResult._from_fields(fields)
            r.extra["measured"] = kept
            out.append(r)
        return out

    def _placements(self, Q: np.ndarray) -> np.ndarray:
        """The tip placements (n, 4, 4) of the answers Q, by Pinocchio."""
        model, data, frame = self.model, self.arm.data, self.frame
        fk, place = pin.forwardKinematics, pin.updateFramePlacement
        if not self.direct:
            Q = [self.arm.to_pin(q) for q in Q]
        placements = []
        for q in Q:
            fk(model, data, q)
            placements.append(place(model, data, frame).homogeneous)
        return np.array(placements) if placements else np.empty((0, 4, 4))

    def _finish(self, answers: Answers, H, q0, opts, t0, every, xy=None, given=None):
        # parsed at the door (a plain one: ``_plain``), its aim or axis with it: not again;
        # a target given otherwise has neither (only a parsed one carries them)
        if type(given) is Target:
            target = given
        elif xy is not None:  # as the user gave it: the closed form reads it as given
            target = parse_target(np.array(xy), self.arm)
        else:
            target = parse_target(H[:3, 3].copy() if self.position else H, self.arm)
        return finish(self.arm, self.solver, answers, target, opts, q0, every, t0)


def _seed_copy(q0: object, shape: tuple) -> np.ndarray | None:
    """A contiguous float64 copy of a seed spelled another plain way (a list or tuple of
    Python numbers, a strided float64 row: what ``ArmModel.seed`` reads to the same values),
    else None. The runner still checks the values (finite, within the limits)."""
    kind = type(q0)
    if kind is list or kind is tuple:
        if len(q0) != shape[0] or not all(type(v) is float or type(v) is int for v in q0):
            return None
        try:
            return np.array(q0, dtype=float)
        except OverflowError:  # an int beyond a float's range: ``ArmModel.seed`` names it
            return None
    if kind is np.ndarray and q0.dtype == _FLOAT and q0.shape == shape:
        return np.ascontiguousarray(q0) if q0.flags.writeable else q0.copy()
    return None


def _rank_key(fields: dict) -> tuple:
    return failure_rank(fields["status"], fields["position_error"], fields["orientation_error"])


def _along(plane) -> bool:
    """Whether ``plane`` lies along two base axes (its normal along the third)."""
    return int(np.count_nonzero(plane.normal)) == 1
