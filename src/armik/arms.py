"""Several tips of one robot at once: ``armik.load(source, tips=[...])``.

Each tip's chain from the common base is an ``Arm`` of its own. Chains that share no
moving joint are solved side by side, each by its own best solver (a closed form where
one applies); the robot's configuration is the chains' joints side by side, in the order
of ``tips``. Chains that share joints (a torso, a lift) are solved together: one model
holds their union (``armik.model.union``) and the task solver (``armik.solve.tasks``)
takes one task per tip over every joint at once, with restarts within the budget; the
configuration is the union's joints in the model's order. Every answer is verified by
Pinocchio's FK of every tip. A result is one ``IKResult`` for the whole robot
(``armik.arms_joined``): ``q`` over every joint, a success when every tip's is one.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Collection, Mapping
from typing import cast

import numpy as np
import pinocchio as pin

from armik import arms_apart, arms_collision, arms_every, arms_many, arms_reach, reasons
from armik.arms_joined import by_tip_errors, joined
from armik.arms_kinematics import ArmsKinematics
from armik.arms_options import at_seed, held_apart, refuse_own_checks
from armik.arms_prefer import is_cost, ranked, scored
from armik.arms_request import ArmsRequest, coupled, read_request, score_of, together_options
from armik.arms_servo import ArmsServo
from armik.arms_tasks import absolute, as_tasks, by_tip, on, placed, rows_by_tip, solve_order
from armik.errors import ArmikError, FrameError, OptionError, TargetError
from armik.frozen import frozen
from armik.model import mimic
from armik.model.arm_model import ArmModel
from armik.model.union import Union
from armik.problem.problem import Problem, as_problem
from armik.problem.tasks import Pose, Relative, Task
from armik.request import Request
from armik.result import IKResult
from armik.solutions import Solutions
from armik.solve.read import options as read_options
from armik.solve.read import read, replayable
from armik.solve.single import routed
from armik.solve.stages import run
from armik.solve.tasks import measure_tasks, solve_tasks
from armik.targets.pose import Target, parse_by_tip


class Arms(ArmsKinematics):
    """The chains of ``tips`` of one robot, each an ``Arm`` (``chain(tip)``); its
    kinematics (``fk``, ``jacobian``, ``fk_batch``, ``within_limits``, ``random_q``,
    ``split``) in ``armik.arms_kinematics``."""

    def __init__(self, chains: Mapping[str, object]) -> None:
        """``chains``: tip -> its ``Arm`` (the facade, kept for ``chain``); everything
        else reads their models (``Arm.kinematics``)."""
        self._facades = dict(chains)
        self._chains: dict[str, ArmModel] = {
            tip: arm.kinematics  # type: ignore[attr-defined]
            for tip, arm in chains.items()
        }
        chains = self._chains
        mimic.across(chains)  # a mimic joint on one chain driven from another: refused
        names = [j for arm in chains.values() for j in arm.joint_names]
        shared = sorted({n for n in names if names.count(n) > 1})
        self.tips: tuple[str, ...] = tuple(chains)
        self.shared: tuple[str, ...] = tuple(shared)
        # chains sharing a joint are solved together, in one model (``model.union``)
        self._union = Union(list(self._chains.values())) if shared else None
        if self._union is not None:
            self.joint_names: tuple[str, ...] = self._union.joint_names
            self.lower, self.upper = self._union.lower, self._union.upper
            self.middle = self._union.middle
        else:
            self.joint_names = tuple(names)
            arms = list(self._chains.values())
            self.lower = np.concatenate([a.lower for a in arms])
            self.upper = np.concatenate([a.upper for a in arms])
            self.middle = np.concatenate([a.middle for a in arms])
        self.dof = len(self.joint_names)
        kinds: dict[str, bool] = {}  # each joint's kind, read from the chains that hold it
        for arm in chains.values():
            kinds.update(zip(arm.joint_names, arm.prismatic.tolist()))
        self.prismatic = np.array([kinds[n] for n in self.joint_names], dtype=np.bool_)
        # chains sharing no joint in one model, built for the first coupling task, and
        # the column of each of ``joint_names`` in it
        self._coupled: Union | None = None
        self._plain: tuple | None = None  # ``descent_settings`` of a call without options
        self._bare: ArmsRequest | None = None  # the request of a call without options
        self._permutation: np.ndarray | None = None
        self._apart = None  # each chain's model checking collisions within the robot
        self._checkers = {}  # the robot's collision checkers, one per set of obstacles
        index = {n: k for k, n in enumerate(self.joint_names)}
        self._columns = {
            tip: np.array([index[n] for n in arm.joint_names]) for tip, arm in self._chains.items()
        }
        self._middle_seeds = self.split(self.middle)  # each chain's seed when q0 is None: read only

    def __reduce__(self) -> tuple[type[Arms], tuple[dict[str, object]]]:
        return (Arms, (self._facades,))  # its chains as their recipes: a backend's jobs carry it

    def __repr__(self) -> str:
        offsets = self.tip_offsets
        said = f", tip_offsets={offsets}" if offsets else ""
        return f"Arms(tips={list(self.tips)}, dof={self.dof}{said})"

    def solve(self, targets: Mapping[str, object], *, q0: object = None, **options) -> IKResult:
        """Every tip at its target (any target form ``Arm.solve`` takes, or a task list),
        each chain by its own solver; one ``IKResult`` for the robot (module docstring)."""
        # the options read once (``armik.arms_request``), then the targets: one row
        request = read_request(self, replayable(options)) if options else self._bare
        if request is None:
            request = read_request(self, options)
        if q0 is not None:  # the whole q0, its bad joints named: not one chain's part of it
            q0 = self._seed(q0)  # clipped into the limits, as Arm's seed
        parsed, relative = self._parsed(targets)
        return self._solve_row(request, parsed, relative, q0)

    def _parsed(
        self, targets: Mapping[str, object], read: Collection[str] = ()
    ) -> tuple[dict[str, object], dict[str, list[Relative]]]:
        """(targets, relative): ``targets`` as given to ``solve`` read once, tip -> a parsed
        pose or position (a ``Target``) or its tasks, in the robot's order of tips (``read``:
        tips whose targets are parsed already, rows of a ``TargetBatch``); each tip's
        ``Relative`` tasks (``_check_targets``)."""
        # a flat list of tasks read by tip; the tips in the robot's order, as the solve's
        if type(targets) is not dict or tuple(targets) != self.tips:  # else as by_tip gives it
            targets = by_tip(self._chains, targets)
        relative = self._check_targets(targets)
        poses = {t: v for t, v in targets.items() if type(v) in _PLAIN or not as_problem(v)}
        if read:
            poses = {t: v for t, v in poses.items() if t not in read}
        if not poses:  # task lists only: as given
            return dict(targets), relative
        return {**targets, **parse_by_tip(poses, self._chains)}, relative  # task lists as given

    def _solve_row(
        self, request: ArmsRequest, targets: dict, relative: dict, q0: np.ndarray | None
    ) -> IKResult:
        """One row: ``targets`` (``_parsed``'s, with their ``relative`` tasks) from ``q0``
        (checked, or None) as ``request`` asks, what ``solve``, a batch's and a path's rows
        return: where the chains' first answers collide, the nearest clear combination."""
        r = self._answer(request, targets, relative, q0, time.perf_counter())
        if not request.options:
            return r
        return arms_collision.clear_or_other(self, r, request, targets, relative, q0)

    def _answer(
        self, request: ArmsRequest, targets: dict, relative: dict, q0: np.ndarray | None, t0
    ) -> IKResult:
        """``_solve_row``'s answer before any check between the chains."""
        chains = self._chains
        if self._union is not None:
            beyond = {} if relative else arms_reach.beyond_reach(chains, targets)
            if beyond:
                return arms_reach.reaching(self, beyond, targets, q0, request, t0)
            return self._solve_together(self._union, targets, relative, q0, request, t0)
        seeds = self._middle_seeds if q0 is None else self.split(q0)
        solver, prefer, held = request.solver, request.prefer, request.each
        if not relative:  # each chain alone: the common case, kept short
            if is_cost(prefer):  # a cost of the whole configuration (``arms_prefer``)
                own = request.chains_options(self.tips)
                start = self.middle if q0 is None else q0
                seeds = held_apart(seeds, own, chains, targets)
                return ranked(self, targets, seeds, start, prefer, own, 1, t0)[0]
            seeds = held_apart(seeds, held, chains, targets) if held else seeds
            results = {
                tip: self._solve_chain(tip, target, seeds[tip], solver, held[tip] if held else {})
                for tip, target in targets.items()
            }
            r = joined(self.tips, results, seeds, time.perf_counter() - t0)
            return r if prefer is None else scored(r, prefer)
        order = solve_order(targets, relative)
        if order is None:  # tips placed relative to each other in a cycle: all at once
            return self._solve_together(self._joint(), targets, relative, q0, request, t0)
        if is_cost(prefer):  # the cost's whole configuration: no chain's
            score_of(self, prefer)
        results = {}
        held = held or {tip: {} for tip in self.tips}
        seeds = held_apart(seeds, held, chains, targets)
        for tip in order:
            # a pose relative to a chain already solved is a pose in the base: exactly,
            # bounds included, since the chains share no joint
            target = targets[tip]
            if tip in relative:
                target = absolute(target, self._placements(results, seeds))
            results[tip] = self._solve_chain(tip, target, seeds[tip], solver, held[tip])
        each = joined(self.tips, results, seeds, time.perf_counter() - t0)
        if each.success:
            return each if prefer is None else scored(each, prefer)
        # the reference chain's answer may be one the other cannot reach from: together
        try:
            first = np.clip(each.q, self.lower, self.upper)  # held values: still q0's
            together = self._solve_together(
                self._joint(), targets, relative, q0, request, t0, first
            )
        except OptionError as e:  # an option the chains took and the joint descent does not
            return dataclasses.replace(each, reason=reasons.not_together(each.reason, e.option))
        return together if together.success else each

    def solve_all(
        self, targets: Mapping[str, object], *, q0: object = None, **options
    ) -> Solutions:
        """Every answer for one target per tip, best first (``armik.arms_every``), as
        ``Arm.solve_all`` gives them: a ``Solutions``."""
        request = read_request(self, replayable(options) if options else options)
        if q0 is not None:
            q0 = self._seed(q0)  # clipped into the limits, as Arm's seed
        parsed, relative = self._parsed(targets)
        found = arms_every.solve_all(self, request, parsed, relative, q0)
        asked = arms_collision.between(self, request.options, parsed)
        return Solutions(arms_collision.kept(self, found, asked))

    def solve_batch(self, targets: Mapping[str, object], *, q0: object = None, **options):
        """Many targets per tip (tip -> N targets, or N rows each a flat list of tasks as
        ``solve`` takes): a ``BatchResult`` over every joint, each
        chain's own batch where the chains are independent (``armik.arms_many``);
        ``workers``, ``chunk_size``, ``progress`` and ``backend`` as ``Arm.solve_batch``'s
        (``backend`` runs chunks of rows where they are solved one by one)."""
        options = replayable(options) if options else options
        refuse_own_checks(options, self.tips)
        targets = rows_by_tip(self._chains, targets, options)  # flat task lists: by tip
        return arms_many.solve_batch(self, targets, q0=q0, **options)

    def servo(self, q0: object, **options: object) -> ArmsServo:
        """A servo for every tip at once, one target per tip a tick (``step({tip: target})``),
        each chain its own ``Servo`` with ``Arm.servo``'s options (``armik.arms_servo``);
        chains that share joints one step over their union (``armik.servo.union``)."""
        return ArmsServo(self, q0, **(replayable(options) if options else options))

    def solve_path(
        self,
        poses: Mapping[str, object],
        q0: object = None,
        *,
        max_joint_step: float | np.ndarray | None = None,
        plan: str = "follow",
        **options,
    ):
        """Waypoints per tip (``poses``: tip -> N waypoints, or N flat task lists; named as
        ``Arm.solve_path``'s) in order from ``q0``, never with a silent jump larger than
        ``max_joint_step`` (``armik.arms_many``)."""
        options = replayable(options) if options else options
        refuse_own_checks(options, self.tips)
        waypoints = rows_by_tip(self._chains, poses, options)
        return arms_many.solve_path(
            self, waypoints, q0, max_joint_step=max_joint_step, plan=plan, **options
        )

    def _placements(self, results: dict[str, IKResult], seeds: dict) -> dict[str, pin.SE3]:
        """Each tip's placement: at its answer where solved, else at its seed."""
        return {
            tip: arm.fk(results[tip].q if tip in results else seeds[tip])
            for tip, arm in self._chains.items()
        }

    def _solve_together(
        self, union: Union, targets, relative: dict, q0, request: ArmsRequest, t0, first=None
    ):
        """Chains sharing joints: one task per tip on ``union``, the task solver (``relative``:
        each tip's ``Relative`` tasks). ``request.solver`` names the chains' own solver, which
        gives the descent its starts (from ``first`` where given, else q0)."""
        shared = union is self._union  # else chains sharing no joint, a task relating them
        prefer, solver = request.prefer, request.solver
        score = request.score if shared or prefer is None else score_of(self, prefer)
        opts, unbound, budget = request.together if shared else coupled(self, request)  # type: ignore[misc]
        tasks: list[Task] = []
        given: list[str] = []  # the tip each task is given by: whose errors it counts in
        for tip, target in targets.items():
            if type(target) is Target and target.rotation is not None:  # the common case
                tasks.append(Pose.of(target, tip))
            else:
                tasks += as_tasks(target, tip, self.tips)
            given += [tip] * (len(tasks) - len(given))
        seed = self.middle if q0 is None else np.asarray(q0, float)
        # each chain's start (``_start``); None held at q0's value, not a restart's random one
        held = request.each if shared else together_options(request)
        held = at_seed(held, self.joint_names, seed) if held else None
        start = self._start(targets, seed if first is None else first, relative, solver, held)
        order = self._permutation
        start = start if order is None else _scatter(start, order)

        def reseed(rng: np.random.Generator) -> np.ndarray:
            # a random configuration, each chain then solved by its own compiled solver in a
            # random order (the first sets the torso): nearer an answer than a random one
            # over many joints, and not always the same basin (TALOS's two hands: 6 misses
            # in 1000 targets against 14 from a random configuration alone)
            # a few attempts a chain (the descent's restarts search): each chain solved on the
            # whole budget again, a check no answer holds made the restarts cost its square
            few = {tip: _few(held[tip] if held else {}) for tip in self.tips}
            q = self._start(targets, self._random(rng), relative, solver, few, rng)
            return q if order is None else _scatter(q, order)

        reference = seed if order is None else _scatter(seed, order)  # the score's q0
        # held joints at q0's values (not the start's), a box row of every step
        constraints = tuple([c.at(cast(ArmModel, union), reference) for c in unbound])
        problem = frozen(Problem, tasks=tuple(tasks), constraints=constraints, budget=budget)
        r = solve_tasks(  # the union serves as the arm (what solve_tasks reads of one)
            cast(ArmModel, union), problem, start, opts, t0,
            reseed=reseed, score=score, reference=reference,
        )  # fmt: skip
        measured = r.extra["task_errors"]
        # each tip's errors are its frames' true distances, as the result's (the tasks'
        # centres), not a region's or a weighting's measure: as on chains solved apart
        true = measured  # exact poses: what the verdict measured is the distance
        if not all([type(t) is Pose and not t.bounds.any() and t.weights.all() for t in tasks]):
            centres = tuple([t.centre() for t in tasks])
            if any([c is not t for c, t in zip(centres, tasks)]):
                true = measure_tasks(cast(ArmModel, union), Problem(centres), r.q, opts)
        if order is not None:  # back to the chains' joints side by side
            r = dataclasses.replace(r, q=r.q[order])
        errors, failed = by_tip_errors(given, measured, true)
        reason = r.reason if not failed else f"tips not within their tasks: {failed}; {r.reason}"
        extra = {**r.extra, "errors": errors}  # r's fields are of their types: no __init__
        return frozen(IKResult, **{**r.__dict__, "reason": reason, "extra": extra})

    def _start(
        self,
        targets: Mapping[str, object],
        q: np.ndarray,
        relative: dict[str, list[Relative]],
        solver: str,
        held: dict[str, dict] | None,
        rng: np.random.Generator | None = None,
    ):
        """Where the descent over every joint starts: each chain in turn solved by its own
        compiled solver (``solver``, with its options ``held``; None: none) from ``q``, the
        joints an earlier chain set (a torso) kept at its values; the descent then
        reconciles the chains. With ``rng``, the chains that no relative task (``relative``)
        orders go in a random order (a restart: another chain sets the torso)."""
        q = q.copy()
        fixed = np.zeros(self.dof, dtype=bool)
        order = (solve_order(targets, relative) if relative else None) or list(targets)
        if rng is not None and not relative:
            order = [order[i] for i in rng.permutation(len(order))]
        for tip in order:
            cols = self._columns[tip]
            target = targets[tip]
            try:
                if tip in relative:
                    placements = {t: self._chains[t].fk(q[c]) for t, c in self._columns.items()}
                    target = absolute(target, placements)
                r = self._solve_chain(tip, target, q[cols], solver, held[tip] if held else {})
            except ArmikError:  # a task this chain's solver does not take: start as is
                continue
            free = ~fixed[cols]  # a failed answer may leave the limits: a start within them
            chain = self._chains[tip]
            q[cols[free]] = np.clip(r.q, chain.lower, chain.upper)[free]
            fixed[cols] = True
        return q

    def _solve_chain(
        self, tip: str, target: object, q0: np.ndarray, solver: str, options: dict
    ) -> IKResult:
        """One chain's answer by ``solver`` with its own options (``Arm.solve``'s route), its
        target parsed (a ``Target``: not read again) or its tasks."""
        if not options and type(target) is Target and target.aim is None:
            # nothing to read: the request ``read`` gives a plain pose, built as it builds it
            request = _new(Request, (target, q0, solver, _NO_OPTIONS, (), 0, False,
                                     time.perf_counter(), None, None, None, None))  # fmt: skip
            return run(self._chains[tip], request)  # type: ignore[no-any-return]
        arm = arms_apart.model(self, tip, options) if options else self._chains[tip]  # collisions
        request = read(arm, target, q0, solver, options, parsed_already=type(target) is Target)
        if request.score is None and request.problem is None:  # the compiled path's stages
            return run(arm, request)  # type: ignore[no-any-return]
        return routed(arm, request)  # type: ignore[no-any-return]

    def _chain_every(
        self, tip: str, target: object, q0: np.ndarray, solver: str, options: dict
    ) -> Solutions:
        """Every answer of one chain by ``solver`` with its own options (``Arm.solve_all``'s
        route, as ``_solve_chain`` gives one), its target parsed or its tasks."""
        arm = arms_apart.model(self, tip, options) if options else self._chains[tip]  # collisions
        parsed = type(target) is Target
        request = read(arm, target, q0, solver, options, True, parsed_already=parsed)
        plain = request.score is None and request.problem is None  # the compiled path's stages
        got = run(arm, request) if plain else routed(arm, request)
        return got if type(got) is Solutions else Solutions(got)

    def _check_targets(self, targets: object) -> dict[str, list[Relative]]:
        """Each tip's ``Relative`` tasks, once the targets are checked: a mapping of known
        tips, each relative task on its own tip and relative to a known one."""
        if type(targets) is dict and targets and targets.keys() <= self._chains.keys():
            relative = _relative(targets, self._chains)  # the common case: known tips
            if not relative:
                return relative
        if not isinstance(targets, Mapping):
            raise OptionError(
                f"targets must map tip names {list(self.tips)} to targets, got {targets!r}",
                option="targets",
                value=targets,
            )
        if not targets:
            raise TargetError(
                f"targets is an empty mapping {targets!r}: give a target for one or more of "
                f"this robot's tips {list(self.tips)}, as {{tip: target}}"
            )
        unknown = [t for t in targets if t not in self._chains]
        relative = _relative(targets, self._chains)
        for tip, rel in relative.items():
            if tip in self._chains:
                unknown += [t.relative_to for t in rel if t.relative_to not in self._chains]
                for t in rel:
                    on(t, tip, self.tips)  # a pose of this tip's frame, not another's
        if unknown:
            raise FrameError(
                f"unknown tips {unknown}; this robot's tips: {list(self.tips)}",
                frame=str(unknown[0]),
                candidates=self.tips,
            )
        return relative


def _relative(targets: Mapping[str, object], chains: Mapping[str, ArmModel]) -> dict:
    """Each tip's ``Relative`` tasks, once each known tip's tasks are checked to be on frames
    its chain moves (``arms_tasks.placed``)."""
    out: dict[str, list[Relative]] = {}
    for tip, target in targets.items():
        problem = None if type(target) in _PLAIN else as_problem(target)
        if problem is None:
            continue
        if tip in chains:
            placed(chains, tip, problem.tasks)
        found = [t for t in problem.tasks if isinstance(t, Relative)]
        if found:
            out[tip] = found
    return out


_PLAIN = (np.ndarray, pin.SE3, Target)  # target types that hold no task: skipped unread


_new = tuple.__new__  # a ``Request`` built as the tuple it is (``armik.solve.read``'s way)
_NO_OPTIONS = read_options({})  # the validated options of a call without any


def _scatter(q: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Joint values in ``joint_names`` order as the union's (``order``: their columns)."""
    out = np.empty_like(q)
    out[order] = q
    return out


def _few(options: dict) -> dict:
    """A chain's ``options`` with 3 restarts, in its budget where it gives one."""
    if "budget" in options:
        return {**options, "budget": dataclasses.replace(options["budget"], restarts=3)}
    return {**options, "max_restarts": 3}
