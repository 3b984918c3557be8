"""What the viewer draws and solves, for one arm (``armik.load``) and for several tips of
one robot (``armik.load(..., tips=[...])``, an ``Arms``) alike: the joints, the tips, the
parts drawn and their poses for a configuration, and the solve of every tip's target.

Each tip's chain is an ``Arm`` whose Pinocchio model holds every link of the URDF, the
joints off the chain locked. Drawn side by side, the chains would draw each link once per
chain, the other chains' links at their locked values; so each link is drawn by the chain
in which it hangs from the deepest joint, the joint it really moves with (a link of the
right arm hangs from the torso in the left arm's model, from its own joint in the right
arm's). A stick figure draws only each chain's own joints: its parts are drawn once where
two chains share them.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from armik.arms import Arms
from armik.constraints.collision import arm_geometry
from armik.errors import InputError, OptionError
from armik.problem.tasks import Task
from armik.result import IKResult
from armik.solve.tasks import frame_ids
from armik.solvers import registry
from armik.view.body import Body, Part
from armik.view.scene import arm_body
from armik.view.stick import size, stick_body

if TYPE_CHECKING:
    from armik.model.arm_model import ArmModel


class Robot:
    """``robot`` (an ``Arm`` or an ``Arms``) as the viewer sees it. Attributes: ``tips``,
    ``chains`` (tip -> its arm model, ``Arm.kinematics``), ``name``, ``joint_names``,
    ``dof``, ``lower``, ``upper``, ``middle``, ``prismatic``, ``body`` (every part drawn,
    once), ``size`` (m) and ``centre`` (m, where the camera looks)."""

    def __init__(self, robot: object) -> None:
        if isinstance(robot, Arms):
            chains = {tip: robot.chain(tip).kinematics for tip in robot.tips}
            names = tuple(robot.joint_names)
        elif callable(getattr(robot, "solve", None)) and hasattr(robot, "kinematics"):
            chains = {robot.tip: robot.kinematics}  # type: ignore[attr-defined]
            names = tuple(robot.joint_names)  # type: ignore[attr-defined]
        else:
            raise InputError(
                f"the viewer takes an arm from armik.load(...), or several tips from "
                f"armik.load(..., tips=[...]), got {robot!r}"
            )
        self.source = robot
        self.chains: dict[str, ArmModel] = chains
        self.tips = tuple(chains)
        first = next(iter(chains.values()))
        self.name = first.name
        self.joint_names = names
        self.dof = len(names)
        index = {n: k for k, n in enumerate(names)}
        self._columns = {t: np.array([index[n] for n in a.joint_names]) for t, a in chains.items()}
        self.lower, self.upper = np.empty(self.dof), np.empty(self.dof)
        self.middle, self.prismatic = np.empty(self.dof), np.zeros(self.dof, bool)
        for tip, arm in chains.items():
            cols = self._columns[tip]
            self.lower[cols], self.upper[cols] = arm.lower, arm.upper
            self.middle[cols], self.prismatic[cols] = arm.middle, arm.prismatic
        if isinstance(robot, Arms):
            self.middle = np.array(robot.middle, dtype=float)
        origins = np.array([a.first_joint_origin for a in chains.values()])
        self.centre = origins.mean(axis=0)
        # every chain's reach from the centre the camera looks at
        reach = [
            size(a) + float(np.linalg.norm(o - self.centre))
            for a, o in zip(chains.values(), origins)
        ]
        self.size = max(reach)
        self.plane = first.plane if len(chains) == 1 else None
        self._bodies = [arm_body(a) for a in chains.values()]
        if len({b.kind for b in self._bodies}) > 1:  # cannot happen for one URDF; be safe
            self._bodies = [stick_body(a, "the chains' meshes differ") for a in chains.values()]
        self._keep = owned_parts(list(chains.values()), self._bodies)
        parts = [b.parts[k] for b, keep in zip(self._bodies, self._keep) for k in keep]
        self.body = Body(parts=tuple(parts), kind=self._bodies[0].kind, note=self._bodies[0].note)

    @property
    def several(self) -> bool:
        return len(self.tips) > 1

    def check_q(self, q: object, name: str = "q") -> np.ndarray:
        """``q`` as one value per joint (rad, m); ``OptionError`` naming the joints."""
        if not self.several:
            return self.chains[self.tips[0]].check_q(q, name)
        try:
            arr = np.array(q, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            arr = np.array([np.nan])
        if arr.shape != (self.dof,) or not np.isfinite(arr).all():
            raise OptionError(
                f"{name} must be {self.dof} finite numbers, one per joint of "
                f"{list(self.joint_names)} (rad, m), got {q!r}",
                option=name,
                value=q,
            )
        return arr

    def split(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """Each chain's joint values of ``q``."""
        return {tip: q[cols] for tip, cols in self._columns.items()}

    def poses(self, q: np.ndarray) -> np.ndarray:
        """(len(body.parts), 4, 4): every part's pose in the base frame for ``q``."""
        parts = self.split(q)
        return np.concatenate(
            [
                body.poses(arm, parts[tip])[keep]
                for (tip, arm), body, keep in zip(self.chains.items(), self._bodies, self._keep)
            ]
        ).reshape(-1, 4, 4)

    def fk(self, q: np.ndarray, tip: str) -> pin.SE3:
        """``T_base_tip`` at ``q``."""
        return self.chains[tip].fk(q[self._columns[tip]])

    def frame_pose(self, q: np.ndarray, tip: str, task: Task) -> pin.SE3:
        """The placement in the base frame of the frame ``task`` asks for (its ``frame``,
        None: the tip) on ``tip``'s chain at ``q``; ``TargetError`` for an unknown frame."""
        arm = self.chains[tip]
        if task.frame is None or task.frame in (tip, arm.tip):
            return self.fk(q, tip)
        ((frame,),) = frame_ids(arm, (task,))
        pin.forwardKinematics(arm.model, arm.data, arm.to_pin(q[self._columns[tip]]))
        return arm.T_base_world * pin.updateFramePlacement(arm.model, arm.data, frame)

    def tip_results(self, r: IKResult, tol: tuple = (1e-6, 1e-6)) -> dict[str, tuple[bool, tuple]]:
        """Per tip solved: (verified, (position error m, orientation error rad or None)).
        Chains solved together give no result per tip: a tip is then verified when its
        errors are within ``tol`` (m, rad), as the verdict measured them."""
        if not self.several:
            return {self.tips[0]: (r.success, (r.position_error, r.orientation_error))}
        errors = r.extra.get("errors", {})
        results = r.extra.get("results", {})
        out = {}
        for tip in self.tips:
            if tip in errors:
                pos, ori = errors[tip]
                mine = results.get(tip)
                if mine is not None:
                    ok = mine.success
                else:
                    ok = r.success or (pos <= tol[0] and (ori is None or ori <= tol[1]))
                out[tip] = (ok, (pos, ori))
        return out

    def solve(
        self, targets: Mapping[str, object], q0: object, solver: str, options: dict
    ) -> IKResult:
        """Every tip of ``targets`` at its target: ``Arm.solve`` (one tip) or
        ``Arms.solve`` with the same arguments."""
        if not self.several:
            (target,) = targets.values()
            return self.source.solve(target, q0=q0, solver=solver, **options)  # type: ignore[attr-defined]
        # "auto" is Arms.solve's default; chains sharing joints take no solver= at all
        chosen = {} if solver == "auto" else {"solver": solver}
        return self.source.solve(dict(targets), q0=q0, **chosen, **options)  # type: ignore[attr-defined]

    def check_collisions(self, options: Mapping[str, object]) -> None:
        """``CollisionError`` now, not at every drag, when ``options`` ask for collision
        checks (``obstacles``, ``self_collision``) and a chain has no collision geometry."""
        if options.get("obstacles") or options.get("self_collision"):
            for arm in self.chains.values():
                arm_geometry(arm)

    def check_solver(self, solver: str) -> None:
        """``SolverError`` for a name unknown or inapplicable to a chain."""
        for arm in self.chains.values():
            registry.choose(solver, arm)

    def solver_choices(self) -> list[str]:
        """'auto' and every registered solver that applies to every chain."""
        return [
            "auto",
            *(
                n
                for n in registry.solvers()
                if all(registry.why_not(n, a) is None for a in self.chains.values())
            ),
        ]


