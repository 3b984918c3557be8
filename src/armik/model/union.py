"""Several chains of one URDF from one base in one Pinocchio model: the joints on any chain
free, every other joint held at its value in the chains' arms (neutral, or ``locked``).

``armik.arms.Arms`` solves chains that share a joint (a torso, a lift) on it with the task
solver (``armik.solve.tasks``), one task per tip, verified by Pinocchio's FK of this model.
It gives that solver what it reads of an arm: the model, per-thread data, joint values to
Pinocchio's configuration, limits, seeds and the base frame. Revolute, prismatic and
continuous joints; a chain with a mimic joint is refused. A tip's frame is its tool point
where its chain has a ``tip_offset``, as on the chain.
"""

from __future__ import annotations

import math
import threading

import numpy as np
import pinocchio as pin

from armik.errors import JointError, TargetError
from armik.model import mimic_frames
from armik.model.frames import named
from armik.model.mimic import joint_of
from armik.model.reduce import reduce_model, set_joint
from armik.tolerances import LIMIT_TOL

TWO_PI = 2.0 * math.pi


class Union:
    """The union of ``chains`` (``Arm`` objects of one URDF, one base) in one model."""

    def __init__(self, chains: list) -> None:
        first = chains[0]
        full = first.chain.full  # the URDF's whole model, as the chains were cut from it
        names = list(dict.fromkeys(j for arm in chains for j in arm.joint_names))
        for arm in chains:
            if arm.mimics:
                raise JointError(
                    f"the chain to {arm.tip!r} has mimic joints: several tips over shared "
                    "joints take chains without them for now",
                    joint=next(iter(arm.mimics)),
                )
        # every joint off the chains held where the chains hold it: at its lock, a mimic
        # joint fixed on a chain at its driver's value (``reduce``), else neutral
        q_ref = pin.neutral(full)
        for arm in chains:
            for jname, value in {**arm.locked, **(arm.chain.fixed_mimics or {})}.items():
                set_joint(full, q_ref, joint_of(full, jname), value)
        keep = {joint_of(full, n) for n in names}
        lock = [j for j in range(1, full.njoints) if full.joints[j].nq > 0 and j not in keep]
        self.model = reduce_model(full, lock, q_ref)
        for arm in chains:  # a tip names its tool point, as on its chain (``frames.frame_id``)
            if arm.tip_offset is not None:
                _to_tool_point(self.model, arm.tip, arm.tip_offset)
        self.tip = first.tip
        self.tip_frame_id = named(self.model, first.tip)  # a link's, where a joint shares it
        base = named(self.model, first.base)
        data = self.model.createData()
        pin.framesForwardKinematics(self.model, data, pin.neutral(self.model))
        self.T_base_world = data.oMf[base].inverse()
        ids = [joint_of(self.model, n) for n in names]
        self._order = sorted(range(len(ids)), key=lambda k: self.model.joints[ids[k]].idx_v)
        self.joint_names = tuple(names[k] for k in self._order)
        self.dof = self.model.nv
        joints = [self.model.joints[joint_of(self.model, n)] for n in self.joint_names]
        self._continuous = [j.nq == 2 for j in joints]
        # each joint's limits as its chain reads them (the URDF's "0 0" and +-1e16 unlimited,
        # a continuous joint unlimited): Pinocchio's model holds the numbers as written
        limits = {
            n: (lo, hi)
            for arm in chains
            for n, lo, hi in zip(arm.joint_names, arm.lower.tolist(), arm.upper.tolist())
        }
        self.lower = np.array([limits[n][0] for n in self.joint_names])
        self.upper = np.array([limits[n][1] for n in self.joint_names])
        # as ``ArmModel``'s, for a configuration's turns (``model.turns``): no mimic here, so
        # 2 pi is a period of every joint but a prismatic one
        prismatic = [j.shortname().startswith("JointModelP") for j in joints]
        self._limit_lists = (self.lower.tolist(), self.upper.tolist(), prismatic)
        self.prismatic = np.array(prismatic, dtype=bool)  # a held value's unit (``Hold.at``)
        bounded = np.isfinite(self.lower) & np.isfinite(self.upper)
        self.middle = 0.5 * (
            np.where(bounded, self.lower, 0.0) + np.where(bounded, self.upper, 0.0)
        )
        self._local = threading.local()
        self._derived: dict = {}  # ``armik.model.derived``: what modules keep (frame chains)
        self._chains = tuple(chains)

    def chain_of(self, tip: str):
        """The chain of ``tip`` (its ``ArmModel``) among those this union joins."""
        return next(chain for chain in self._chains if chain.tip == tip)

    @property
    def data(self) -> pin.Data:
        data = getattr(self._local, "data", None)
        if data is None:
            data = self._local.data = self.model.createData()
        return data

    def to_pin(self, q: np.ndarray) -> np.ndarray:
        """Joint values (rad, m; one angle per continuous joint) as Pinocchio's q."""
        if self.model.nq == self.dof:  # no continuous joint: q is Pinocchio's q (the solver's loop)
            return np.array(q, dtype=float)
        qp = np.empty(self.model.nq)
        k = 0
        for value, continuous in zip(np.asarray(q, dtype=float), self._continuous):
            if continuous:
                qp[k], qp[k + 1] = math.cos(value), math.sin(value)
                k += 2
            else:
                qp[k] = value
                k += 1
        return qp

    def fk(self, q: np.ndarray, frame: str | None = None) -> pin.SE3:
        fid = self.tip_frame_id if frame is None else named(self.model, frame)
        pin.forwardKinematics(self.model, self.data, self.to_pin(q))
        return self.T_base_world * pin.updateFramePlacement(self.model, self.data, fid)

    def refuse_followed(self, frame: str) -> None:
        """A ``TargetError`` for a task on ``frame`` where a mimic joint off the chains turns
        it with a chain's joint (``mimic_frames``): the union holds that joint still."""
        for arm in self._chains:
            if mimic_frames.full_frame(arm, frame) is not None:
                raise TargetError(
                    f"frame {frame!r} is turned by a mimic joint off the chains, with a joint "
                    f"of the chain to {arm.tip!r}: over shared joints the task solver holds "
                    f"that mimic joint still; solve that chain alone (robot.chain({arm.tip!r})"
                    ".solve([...])), or give a frame on a chain"
                )

    def joint_index(self, name: str) -> int:
        """Index of joint ``name`` in q; raises ``JointError`` listing the joints."""
        if name not in self.joint_names:
            raise JointError(
                f"joint {name!r} is on none of these chains; joints: {list(self.joint_names)}",
                joint=name,
            )
        return self.joint_names.index(name)

    def seed(self, q0: object) -> np.ndarray:
        return self.middle.copy() if q0 is None else np.asarray(q0, dtype=float).copy()

    def random_q(self, rng: np.random.Generator | int | None = None) -> np.ndarray:
        rng = np.random.default_rng(rng)
        lo = np.where(np.isfinite(self.lower), self.lower, -math.pi)
        hi = np.where(np.isfinite(self.upper), self.upper, math.pi)
        return rng.uniform(lo, hi)

    def within_limits(self, q: np.ndarray, tol: float = LIMIT_TOL) -> bool:
        q = np.asarray(q, dtype=float)
        return bool(np.all(q >= self.lower - tol) and np.all(q <= self.upper + tol))


def _to_tool_point(model: pin.Model, tip: str, offset: tuple[float, float, float]) -> None:
    """The frame ``tip`` of ``model`` moved by ``offset`` (m, in the tip frame): a tip's
    name means its tool point on its chain, where ``tip_offset`` adds it (``reduce``), and
    so it does where the chains are solved together and verified on this model."""
    link = model.frames[named(model, tip)]
    for fid, frame in enumerate(model.frames):  # a joint's frame of the name, where it is
        if frame.name == tip and frame.parentJoint == link.parentJoint:  # the link's (SCARA)
            if frame.placement.isApprox(link.placement, 1e-12):
                offset_se3 = pin.SE3(np.eye(3), np.asarray(offset, dtype=float))
                frame.placement = link.placement * offset_se3
                model.frames[fid] = frame
