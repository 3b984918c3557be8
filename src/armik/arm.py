"""Arm: a Pinocchio chain from a base frame to a tip frame.

Joint values seen by users are one number per joint: radians for revolute and continuous
joints, metres for prismatic ones. Pinocchio stores a continuous joint as (cos, sin)
(nq = 2, nv = 1); the conversion lives here and nowhere else.
"""

from __future__ import annotations

import difflib
import logging
import math
import operator
import threading
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path

import numpy as np
import pinocchio as pin

from . import urdf as urdf_reading
from .errors import ArmikWarning, FrameError, JointError, OptionError, URDFError, listing
from .kernel.coordinates import pin_configuration
from .robots import CATALOGUE, entry
from .structure import Plane, find_plane
from .urdf import URDFInfo, read_urdf

log = logging.getLogger(__name__)

TWO_PI = 2.0 * math.pi
LIMIT_TOL = 1e-12  # joint values this close outside a limit still count as inside
_FLOAT = np.dtype(float)
_le = operator.le
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
    catalogue tip, else ``tool0`` as in REP 199, else the leaf at the end of the longest
    chain of moving joints; ``Arm.tip_reason`` says which and why). Every joint off the
    chain is locked at the value in ``locked`` (joint name -> rad or m) or at its neutral
    value. ``tip_offset`` (m, in the tip frame) moves the tool point. The arm's name is the
    catalogue name, else the URDF's ``<robot name>``.

    Raises ``URDFError``, ``FrameError``, ``JointError`` or ``OptionError`` (all
    ``ValueError``) naming the bad value and the fix.
    """
    if not isinstance(source, (str, Path)):
        raise URDFError(
            f"source must be a robot name or a path to a URDF file, got {source!r}",
            path=str(source),
        )
    for role, value in (("base", base), ("tip", tip)):
        if value is not None and not isinstance(value, str):
            raise FrameError(
                f"{role} must be a frame name (a str), got {value!r}; "
                f"'armik info {source} --frames' lists the frames",
                frame=str(value),
            )
    locked = _check_locked(locked)
    tip_offset = _check_offset(tip_offset)
    name = str(source)
    if isinstance(source, str) and source in CATALOGUE:
        spec = entry(source)
        path = spec.urdf_path()
        tip = tip if tip is not None else spec.tip
        base = base if base is not None else spec.base
        if tip_offset is None and tip == spec.tip:
            tip_offset = spec.tip_offset
        locked = {**spec.locked, **(locked or {})}
        name_from_urdf = False
    else:
        path = Path(source)
        if not path.exists() and path.suffix.lower() not in (".urdf", ".xml"):
            raise URDFError(
                f"{name!r} is neither a bundled robot ({listing(CATALOGUE)}) nor an existing "
                "URDF file: check the name or the path",
                path=name,
            )
        name = path.stem
        name_from_urdf = True
    if name_from_urdf:
        model, info = read_urdf(path)
    else:  # bundled files are vetted: what reading them notes is in ``armik info``
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ArmikWarning)
            model, info = read_urdf(path)
    arm = Arm(
        model,
        info,
        name=info.name if name_from_urdf and info.name else name,
        base=base,
        tip=tip,
        locked=locked or {},
        tip_offset=tip_offset,
        source=str(path),
    )
    if not name_from_urdf and tip == spec.tip:
        arm.tip_reason = f"the catalogue's tip for {name!r}"
    arm._recipe = Recipe(str(source), base, tip, dict(locked or {}), arm.tip_offset)
    return arm


def _check_locked(locked: object) -> dict[str, float] | None:
    if locked is None:
        return None
    if not isinstance(locked, Mapping):
        raise JointError(
            f"locked must map joint names to values (rad or m), e.g. {{'finger': 0.0}}; "
            f"got {locked!r}",
            joint=str(locked),
        )
    for key in locked:
        if not isinstance(key, str):
            raise JointError(
                f"locked must map joint names (str) to values, got the key {key!r}",
                joint=str(key),
            )
    return dict(locked)


def _check_offset(offset: object) -> tuple[float, float, float] | None:
    """``tip_offset`` as 3 finite floats (m); raises ``OptionError`` otherwise."""
    if offset is None:
        return None
    fix = "give 3 finite numbers (x, y, z) in metres in the tip frame"
    if isinstance(offset, (str, bytes)):
        raise OptionError(
            f"tip_offset must be numbers, got {offset!r}: {fix}", option="tip_offset", value=offset
        )
    try:
        arr = np.asarray(offset)
        if np.iscomplexobj(arr):
            raise TypeError
        arr = arr.astype(float)
    except (TypeError, ValueError):
        raise OptionError(
            f"tip_offset must be numbers, got {offset!r}: {fix}", option="tip_offset", value=offset
        ) from None
    if arr.shape != (3,):
        raise OptionError(
            f"tip_offset must have 3 values, got shape {arr.shape}: {fix}",
            option="tip_offset",
            value=offset,
        )
    if not np.isfinite(arr).all() or np.abs(arr).max() > urdf_reading.MAX_LENGTH:
        raise OptionError(
            f"tip_offset {arr.tolist()} is not finite or beyond "
            f"{urdf_reading.MAX_LENGTH:g} m: {fix}",
            option="tip_offset",
            value=offset,
        )
    return tuple(float(v) for v in arr)


def _check_limit_value(jname: str, value: object) -> float:
    try:
        if isinstance(value, (str, bytes, complex)) or np.iscomplexobj(value):
            raise TypeError
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        out = math.nan
    if math.isnan(out) or (math.isfinite(out) and abs(out) > urdf_reading.MAX_LIMIT):
        raise JointError(
            f"limits for {jname!r} must be numbers (rad or m) within "
            f"+-{urdf_reading.MAX_LIMIT:g}, or "
            f"-inf/inf for no limit on that side; got {value!r}",
            joint=jname,
        )
    return out


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
    -inf/+inf for continuous joints), ``neutral``, ``middle``, ``base``, ``tip``,
    ``tip_reason`` (how the tip was chosen when none was given), ``info`` (what the URDF
    says: its tree, and ``info.notes`` on how it was read), ``model`` (the reduced
    Pinocchio model, not to be modified).
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
        self.info = info
        frames = [f.name for f in full.frames if f.name != "universe"]
        self.base = base if base is not None else info.root_link
        base_id = self._lookup_frame(full, self.base, "base", frames)
        if tip is None:
            tip, self.tip_reason = _default_tip(info, self.base)
            log.info("arm %r: tip %r, %s", name, tip, self.tip_reason)
        else:
            self.tip_reason = "given"
        self.tip = tip
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
        model = _reduce(full, to_lock, q_ref) if to_lock else full.copy()

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
    def _lookup_frame(full: pin.Model, name: str, role: str, frames: list[str]) -> int:
        try:
            return _frame_id(full, name)
        except KeyError:
            close = difflib.get_close_matches(name, frames, n=5, cutoff=0.5)
            hint = f"closest: {listing(close)}; " if close else ""
            shown = (
                f"frames: {listing(frames)}"
                if len(frames) <= 40
                else (f"'armik info <robot> --frames' lists all {len(frames)} frames")
            )
            raise FrameError(
                f"unknown {role} frame {name!r}; {hint}{shown}",
                frame=name,
                candidates=close or frames,
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
        self._continuous = continuous
        lower = np.full(self.dof, -np.inf)
        upper = np.full(self.dof, np.inf)
        for i in self._simple:
            lo, hi = m.lowerPositionLimit[idx_q[i]], m.upperPositionLimit[idx_q[i]]
            # lower == upper == 0 means "not given" (warned about when the URDF was read);
            # other equal limits pin the joint, as its URDF says.
            if lo < hi or (lo == hi and self.joint_names[i] not in info.unset_limits):
                # Limits beyond urdf_reading.MAX_LIMIT mean "free" (warned about when read).
                lower[i] = lo if lo >= -urdf_reading.MAX_LIMIT else -np.inf
                upper[i] = hi if hi <= urdf_reading.MAX_LIMIT else np.inf
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

    def with_limits(self, limits: Mapping[str, tuple[float, float]]) -> Arm:
        """A copy of this arm with some joint limits replaced (name -> (lower, upper))."""
        if not isinstance(limits, Mapping):
            raise JointError(
                f"limits must map joint names to (lower, upper), got {limits!r}",
                joint=str(limits),
            )
        lower, upper = self.lower.copy(), self.upper.copy()
        checked = {}
        for jname, pair in limits.items():
            if not isinstance(jname, str):
                raise JointError(f"joint names must be str, got {jname!r}", joint=str(jname))
            i = self.joint_index(jname)
            if isinstance(pair, (str, bytes)) or not hasattr(pair, "__len__") or len(pair) != 2:
                raise JointError(
                    f"limits for {jname!r} must be a pair (lower, upper) in rad or m, got {pair!r}",
                    joint=jname,
                )
            lo, hi = (_check_limit_value(jname, v) + 0.0 for v in pair)  # -0.0 -> 0.0
            checked[jname] = (lo, hi)
            if not lo <= hi:
                raise JointError(
                    f"limits for {jname!r} must satisfy lower <= upper, got ({lo}, {hi})",
                    joint=jname,
                )
            lower[i], upper[i] = lo, hi
        clone = object.__new__(Arm)
        # Cached properties (the reach counts prismatic travel) are recomputed for the clone.
        # So are the prepared solves (``armik.plan``: they hold the limits).
        cached = {k for k, v in vars(Arm).items() if isinstance(v, cached_property)}
        cached |= {"_local", "_plans"}
        clone.__dict__.update({k: v for k, v in self.__dict__.items() if k not in cached})
        clone._set_limits(lower, upper)
        clone._limit_lists = (lower.tolist(), upper.tolist(), self.prismatic.tolist())
        clone._local = threading.local()
        if self._recipe is not None:
            kept = tuple(x for x in self._recipe.limits if x[0] not in checked)
            new = tuple((n, lo, hi) for n, (lo, hi) in checked.items())
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
        out = np.empty(self.model.nq)
        pin_configuration(q, self._idx_q, self._continuous, out)
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
        """The box random configurations come from: the limits, [-pi, pi] where unlimited."""
        lo = np.where(np.isfinite(self.lower), self.lower, -math.pi)
        hi = np.where(np.isfinite(self.upper), self.upper, math.pi)
        return lo, hi

    def random_q(self, rng: np.random.Generator | int | None = None) -> np.ndarray:
        """Uniform joint values within the limits; unlimited joints in [-pi, pi]."""
        return np.random.default_rng(rng).uniform(*self.sampling_box())

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
            f"{name} = {v:.6g} outside [{lo:.6g}, {hi:.6g}]"
            for name, v, lo, hi in zip(self.joint_names, values, lower, upper)
            if not lo - tol <= v <= hi + tol
        ]

    def check_q(self, q: object, name: str = "q") -> np.ndarray:
        """``q`` as a float array of length ``dof``; raises ``OptionError`` otherwise."""
        try:
            if isinstance(q, (str, bytes)) or np.iscomplexobj(q):
                raise TypeError  # never drop an imaginary part silently
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
        if type(q0) is np.ndarray and q0.dtype == _FLOAT and q0.shape == (self.dof,):
            # The common case, on plain floats: check_q would return q0 itself, and a sum
            # of floats is finite only when every one is (else the general path decides).
            values = q0.tolist()
            if math.isfinite(sum(values)) and self._within(values):
                return q0
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
        if type(solver) is not str:
            _check_solver_name(solver)
        return _solve_one()(self, target, q0, solver, options)

    def solve_all(self, target, *, q0=None, solver: str = "auto", **options):
        """Every distinct solution the solver finds, each verified, best first."""
        if type(solver) is not str:
            _check_solver_name(solver)
        return _solve_one()(self, target, q0, solver, options, True)

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


_SOLVE = []  # armik.solve.solve_one, imported at the first solve (it imports this module)


def _import_solve() -> None:
    # An import statement per call costs 2 us of a 25 us solve.
    from .solve import solve_one

    _SOLVE[:] = [solve_one]


def _solve_one():
    if not _SOLVE:
        _import_solve()
    return _SOLVE[0]


def _check_solver_name(solver: object) -> None:
    # Before the target is parsed, so that a wrong solver argument is named first.
    from .ik import registry

    registry.check_name(solver)


def _reduce(full: pin.Model, to_lock: list[int], q_ref: np.ndarray) -> pin.Model:
    """``pin.buildReducedModel`` that survives frames sharing a name (a link and a joint
    both called "quill", a link called "universe"): Pinocchio looks frames up by name there
    and raises "Several frames match the filter". For the call, later duplicates and the
    locked joints (whose frames it re-creates under the joint's name) get unique names;
    the frames get their names back afterwards."""
    work = full.copy()
    renamed: dict[str, str] = {}
    joint_tmp: dict[int, str] = {}
    for j in to_lock:  # a joint and its JOINT frame keep one (temporary) name
        joint_tmp[j] = f"{full.names[j]}\x00armik-joint{j}"
        renamed[joint_tmp[j]] = full.names[j]
        work.names[j] = joint_tmp[j]
    seen: set[str] = set()
    for i, frame in enumerate(work.frames):
        tmp = None
        if frame.type == pin.JOINT and frame.parentJoint in joint_tmp:
            tmp = joint_tmp[frame.parentJoint]
        elif frame.name in seen:
            tmp = f"{frame.name}\x00armik{i}"
            renamed[tmp] = frame.name
        if tmp is not None:
            frame.name = tmp
            work.frames[i] = frame
        seen.add(frame.name)
    model = pin.buildReducedModel(work, to_lock, q_ref)
    for i, frame in enumerate(model.frames):
        if frame.name in renamed:
            frame.name = renamed[frame.name]
            model.frames[i] = frame
    for j in range(model.njoints):
        if model.names[j] in renamed:
            model.names[j] = renamed[model.names[j]]
    return model


def _default_tip(info: URDFInfo, base: str) -> tuple[str, str]:
    """The tip when none is given, and why: ``tool0`` downstream of the base (REP 199,
    the tool flange of ROS-Industrial and UR descriptions); else the leaf at the end of
    the longest chain of moving joints; leaves tied there that hang on fixed joints from
    one link give that link. Raises ``FrameError`` listing the leaves when it is a choice."""
    children = info.children()
    if base not in children:
        raise FrameError(
            f"no tip given and the base {base!r} is not a link of the URDF: pass tip=",
            frame=base,
        )
    leaves: list[tuple[str, int, str | None]] = []
    stack: list[tuple[str, int, str | None]] = [(base, 0, None)]
    tool0 = False
    while stack:  # iterative: trees can be deep
        link, moving, last = stack.pop()
        tool0 |= link == "tool0" and moving > 0
        kids = children.get(link, [])
        if not kids:
            leaves.append((link, moving, last))
        for j in kids:
            step = j.type != "fixed"
            stack.append((j.child, moving + step, j.name if step else last))
    if tool0:
        return "tool0", "'tool0', the tool flange by convention (REP 199)"
    best = max(m for _, m, _ in leaves)
    if best == 0:
        raise FrameError(
            f"no tip given and no moving joint lies downstream of {base!r}: pick another base",
            frame=base,
        )
    top = sorted((leaf for leaf in leaves if leaf[1] == best), key=lambda leaf: leaf[0])
    if len(top) == 1:
        return top[0][0], f"the leaf at the end of the longest chain ({best} moving joints)"
    lasts = {last for _, _, last in top}
    if len(lasts) == 1:
        joint = info.joints[lasts.pop()]
        return joint.child, (
            f"the link after the last moving joint {joint.name!r} of the longest chain "
            f"({best} moving joints); the leaves {listing(n for n, _, _ in top)} hang from "
            "it on fixed joints"
        )
    names = [n for n, _, _ in top]
    raise FrameError(
        f"no tip given and the URDF has {len(names)} leaf links at the end of chains of "
        f"{best} moving joints: pass tip= one of {listing(names)}",
        frame="",
        candidates=names,
    )