def owned_parts(chains: list, bodies: list[Body]) -> list[np.ndarray]:
    """For each chain, the indices of its body's parts it draws (module docstring)."""
    if bodies[0].kind != "meshes":
        seen: set = set()
        keep = []
        for arm, body in zip(chains, bodies):
            mine = []
            for k, part in enumerate(body.parts):
                key = _stick_key(arm, part)
                if key not in seen:
                    seen.add(key)
                    mine.append(k)
            keep.append(np.array(mine, dtype=int))
        return keep
    owner: dict[str, tuple[int, int]] = {}  # link -> (the URDF's joint id, chain)
    for i, (arm, body) in enumerate(zip(chains, bodies)):
        for part in body.parts:
            depth = _full_joint(arm, part.joint)
            if part.link not in owner or depth > owner[part.link][0]:
                owner[part.link] = (depth, i)
    return [
        np.array([k for k, p in enumerate(b.parts) if owner[p.link][1] == i], dtype=int)
        for i, b in enumerate(bodies)
    ]


def _full_joint(arm, joint: int) -> int:
    """The id in the whole URDF's model of joint ``joint`` of the chain's model: joints are
    numbered depth first, so of two joints a link hangs from the deeper has the larger."""
    if joint == 0:
        return 0
    return int(arm.chain.full.getJointId(arm.model.names[joint]))


def _stick_key(arm, part: Part) -> tuple:
    """What makes two stick figures' parts the same: what they draw, on which joint, where."""
    joint = arm.model.names[part.joint] if part.joint else ""
    where = np.round(part.placement, 9).tobytes()
    bounds = np.round(np.asarray(part.mesh.bounds, float), 9).tobytes()
    return part.link, joint, where, bounds
