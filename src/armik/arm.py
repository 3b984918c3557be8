"""Arm: a Pinocchio chain from a base frame to a tip frame.

Joint values seen by users are one number per joint: radians for revolute and continuous
joints, metres for prismatic ones. Pinocchio stores a continuous joint as (cos, sin)
(nq = 2, nv = 1); the conversion lives here and nowhere else.
"""

from __future__ import annotations

import logging
import math
import threading
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path

import numpy as np
import pinocchio as pin

from .errors import ArmikWarning, FrameError, JointError, OptionError, URDFError, listing
from .planar import Plane, find_plane
from .robots import CATALOGUE, entry
from .urdf import URDFInfo, read_urdf

log = logging.getLogger(__name__)

TWO_PI = 2.0 * math.pi
LIMIT_TOL = 1e-12  # joint values this close outside a limit still count as inside
_FRAME_PREFERENCE = (pin.BODY, pin.OP_FRAME, pin.FIXED_JOINT, pin.JOINT, pin.SENSOR)


def load(
    source: str | Path,
    *,
    base: str | None = None,
    tip: str | None = None,
    locked: Mapping[str, float] | None = None,
    tip_offset: tuple[float, float, float] | None = None,
) -> Arm:
    """Load an arm from a bundled robot name (see ``armik.robots()``) or a URDF path.

    The chain runs from ``base`` (default: the URDF root link) to ``tip`` (default: the
    catalogue tip, else the single leaf frame). Every joint off the chain is locked at the
    value in ``locked`` (joint name -> rad or m) or at its neutral value. ``tip_offset``
    (m, in the tip frame) moves the tool point.

    Raises ``URDFError``, ``FrameError`` or ``JointError`` (all ``ValueError``) naming the
    bad value and the fix.
    """
    if not isinstance(source, (str, Path)):
        raise URDFError(
            f"source must be a robot name or a path to a URDF file, got {source!r}",
            path=str(source),
        )
    name = str(source)
    if isinstance(source, str) and source in CATALOGUE:
        spec = entry(source)
        path = spec.urdf_path()
        tip = tip if tip is not None else spec.tip
        base = base if base is not None else spec.base
        if tip_offset is None and tip == spec.tip:
            tip_offset = spec.tip_offset
        locked = {**spec.locked, **(locked or {})}
    else:
        path = Path(source)
        if not path.exists() and path.suffix.lower() not in (".urdf", ".xml"):
            raise URDFError(
                f"{name!r} is neither a bundled robot ({listing(CATALOGUE)}) nor an existing "
                "URDF file: check the name or the path",
                path=name,
            )
        name = path.stem
    model, info = read_urdf(path)
    arm = Arm(
        model,
        info,
        name=name,
        base=base,
        tip=tip,
        locked=locked or {},
        tip_offset=tip_offset,
        source=str(path),
    )
    arm._recipe = Recipe(str(source), base, tip, dict(locked or {}), arm.tip_offset)
    return arm


@dataclass(frozen=True)
class Recipe:
    """How an arm was built: what ``load`` was given and the limits replaced since. An
    ``Arm`` pickles as its recipe (a Pinocchio model does not pickle portably) and is
    rebuilt from it, so arms travel to worker processes; the URDF must be readable there."""

    source: str
    base: str | None
    tip: str | None
    locked: dict[str, float]
    tip_offset: tuple[float, float, float] | None
    limits: tuple[tuple[str, float, float], ...] = ()

    def build(self) -> Arm:
        arm = load(
            self.source,
            base=self.base,
            tip=self.tip,
            locked=self.locked or None,
            tip_offset=self.tip_offset,
        )
        if self.limits:
            arm = arm.with_limits({name: (lo, hi) for name, lo, hi in self.limits})
        return arm


def _rebuild(recipe: Recipe) -> Arm:
    return recipe.build()


def _frame_id(model: pin.Model, name: str) -> int:
    for ftype in _FRAME_PREFERENCE:
        if model.existFrame(name, ftype):
            return model.getFrameId(name, ftype)
    raise KeyError(name)


