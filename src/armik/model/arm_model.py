"""The arm model: one chain's Pinocchio model with its joints, limits, coordinates and
kinematics. It knows no solver: the facade (``armik.arm.Arm``) has one and solves on it.

Joint values seen by users are one number per joint: radians for revolute and continuous
joints, metres for prismatic ones. Pinocchio stores a continuous joint as (cos, sin)
(nq = 2, nv = 1); the conversion lives here and nowhere else.
"""

from __future__ import annotations

import math
import operator
import threading
from collections.abc import Mapping
from dataclasses import replace
from functools import cached_property
from types import MappingProxyType
from typing import Any

import numpy as np
import pinocchio as pin

from armik.checked import configuration
from armik.errors import InputError, JointError, OptionError, listing, warn
from armik.kernel.chain import KernelChain
from armik.kernel.coordinates import pin_configuration
from armik.kernel.fk_many import fk_many
from armik.model import mimic as _mimic
from armik.model.chain_arrays import build_chain
from armik.model.geometry import Plane, find_plane
from armik.model.limit_units import degrees_note, in_radians
from armik.model.reduce import check_limits, reduce_chain
from armik.model.urdf import URDFInfo
from armik.model.value_checks import violation
from armik.tolerances import LIMIT_TOL, MAX_LIMIT

TWO_PI = 2.0 * math.pi
_FLOAT = np.dtype(float)
_le = operator.le


