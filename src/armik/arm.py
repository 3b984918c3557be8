"""The facade: an ``Arm`` (``armik.load`` builds it, ``armik.loading``) has an arm model
(``Arm.kinematics``, an ``armik.model.arm_model.ArmModel``) and solves on it.

Everything below this module works on the model and never imports the facade.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin

from armik import checked
from armik.constraints import collision
from armik.model import frames
from armik.model.arm_model import ArmModel
from armik.model.urdf import URDFInfo
from armik.of_model import OfModel
from armik.servo.servo import start as start_servo
from armik.solutions import Solutions
from armik.solve.batch import solve_batch
from armik.solve.intervals import Intervals, intervals
from armik.solve.path import solve_path
from armik.solve.read import read, read_batch, read_path
from armik.solve.single import routed
from armik.solve.stages import run
from armik.solvers.registry import validate_name
from armik.tolerances import LIMIT_TOL

if TYPE_CHECKING:
    from armik.batch_result import BatchResult
    from armik.constraints.collision import Pair
    from armik.result import IKResult
    from armik.solve.progress import ProgressArg


class Arm:
    """One robot arm's chain and its solvers; built by ``armik.load``.

    Attributes (read-only): ``name``, ``source`` (the URDF's path, or "<string>"),
    ``dof``, ``joint_names``, ``joint_types``, ``lower``, ``upper`` (rad or m; -inf/+inf
    for continuous joints), ``neutral``, ``middle``, ``base``, ``tip``, ``tip_offset``
    (the tool point's offset from ``tip``, m in its frame, where ``fk`` and targets place
    it; None for none: ``load``'s, or the catalogue's for its tip), ``tip_reason``
    (how the tip was chosen when none was given), ``locked`` (every joint locked by
    value, on or off the chain, name -> rad or m), ``info`` (what the URDF says: its tree,
    and ``info.notes`` on how it was read), ``model`` (the reduced Pinocchio model, not
    to be modified) and ``kinematics``, the arm model everything else reads
    (``armik.model.arm_model.ArmModel``: the joints locked on the chain, Pinocchio
    coordinates, the compiled chain, ...).
    """

    __slots__ = ("kinematics",)

    name = OfModel[str]()
    source = OfModel[str]()
    dof = OfModel[int]()
    joint_names = OfModel[list[str]]()
    joint_types = OfModel[list[str]]()
    lower = OfModel[np.ndarray]()
    upper = OfModel[np.ndarray]()
    neutral = OfModel[np.ndarray]()
    middle = OfModel[np.ndarray]()
    base = OfModel[str]()
    tip = OfModel[str]()
    tip_offset = OfModel[tuple[float, float, float] | None]()
    tip_reason = OfModel[str]()
    locked = OfModel[Mapping[str, float]]()
    info = OfModel[URDFInfo]()
    model = OfModel[pin.Model]()

    def __init__(self, kinematics: ArmModel) -> None:
        self.kinematics = kinematics

    def __reduce__(self) -> tuple[type[Arm], tuple[ArmModel]]:
        return (Arm, (self.kinematics,))  # the model travels as its recipe

    def __repr__(self) -> str:
        return "Arm" + repr(self.kinematics).removeprefix(type(self.kinematics).__name__)

    # -- kinematics -----------------------------------------------------------------------

    def fk(self, q: object, frame: str | None = None) -> pin.SE3:
        """``T_base_frame`` at joint values ``q`` (rad, m): the tip's, or any frame's."""
        return frames.placement(self.kinematics, q, frame)

    def jacobian(self, q: object, frame: str | None = None, reference: str | None = None) -> Any:
        """The 6 x dof Jacobian of the tip or ``frame``, in its own axes (``reference=
        "local"``) or the base's (``"base"``); ``armik.model.frames``."""
        return frames.jacobian(self.kinematics, q, frame, reference)

    def random_q(
        self, rng: np.random.Generator | int | None = None, n: int | None = None
    ) -> np.ndarray:
        """Uniform joint values within the limits, unlimited joints in [-pi, pi]: one
        configuration (dof,), or ``n`` of them (n, dof). ``rng``: a generator or a seed."""
        return self.kinematics.random_q(checked.generator("rng", rng), n)

    def fk_batch(self, Q: object) -> np.ndarray:
        """Tip poses (N, 4, 4) of Q (N, dof) by the compiled FK (``fk``'s, to 1e-12)."""
        return self.kinematics.fk_batch(Q)

    def within_limits(self, q: object, tol: float = LIMIT_TOL) -> bool:
        """Whether every joint of ``q`` (one configuration, ``dof`` values; a NaN is
        outside) lies within its limits (``tol`` rad or m beyond); ``OptionError`` naming
        ``q`` when it is not one configuration of this arm."""
        q = checked.configuration("q", q, self.joint_names, finite=False)
        return self.kinematics.within_limits(q, checked.number("tol", tol))

    def frames(self) -> list[str]:
        """The names of the URDF's frames on this arm's model (tips to choose from)."""
        return self.kinematics.frames()

    def with_limits(self, limits: Mapping[str, tuple[float, float]]) -> Arm:
        """A copy of this arm with some joint limits replaced (name -> (lower, upper))."""
        return Arm(self.kinematics.with_limits(limits))

    def with_locked(self, locked: Mapping[str, float]) -> Arm:
        """A new arm with the joints of ``locked`` (name -> rad or m) locked at those values,
        on or off the chain, besides those this arm already locks (a joint locked again takes
        the new value). Built from the arm's recipe, as ``armik.load`` would; the limits
        replaced by ``with_limits`` hold the locked values and the joints that stay free.
        ``JointError`` as ``armik.load``: an unknown joint, a value that is not finite or
        lies outside the joint's limits (``with_limits``' or the URDF's), no joint left."""
        return Arm(self.kinematics.with_locked(locked))

    # -- solving --------------------------------------------------------------------------

    def solve(
        self, target: object, *, q0: object = None, solver: str = "auto", **options: Any
    ) -> IKResult:
        """Solve IK for ``target`` (SE3, 4x4, xyz, (xyz, quat xyzw), or xy on a planar arm).

        Returns one verified ``IKResult``: a closed form's branch within the limits nearest
        ``q0``, a numeric solver's first verified answer from ``q0`` (``prefer="nearest"``
        searches for the nearest), or ``success=False`` with a status and reason. Raises
        ``InputError`` for malformed input only; an unreachable target is a result, not an
        exception.
        """
        if type(solver) is not str:
            validate_name(solver)
        # read, then ``routed``, inline: a warm solve's Python calls are its budget
        request = read(self.kinematics, target, q0, solver, options)  # options read once
        if request.score is None and request.problem is None:  # the compiled path's stages
            return run(self.kinematics, request)  # type: ignore[no-any-return]
        return routed(self.kinematics, request)  # type: ignore[no-any-return]

    def solve_all(
        self, target: object, *, q0: object = None, solver: str = "auto", **options: Any
    ) -> Solutions:
        """Every distinct solution the solver finds, each verified, best first (read as a
        list of ``IKResult``: ``armik.solutions``)."""
        if type(solver) is not str:
            validate_name(solver)
        # read, then ``routed``, inline, as ``solve``'s
        request = read(self.kinematics, target, q0, solver, options, True)
        if request.score is None and request.problem is None:  # the compiled path's stages
            got = run(self.kinematics, request)
        else:
            got = routed(self.kinematics, request)
        return got if type(got) is Solutions else Solutions(got)

    def intervals(self, target: object, over: str, *, q0: object = None) -> Intervals:
        """Each branch's intervals of ``over`` ("swivel", "panda_joint7") within the limits."""
        return intervals(self.kinematics, target, over, q0)

    def solve_batch(
        self,
        targets: object,
        *,
        q0: object = None,
        solver: str = "auto",
        workers: int | None = None,
        chunk_size: int | None = None,
        progress: ProgressArg = None,
        backend: object = None,
        **options: Any,
    ) -> BatchResult:
        """Solve many targets ((N, 4, 4), (N, 7), (N, 3), a list) on every core: a
        ``BatchResult`` (``armik.solve.batch``); ``backend`` names where the chunks run
        (``armik.solve.backends``)."""
        request = read_batch(self.kinematics, targets, q0, solver, options)
        return solve_batch(self.kinematics, request, workers, chunk_size, progress, backend)

    def solve_path(
        self,
        poses: object,
        q0: object = None,
        *,
        max_joint_step: float | np.ndarray | None = None,
        plan: str = "follow",
        solver: str = "auto",
        **options: Any,
    ) -> BatchResult:
        """Waypoints in order from ``q0`` (None: no start, the first waypoint free, solved
        from mid-limits), no silent jump over ``max_joint_step``; ``plan="global"``: the
        least motion (``armik.solve.path``)."""
        request, local = read_path(self.kinematics, poses, q0, solver, plan, options)
        return solve_path(self.kinematics, request, local, max_joint_step, plan)

    # -- streaming (armik.servo.Servo: q0, dt=0.002, velocity_limits=, ...) and collisions --
    servo = start_servo

    def min_distance(
        self, q: object, obstacles: object = (), self_collision: bool = False
    ) -> tuple[float, Pair | None]:
        """(distance m, (name_a, name_b)): the closest pair at joint values ``q`` (rad, m)
        among the arm's links and ``obstacles`` (shapes in the base frame) and, with
        ``self_collision``, the arm's own non-adjacent links; negative when they overlap.
        Raises ``CollisionError`` when the URDF has no collision geometry."""
        return collision.min_distance(self.kinematics, q, obstacles, self_collision)

    def in_collision(
        self, q: object, obstacles: object = (), self_collision: bool = False, margin: float = 0.0
    ) -> bool:
        """Whether some pair ``min_distance`` checks is closer than ``margin`` (m) at ``q``."""
        return collision.in_collision(self.kinematics, q, obstacles, self_collision, margin)