class Arm:
    """The kinematic chain of one robot arm; built by ``armik.load``.

    Attributes: ``dof``, ``joint_names``, ``joint_types``, ``lower``, ``upper`` (rad or m;
    -inf/+inf for continuous joints), ``neutral``, ``middle``, ``base``, ``tip``, ``model``
    (the reduced Pinocchio model, not to be modified).
    """

    def __init__(
        self,
        full: pin.Model,
        info: URDFInfo,
        *,
        name: str,
        base: str | None,
        tip: str | None,
        locked: Mapping[str, float],
        tip_offset: tuple[float, float, float] | None,
        source: str,
    ) -> None:
        self.name = name
        self.source = source
        frames = [f.name for f in full.frames if f.name != "universe"]
        self.base = base if base is not None else info.root_link
        self.tip = tip if tip is not None else self._single_leaf(full, frames)
        base_id = self._lookup_frame(full, self.base, "base", frames)
        tip_id = self._lookup_frame(full, self.tip, "tip", frames)

        base_joint = full.frames[base_id].parentJoint
        tip_joint = full.frames[tip_id].parentJoint
        tip_support = list(full.supports[tip_joint])
        if base_joint not in tip_support:
            raise FrameError(
                f"tip {self.tip!r} is not downstream of base {self.base!r}: no chain leads "
                "from the base to the tip; swap them or pick frames on one branch",
                frame=self.tip,
                candidates=frames,
            )
        chain = [j for j in tip_support[tip_support.index(base_joint) + 1 :]]
        if not chain:
            raise FrameError(
                f"the chain from {self.base!r} to {self.tip!r} has no moving joint: "
                "pick a tip further from the base",
                frame=self.tip,
                candidates=frames,
            )
        for j in chain:
            jname = full.names[j]
            if full.joints[j].nv != 1:
                raise JointError(
                    f"joint {jname!r} ({full.joints[j].shortname()}) has {full.joints[j].nv} "
                    "degrees of freedom; armik handles revolute, continuous and prismatic joints",
                    joint=jname,
                )
            if jname in info.mimic:
                raise JointError(
                    f"joint {jname!r} on the chain mimics {info.mimic[jname]!r}; mimic joints "
                    "on the chain are not supported: pick a tip before it or remove the mimic tag",
                    joint=jname,
                )

        q_ref = pin.neutral(full)
        all_joints = list(full.names)[1:]
        for jname, value in locked.items():
            if not full.existJointName(jname):
                raise JointError(
                    f"locked joint {jname!r} does not exist; joints: {listing(all_joints)}",
                    joint=jname,
                    candidates=all_joints,
                )
            jid = full.getJointId(jname)
            if jid in chain:
                raise JointError(
                    f"locked joint {jname!r} lies on the chain from {self.base!r} to "
                    f"{self.tip!r}; only joints off the chain can be locked",
                    joint=jname,
                    candidates=all_joints,
                )
            try:
                number = float(value)
            except (TypeError, ValueError):
                number = math.nan
            if not math.isfinite(number):
                raise JointError(
                    f"locked value for {jname!r} must be a finite number (rad or m), got {value!r}",
                    joint=jname,
                )
            _set_joint(full, q_ref, jid, number)
        to_lock = [j for j in range(1, full.njoints) if j not in chain]
        model = pin.buildReducedModel(full, to_lock, q_ref) if to_lock else full.copy()

        tip_frame = _frame_id(model, self.tip)
        if tip_offset is not None:
            frame = model.frames[tip_frame]
            placement = frame.placement * pin.SE3(np.eye(3), np.asarray(tip_offset, float))
            tip_frame = model.addFrame(
                pin.Frame(self.tip + "_tool", frame.parentJoint, tip_frame, placement, pin.OP_FRAME)
            )
        self.model = model
        self.tip_frame_id = tip_frame
        self.tip_offset = None if tip_offset is None else tuple(float(v) for v in tip_offset)

        # The base frame's own joint is locked, so its world placement is a constant.
        data_full = full.createData()
        pin.framesForwardKinematics(full, data_full, q_ref)
        self.T_world_base = data_full.oMf[base_id].copy()
        self.T_base_world = self.T_world_base.inverse()
        self._base_is_world = self.T_world_base.isIdentity(1e-15)

        self._setup_joints(info)
        self._local = threading.local()
        self._recipe: Recipe | None = None  # set by ``load``; an Arm built directly has none

    # -- construction helpers -------------------------------------------------------------

    @staticmethod
    def _single_leaf(full: pin.Model, frames: list[str]) -> str:
        parents = {full.frames[i].parentFrame for i in range(full.nframes)}
        leaves = [
            full.frames[i].name
            for i in range(1, full.nframes)
            if i not in parents and full.frames[i].type == pin.BODY
        ]
        if len(leaves) == 1:
            return leaves[0]
        raise FrameError(
            f"no tip given and the URDF has {len(leaves)} leaf links; pass tip= one of "
            f"{listing(leaves)}",
            frame="",
            candidates=leaves,
        )

    @staticmethod
    def _lookup_frame(full: pin.Model, name: str, role: str, frames: list[str]) -> int:
        try:
            return _frame_id(full, name)
        except KeyError:
            raise FrameError(
                f"unknown {role} frame {name!r}; frames of this URDF: {listing(frames)}",
                frame=name,
                candidates=frames,
            ) from None

    def _setup_joints(self, info: URDFInfo) -> None:
        m = self.model
        self.dof = m.nv
        self.joint_names = [m.names[j] for j in range(1, m.njoints)]
        self.joint_types = [info.joint_types.get(n, "revolute") for n in self.joint_names]
        idx_q = np.array([m.joints[j].idx_q for j in range(1, m.njoints)])
        continuous = np.array([m.joints[j].nq == 2 for j in range(1, m.njoints)])
        self._idx_q = idx_q
        self._cont = np.flatnonzero(continuous)
        self._simple = np.flatnonzero(~continuous)
        self._identity_q = not continuous.any()
        lower = np.full(self.dof, -np.inf)
        upper = np.full(self.dof, np.inf)
        for i in self._simple:
            lo, hi = m.lowerPositionLimit[idx_q[i]], m.upperPositionLimit[idx_q[i]]
            if lo < hi:
                lower[i], upper[i] = lo, hi
            else:
                log.warning(
                    "joint %r has lower == upper limit (%g); treated as unlimited",
                    self.joint_names[i],
                    lo,
                )
        self._set_limits(lower, upper)
        self.prismatic = np.array([t == "prismatic" for t in self.joint_types])
        self._limit_lists = (self.lower.tolist(), self.upper.tolist(), self.prismatic.tolist())

    def _set_limits(self, lower: np.ndarray, upper: np.ndarray) -> None:
        self.lower = lower
        self.upper = upper
        self.lower.flags.writeable = False
        self.upper.flags.writeable = False
        self.bounded = np.flatnonzero(np.isfinite(lower) | np.isfinite(upper))
        finite = np.isfinite(lower) & np.isfinite(upper)
        self.middle = np.zeros(self.dof)
        self.middle[finite] = 0.5 * (lower[finite] + upper[finite])
        self.neutral = np.clip(np.zeros(self.dof), lower, upper)
        # Bounds in Pinocchio's tangent space indices, for the solvers.
        self._bounded_q = self._idx_q[self.bounded]

    def with_limits(self, limits: Mapping[str, tuple[float, float]]) -> Arm:
        """A copy of this arm with some joint limits replaced (name -> (lower, upper))."""
        lower, upper = self.lower.copy(), self.upper.copy()
        for jname, (lo, hi) in limits.items():
            i = self.joint_index(jname)
            if not lo <= hi:
                raise JointError(
                    f"limits for {jname!r} must satisfy lower <= upper, got ({lo}, {hi})",
                    joint=jname,
                )
            lower[i], upper[i] = lo, hi
        clone = object.__new__(Arm)
        # Cached properties (the reach counts prismatic travel) are recomputed for the clone.
        cached = {k for k, v in vars(Arm).items() if isinstance(v, cached_property)}
        clone.__dict__.update(
            {k: v for k, v in self.__dict__.items() if k != "_local" and k not in cached}
        )
        clone._set_limits(lower, upper)
        clone._limit_lists = (lower.tolist(), upper.tolist(), self.prismatic.tolist())
        clone._local = threading.local()
        if self._recipe is not None:
            kept = tuple(x for x in self._recipe.limits if x[0] not in limits)
            new = tuple((n, float(lo), float(hi)) for n, (lo, hi) in limits.items())
            clone._recipe = replace(self._recipe, limits=kept + new)
        return clone

    def joint_index(self, name: str) -> int:
        """Index of joint ``name`` in ``q``; raises ``JointError`` listing the joints."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise JointError(
                f"joint {name!r} is not on this arm's chain; joints: {listing(self.joint_names)}",
                joint=name,
                candidates=self.joint_names,
            ) from None

    # -- per-thread Pinocchio data --------------------------------------------------------

    @property
    def data(self) -> pin.Data:
        """This thread's Pinocchio Data (so that threads never share scratch memory)."""
        d = getattr(self._local, "data", None)
        if d is None:
            d = self._local.data = self.model.createData()
        return d

    # -- coordinates ----------------------------------------------------------------------

    def to_pin(self, q: np.ndarray) -> np.ndarray:
        """Joint values (one per joint) -> Pinocchio configuration (cos, sin for continuous)."""
        if self._identity_q:
            return np.array(q, dtype=float)
        out = np.empty(self.model.nq)
        out[self._idx_q[self._simple]] = q[self._simple]
        c = self._idx_q[self._cont]
        out[c] = np.cos(q[self._cont])
        out[c + 1] = np.sin(q[self._cont])
        return out

    def from_pin(self, qp: np.ndarray, copy: bool = True) -> np.ndarray:
        """Pinocchio configuration -> joint values; continuous angles in (-pi, pi].

        ``copy=False`` may return ``qp`` itself (no continuous joint): read-only use only.
        """
        if self._identity_q:
            return qp.copy() if copy else qp
        out = np.empty(self.dof)
        out[self._simple] = qp[self._idx_q[self._simple]]
        c = self._idx_q[self._cont]
        out[self._cont] = np.arctan2(qp[c + 1], qp[c])
        return out

    def clip_pin(self, qp: np.ndarray) -> None:
        """Clip the bounded joints of a Pinocchio configuration into their limits, in place."""
        if self._identity_q:  # no continuous joint: q is qp, and inf bounds clip nothing
            np.minimum(np.maximum(qp, self.lower, out=qp), self.upper, out=qp)
            return
        b = self._bounded_q
        qp[b] = np.clip(qp[b], self.lower[self.bounded], self.upper[self.bounded])

    # -- kinematics -----------------------------------------------------------------------

    def fk(self, q: np.ndarray) -> pin.SE3:
        """Tip pose in the base frame, ``T_base_tip``, for joint values ``q`` (rad, m)."""
        return self.fk_pin(self.to_pin(self.check_q(q)))

    def fk_pin(self, qp: np.ndarray) -> pin.SE3:
        """``T_base_tip`` for a Pinocchio configuration (no input checks: for solvers)."""
        d = self.data
        pin.forwardKinematics(self.model, d, qp)
        T_world_tip = pin.updateFramePlacement(self.model, d, self.tip_frame_id)
        if self._base_is_world:
            return T_world_tip.copy()
        return self.T_base_world * T_world_tip

    def jacobian(self, q: np.ndarray, frame: str = "local") -> np.ndarray:
        """The 6 x dof tip Jacobian, rows (vx, vy, vz, wx, wy, wz), columns per joint.

        ``frame="local"`` (default): the tip's twist expressed in the tip frame (Pinocchio's
        LOCAL). ``frame="base"``: the same twist with axes aligned with the base frame, at
        the tip origin (LOCAL_WORLD_ALIGNED rotated into the base). Units: m/rad, rad/rad.
        """
        qp = self.to_pin(self.check_q(q))
        if frame == "local":
            return pin.computeFrameJacobian(
                self.model, self.data, qp, self.tip_frame_id, pin.LOCAL
            ).copy()
        if frame == "base":
            J = pin.computeFrameJacobian(
                self.model, self.data, qp, self.tip_frame_id, pin.LOCAL_WORLD_ALIGNED
            )
            R = self.T_base_world.rotation
            return np.vstack([R @ J[:3], R @ J[3:]])
        raise OptionError(
            f"frame must be 'local' or 'base', got {frame!r}", option="frame", value=frame
        )

    # -- joint values ---------------------------------------------------------------------

    def sampling_box(self) -> tuple[np.ndarray, np.ndarray]:
        """The box random configurations come from: the limits, [-pi, pi] where unlimited."""
        lo = np.where(np.isfinite(self.lower), self.lower, -math.pi)
        hi = np.where(np.isfinite(self.upper), self.upper, math.pi)
        return lo, hi

    def random_q(self, rng: np.random.Generator | int | None = None) -> np.ndarray:
        """Uniform joint values within the limits; unlimited joints in [-pi, pi]."""
        return np.random.default_rng(rng).uniform(*self.sampling_box())

    def within_limits(self, q: np.ndarray, tol: float = LIMIT_TOL) -> bool:
        lower, upper, _ = self._limit_lists
        return all(lo - tol <= v <= hi + tol for v, lo, hi in zip(q.tolist(), lower, upper))

    def limit_violations(self, q: np.ndarray, tol: float = LIMIT_TOL) -> list[str]:
        """Human-readable list of the joints outside their limits."""
        if self.within_limits(q, tol):
            return []
        bad = np.flatnonzero((q < self.lower - tol) | (q > self.upper + tol))
        return [
            f"{self.joint_names[i]} = {q[i]:.6g} outside [{self.lower[i]:.6g}, {self.upper[i]:.6g}]"
            for i in bad
        ]

    def check_q(self, q: object, name: str = "q") -> np.ndarray:
        """``q`` as a float array of length ``dof``; raises ``OptionError`` otherwise."""
        try:
            arr = np.asarray(q, dtype=float)
        except (TypeError, ValueError):
            raise OptionError(
                f"{name} must be {self.dof} numbers, got {q!r}", option=name, value=q
            ) from None
        if arr.shape != (self.dof,):
            raise OptionError(
                f"{name} must have {self.dof} values (one per joint: "
                f"{', '.join(self.joint_names)}), got shape {arr.shape}",
                option=name,
                value=q,
            )
        if not np.isfinite(arr).all():
            raise OptionError(f"{name} must be finite, got {arr.tolist()}", option=name, value=q)
        return arr

    def seed(self, q0: object | None) -> np.ndarray:
        """Validate a seed configuration; ``None`` gives ``middle``.

        A seed outside the limits is clipped into them with an ``ArmikWarning`` (robot
        states read from encoders are often a hair outside).
        """
        if q0 is None:
            return self.middle.copy()
        q = self.check_q(q0, "q0")
        if not self.within_limits(q):
            warnings.warn(
                "q0 outside the joint limits was clipped into them: "
                + "; ".join(self.limit_violations(q)),
                ArmikWarning,
                stacklevel=3,
            )
            q = np.clip(q, self.lower, self.upper)
        return q

    def nearest_equivalent(self, q: np.ndarray, q_ref: np.ndarray) -> np.ndarray:
        """Shift each angle by a multiple of 2 pi to the value nearest ``q_ref`` that stays
        within the limits; a joint with no such value keeps its value."""
        out = []
        # Plain floats: a per-joint loop over numpy scalars costs ten times more.
        for qi, ri, lo, hi, linear in zip(
            np.asarray(q, float).tolist(), np.asarray(q_ref, float).tolist(), *self._limit_lists
        ):
            if not linear and not (-math.pi <= qi - ri <= math.pi and lo <= qi <= hi):
                near = qi + TWO_PI * round((ri - qi) / TWO_PI)
                best = None
                for c in (near, near - TWO_PI, near + TWO_PI, qi):
                    if lo - LIMIT_TOL <= c <= hi + LIMIT_TOL and (
                        best is None or abs(c - ri) < abs(best - ri)
                    ):
                        best = c
                if best is not None:
                    qi = min(max(best, lo), hi)
            out.append(qi)
        return np.array(out)

    # -- structure ------------------------------------------------------------------------

    @cached_property
    def plane(self) -> Plane | None:
        """The plane of motion if every joint is revolute with parallel axes, else None."""
        return find_plane(self)

    @cached_property
    def reach(self) -> float:
        """An upper bound (m) on the distance from the first joint's origin to the tip:
        the sum of the fixed distances between consecutive joint origins and the tip, plus
        the travel of prismatic joints (inf for an unlimited prismatic joint)."""
        qp = self.to_pin(self.middle)
        self.fk_pin(qp)
        data = self.data
        pts = [data.oMi[j].translation.copy() for j in range(1, self.model.njoints)]
        pts.append(data.oMf[self.tip_frame_id].translation.copy())
        total = sum(float(np.linalg.norm(b - a)) for a, b in zip(pts, pts[1:]))
        for i in np.flatnonzero(self.prismatic):
            total += max(abs(self.lower[i] - self.middle[i]), abs(self.upper[i] - self.middle[i]))
        return total

    @cached_property
    def kernel_chain(self):
        """The compiled kernel's view of this chain (``armik.kernel.chain.Chain``): plain
        arrays read once from the model."""
        from .kernel.chain import build_chain

        return build_chain(self)

    @cached_property
    def first_joint_origin(self) -> np.ndarray:
        """Origin of the first joint in the base frame (m); it never moves."""
        self.fk_pin(self.to_pin(self.middle))
        return self.T_base_world.act(self.data.oMi[1].translation)

    def __reduce__(self):
        if self._recipe is None:
            raise TypeError(
                f"arm {self.name!r} was not built by armik.load, so it has no recipe to "
                "pickle; build it with armik.load(...)"
            )
        return (_rebuild, (self._recipe,))

    def frames(self) -> list[str]:
        return [f.name for f in self.model.frames if f.name != "universe"]

    def __repr__(self) -> str:
        return (
            f"Arm({self.name!r}, dof={self.dof}, base={self.base!r}, tip={self.tip!r}, "
            f"joints={self.joint_names})"
        )

    # -- solving --------------------------------------------------------------------------

    def solve(self, target, *, q0=None, solver: str = "auto", **options):
        """Solve IK for ``target`` (SE3, 4x4, xyz, (xyz, quat xyzw), or xy on a planar arm).

        Returns one verified ``IKResult``: the best solution (within limits, nearest
        ``q0``), or ``success=False`` with a status and reason. Raises ``InputError`` for
        malformed input only; an unreachable target is a result, not an exception.
        """
        from .solve import solve

        return solve(self, target, q0=q0, solver=solver, all_solutions=False, **options)[0]

    def solve_all(self, target, *, q0=None, solver: str = "auto", **options):
        """Every distinct solution the solver finds, each verified, best first."""
        from .solve import solve

        return solve(self, target, q0=q0, solver=solver, all_solutions=True, **options)

    def solve_batch(self, targets, *, q0=None, solver: str = "auto", workers=None, **options):
        """Solve many targets ((N, 4, 4), (N, 7), (N, 3) or a list) on every core; returns a
        ``BatchResult``. See ``armik.batch.solve_batch``."""
        from .batch import solve_batch

        return solve_batch(self, targets, q0=q0, solver=solver, workers=workers, **options)

    def solve_path(self, poses, q0, *, max_joint_step=None, **options):
        """Solve waypoints in order, each from the previous answer, never with a silent
        jump larger than ``max_joint_step``; returns a ``BatchResult``. See
        ``armik.path.solve_path``."""
        from .path import solve_path

        return solve_path(self, poses, q0, max_joint_step=max_joint_step, **options)


def _set_joint(model: pin.Model, q: np.ndarray, jid: int, value: float) -> None:
    joint = model.joints[jid]
    if joint.nq == 1:
        q[joint.idx_q] = value
    elif joint.nq == 2 and joint.nv == 1:
        q[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
    else:
        raise JointError(
            f"joint {model.names[jid]!r} has {joint.nq} coordinates; it can only "
            "be locked at its neutral value",
            joint=model.names[jid],
        )