class ArmModel:
    """The kinematic chain of one robot arm: what every solver, check and tool reads
    (``armik.load`` builds one inside its facade, ``Arm.kinematics``)."""

    package_dirs: tuple[str, ...] = ()  # where package:// paths are looked up (meshes)
    disabled_pairs: frozenset[tuple[str, str]] = frozenset()  # an SRDF's, sorted link names

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
        limits: Mapping[str, tuple[float, float]] | None = None,  # a locked value's, if given
    ) -> None:
        self.name = name
        self.source = source
        self.info = info
        chain = reduce_chain(
            full, info, locked, limits or {}, name=name, base=base, tip=tip, tip_offset=tip_offset
        )
        self.base, self.tip, self.tip_reason = chain.base, chain.tip, chain.tip_reason
        self.model = chain.model
        self.mimics, self.physical_model = chain.mimics, chain.plain  # see ReducedChain
        self.chain = chain  # how it was cut from the URDF's model (collision geometry)
        self.tip_frame_id = chain.tip_frame_id
        self.tip_offset = chain.tip_offset
        self.T_world_base = chain.T_world_base
        self.locked = MappingProxyType(chain.locked)
        self.locked_on_chain = chain.locked_on_chain
        self.T_base_world = self.T_world_base.inverse()
        self._base_is_world = self.T_world_base.isIdentity(1e-15)

        self._setup_joints(info)
        self._local = threading.local()
        self._derived: dict[Any, Any] = {}  # ``armik.model.derived``: what modules keep
        self._recipe: Any = None  # how it was loaded (``armik.loading.Recipe``), to pickle
        # objects of the URDF's collision geometry left out: a chain's within a robot, those
        # another chain moves (``armik.arms_apart``)
        self.left_out: frozenset[str] = frozenset()

    def __reduce__(self) -> tuple[Any, tuple[()]]:
        # A Pinocchio model does not pickle portably: the arm travels as its recipe.
        return (self._built_by("pickle").build_model, ())

    def _setup_joints(self, info: URDFInfo) -> None:
        m = self.model
        self.dof = m.nv
        ids = [j for j in range(1, m.njoints) if m.joints[j].nq > 0]  # not mimic: driving
        self.joint_names = [m.names[j] for j in ids]
        self.joint_types = [info.joint_types.get(n, "revolute") for n in self.joint_names]
        idx_q = np.array([m.joints[j].idx_q for j in ids])
        continuous = np.array([m.joints[j].nq == 2 for j in ids])
        self._idx_q = idx_q
        self._cont = np.flatnonzero(continuous)
        self._simple = np.flatnonzero(~continuous)
        self._identity_q = not continuous.any()
        self._continuous = continuous
        lower, upper = np.full(self.dof, -np.inf), np.full(self.dof, np.inf)
        for i in self._simple:
            lo, hi = m.lowerPositionLimit[idx_q[i]], m.upperPositionLimit[idx_q[i]]
            # lower == upper == 0 means "not given" (warned about when the URDF was read);
            # other equal limits pin the joint, as its URDF says.
            if lo < hi or (lo == hi and self.joint_names[i] not in info.unset_limits):
                # Limits beyond MAX_LIMIT mean "free" (warned about when read).
                lower[i] = lo if lo >= -MAX_LIMIT else -np.inf
                upper[i] = hi if hi <= MAX_LIMIT else np.inf
        self.joint_map, self.driving_joints, self._mimic_box = _mimic.joint_map(self)
        self._set_limits(*_mimic.narrow(lower, upper, self._mimic_box, self))
        self.prismatic = np.array([t == "prismatic" for t in self.joint_types])
        self._limit_lists = (self.lower.tolist(), self.upper.tolist(), _mimic.no_period(self))

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
        simple = np.zeros(self.dof, bool)
        simple[self._simple] = True
        self._bounded_q = self._idx_q[self.bounded[simple[self.bounded]]]
        self._bounded_simple = self.bounded[simple[self.bounded]]
        # Continuous joints given limits (with_limits): clipped and read as angles, unwrapped
        # into the window around the middle of their limits.
        self._bounded_cont = self.bounded[~simple[self.bounded]]
        lo_c, hi_c = lower[self._bounded_cont], upper[self._bounded_cont]
        self._cont_centre = np.where(
            np.isfinite(lo_c) & np.isfinite(hi_c),
            0.5 * (lo_c + hi_c),
            np.where(np.isfinite(lo_c), lo_c + math.pi, hi_c - math.pi),
        )

    def with_limits(
        self, limits: Mapping[str, tuple[float, float]], others: Mapping[str, tuple] | None = None
    ) -> ArmModel:
        """A copy of this arm with some joint limits replaced (name -> (lower, upper));
        ``others``: joints off its chain, checked by the chains that hold them (several
        tips), whose limits its recipe keeps for a lock of them."""
        checked = in_radians(check_limits(limits, self.joint_index), self)
        lower, upper = self.lower.copy(), self.upper.copy()
        for jname, (lo, hi) in checked.items():
            i = self.joint_index(jname)
            lower[i], upper[i] = lo, hi
        clone = object.__new__(type(self))
        # Cached properties (the reach counts prismatic travel) are recomputed for the clone,
        # and so is everything modules derived (``armik.model.derived``: prepared solves hold
        # the limits).
        cached = {k for k, v in vars(ArmModel).items() if isinstance(v, cached_property)}
        cached |= {"_local", "_derived", "_tol_bounds"}
        clone.__dict__.update({k: v for k, v in self.__dict__.items() if k not in cached})
        lower, upper = _mimic.narrow(lower, upper, self._mimic_box, self)
        clone._set_limits(lower, upper)
        clone._limit_lists = (lower.tolist(), upper.tolist(), self._limit_lists[2])
        clone._local = threading.local()
        clone._derived = {}
        if self._recipe is not None:
            every = {**(others or {}), **checked}
            kept = tuple(x for x in self._recipe.limits if x[0] not in every)
            new = tuple((n, lo, hi) for n, (lo, hi) in every.items())
            clone._recipe = replace(self._recipe, limits=kept + new)
        return clone

    def with_locked(self, locked: Mapping[str, float]) -> ArmModel:
        """A new model with ``locked``'s joints locked too (see ``Arm.with_locked``)."""
        return self._built_by("rebuild from").locked_model(locked, self.joint_names[-1])

    def _built_by(self, what: str) -> Any:
        """The recipe ``armik.load`` built this model by, or ``TypeError`` (no ``what``)."""
        if self._recipe is None:
            raise TypeError(
                f"arm {self.name!r} was not built by armik.load, so it has no recipe to "
                f"{what}; build it with armik.load(...)"
            )
        return self._recipe

    def joint_index(self, name: str) -> int:
        """Index of joint ``name`` in ``q``; raises ``JointError`` listing the joints."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise JointError(
                f"joint {name!r} {_mimic.not_a_joint(self, name)}; joints: "
                f"{listing(self.joint_names)}",
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

    def tip_views(self) -> tuple[pin.Data, np.ndarray, np.ndarray]:
        """(data, R, p): this thread's Pinocchio Data and views of its tip placement's
        rotation (3x3, column-major) and translation, in Pinocchio's own memory: after
        ``updateFramePlacement(model, data, tip_frame_id)`` they hold its result without a
        copy. Keep them with ``data`` (they do not keep it alive) and read them only after
        that call."""
        views = getattr(self._local, "tip", None)
        if views is None:
            data = self.data
            placement = data.oMf[self.tip_frame_id]  # a reference into data, not a copy
            views = self._local.tip = (data, placement.rotation, placement.translation)
        return views

    # -- coordinates ----------------------------------------------------------------------

    def to_pin(self, q: np.ndarray) -> np.ndarray:
        """Joint values (one per joint) -> Pinocchio configuration (cos, sin for continuous)."""
        if self._identity_q:
            return np.array(q, dtype=float)
        q = np.asarray(q, dtype=float)
        if q.shape != (self.dof,):
            raise ValueError(f"q must have {self.dof} values, got shape {q.shape}")
        out = np.empty(self.model.nq)  # a read-only q (an answer's row) copied: one kernel
        pin_configuration(q if q.flags.writeable else q.copy(), self._idx_q, self._continuous, out)
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
        if self._bounded_cont.size:
            out[self._bounded_cont] = self._unwrap(out[self._bounded_cont])
        return out

    def _unwrap(self, angles: np.ndarray) -> np.ndarray:
        """Angles of limited continuous joints shifted by 2 pi k into the window of width
        2 pi centred on the middle of their limits."""
        centre = self._cont_centre
        return angles + TWO_PI * np.round((centre - angles) / TWO_PI)

    def clip_pin(self, qp: np.ndarray) -> None:
        """Clip the bounded joints of a Pinocchio configuration into their limits, in place.

        A continuous joint given limits (``with_limits``) is clipped as an angle, not as
        its (cos, sin) pair."""
        if self._identity_q:  # no continuous joint: q is qp, and inf bounds clip nothing
            np.minimum(np.maximum(qp, self.lower, out=qp), self.upper, out=qp)
            return
        b = self._bounded_q
        if b.size:
            s = self._bounded_simple
            qp[b] = np.clip(qp[b], self.lower[s], self.upper[s])
        if self._bounded_cont.size:
            k = self._bounded_cont
            c = self._idx_q[k]
            angle = self._unwrap(np.arctan2(qp[c + 1], qp[c]))
            angle = np.clip(angle, self.lower[k], self.upper[k])
            qp[c], qp[c + 1] = np.cos(angle), np.sin(angle)

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
            J = pin.computeFrameJacobian(self.model, self.data, qp, self.tip_frame_id, pin.LOCAL)
            return J.reshape(6, self.dof).copy()  # Pinocchio gives a 1-DOF Jacobian as (6,)
        if frame == "base":
            J = pin.computeFrameJacobian(
                self.model, self.data, qp, self.tip_frame_id, pin.LOCAL_WORLD_ALIGNED
            )
            J = J.reshape(6, self.dof)
            R = self.T_base_world.rotation
            return np.vstack([R @ J[:3], R @ J[3:]])
        raise OptionError(
            f"frame must be 'local' or 'base', got {frame!r}", option="frame", value=frame
        )

    # -- joint values ---------------------------------------------------------------------

    def sampling_box(self) -> tuple[np.ndarray, np.ndarray]:
        """Where random configurations come from: the limits (2 pi wide beside a one-sided
        limit), [-pi, pi] where unlimited."""
        low, up, pi = np.isfinite(self.lower), np.isfinite(self.upper), math.pi
        lo = np.where(low, self.lower, np.where(up, self.upper - 2 * pi, -pi))
        return lo, np.where(up, self.upper, np.where(low, self.lower + 2 * pi, pi))

    def random_q(
        self, rng: np.random.Generator | int | None = None, n: int | None = None
    ) -> np.ndarray:
        """Uniform joint values within the limits, unlimited joints in [-pi, pi]: one
        configuration (dof,), or ``n`` of them (n, dof). ``rng``: a generator or a seed."""
        lo, hi = self.sampling_box()
        if n is None:
            return np.random.default_rng(rng).uniform(lo, hi)
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 0 <= n <= 10**8:
            raise OptionError(
                f"n must be a whole number of configurations in [0, 1e8], got {n!r}",
                option="n",
                value=n,
            )
        return np.random.default_rng(rng).uniform(lo, hi, size=(int(n), self.dof))

    def fk_batch(self, Q: object) -> np.ndarray:
        """Tip poses ``T_base_tip`` (N, 4, 4) of joint values Q (N, dof), rad or m: compiled
        forward kinematics over the arm's chain (the GIL released), the same placements as
        ``fk`` row by row (to 1e-12, tests/model/test_fk_batch.py)."""
        try:
            if isinstance(Q, (str, bytes)) or np.iscomplexobj(Q):  # type: ignore[arg-type]
                raise TypeError
            Q = np.array(Q, dtype=float, order="C", ndmin=2)
        except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range)
            raise OptionError(
                f"Q must be an (N, {self.dof}) array of finite joint values, got {Q!r}",
                option="Q",
            ) from None
        if Q.ndim != 2 or Q.shape[1] != self.dof:
            raise OptionError(
                f"Q must have shape (N, {self.dof}), one row per configuration, got {Q.shape}",
                option="Q",
            )
        if not np.isfinite(Q).all():
            i = int(np.flatnonzero(~np.isfinite(Q).all(axis=1))[0])
            raise OptionError(f"row {i} of Q is not finite: {Q[i].tolist()}", option="Q")
        out = np.empty((len(Q), 4, 4))
        packed, kind, halton = self.kernel_chain.flat
        fk_many(packed, kind, halton, Q, out)
        return out

    def within_limits(self, q: np.ndarray, tol: float = LIMIT_TOL) -> bool:
        if type(q) is not np.ndarray:
            q = np.asarray(q, dtype=float)
        return self._within(q.tolist(), tol)

    def _within(self, values: list[float], tol: float = LIMIT_TOL) -> bool:
        """``within_limits`` on plain floats: lower - tol <= v <= upper + tol for every
        joint (False for NaN), with the widened bounds computed once per limits and tol."""
        bounds = self.__dict__.get("_tol_bounds")
        if bounds is None or bounds[0] is not self._limit_lists or bounds[1] != tol:
            lower, upper, _ = self._limit_lists
            bounds = (
                self._limit_lists,
                tol,
                [lo - tol for lo in lower],
                [hi + tol for hi in upper],
            )
            self.__dict__["_tol_bounds"] = bounds
        return all(map(_le, bounds[2], values)) and all(map(_le, values, bounds[3]))

    def limit_violations(self, q: np.ndarray, tol: float = LIMIT_TOL) -> list[str]:
        """Human-readable list of the joints outside their limits."""
        values = np.asarray(q, dtype=float).tolist()  # plain floats: numpy per joint is slow
        lower, upper, _ = self._limit_lists
        return [
            violation(name, v, lo, hi)
            for name, v, lo, hi in zip(self.joint_names, values, lower, upper)
            if not lo - tol <= v <= hi + tol
        ]

    def check_q(self, q: object, name: str = "q") -> np.ndarray:
        """``q`` as a float array of length ``dof``, finite; raises ``OptionError``
        otherwise (``armik.checked.configuration``)."""
        return configuration(name, q, self.joint_names)

    def seed(self, q0: object | None) -> np.ndarray:
        """Validate a seed configuration; ``None`` gives ``middle``.

        A seed outside the limits is clipped into them with an ``ArmikWarning`` (robot
        states read from encoders are often a hair outside).
        """
        if q0 is None:
            return self.middle.copy()
        if type(q0) is np.ndarray and q0.dtype == _FLOAT and q0.shape == (self.dof,):
            # The common case, on plain floats: check_q would return q0 itself, and a sum
            # of floats is finite only when every one is (else the general path decides).
            values = q0.tolist()
            if math.isfinite(sum(values)) and self._within(values):
                # a read-only array (a result's q) is copied: compiled code taking it would
                # be compiled a second time, for read-only arrays
                return q0 if q0.flags.writeable else q0.copy()
        q = self.check_q(q0, "q0")
        if not self.within_limits(q):
            warn(
                "q0 outside the joint limits was clipped into them: "
                + "; ".join(self.limit_violations(q))
                + degrees_note(q, self)
            )
            q = np.clip(q, self.lower, self.upper)
        return q if q.flags.writeable and q.flags.c_contiguous else np.array(q)

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
        return total + _mimic.travel(self)

    @cached_property
    def kernel_chain(self) -> KernelChain:
        """The compiled kernel's view of this chain: plain arrays read once from the model."""
        return build_chain(self)

    @cached_property
    def first_joint_origin(self) -> np.ndarray:
        """Origin of the first joint in the base frame (m); it never moves."""
        self.fk_pin(self.to_pin(self.middle))
        return self.T_base_world.act(self.data.oMi[1].translation)

    def frames(self) -> list[str]:
        return [f.name for f in self.model.frames if f.name != "universe"]

    def __repr__(self) -> str:
        offset = "" if self.tip_offset is None else f", tip_offset={self.tip_offset}"
        return (
            f"{type(self).__name__}({self.name!r}, dof={self.dof}, base={self.base!r}, "
            f"tip={self.tip!r}{offset}, joints={self.joint_names})"
        )


def model_of(arm: object) -> ArmModel:
    """The model of an ``Arm`` (``kinematics``) or ``arm`` itself: what public functions
    below the facade take. ``InputError`` for anything else."""
    kinematics = getattr(arm, "kinematics", arm)
    if not isinstance(kinematics, ArmModel):
        raise InputError(f"expected an arm from armik.load(...), got {arm!r}")
    return kinematics
