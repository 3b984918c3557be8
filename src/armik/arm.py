"""The facade: ``armik.load`` builds an ``Arm``, which has an arm model
(``Arm.kinematics``, an ``armik.model.arm_model.ArmModel``) and solves on it.

Everything below this module works on the model and never imports the facade.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, overload

import numpy as np
import pinocchio as pin

from armik import checked
from armik.arms import Arms
from armik.constraints import collision
from armik.constraints.srdf import read_srdf
from armik.errors import ArmikWarning, JointError, OptionError, URDFError, did_you_mean, listing
from armik.model import frames
from armik.model.arm_model import ArmModel
from armik.model.catalogue import CATALOGUE, entry
from armik.model.reduce import check_frames, check_locked, check_offset, check_package_dirs
from armik.model.relock import relocked
from armik.model.urdf import URDFInfo, read_urdf, read_urdf_string
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


@overload
def load(
    source: str | Path,
    *,
    base: str | None = None,
    tip: str | None = None,
    locked: Mapping[str, float] | None = None,
    tip_offset: tuple[float, float, float] | None = None,
    package_dirs: Sequence[str | Path] | None = None,
    srdf: str | Path | None = None,
    tips: None = None,
) -> Arm: ...


@overload
def load(
    source: str | Path,
    *,
    base: str | None = None,
    tip: str | None = None,
    locked: Mapping[str, float] | None = None,
    tip_offset: tuple[float, float, float] | None = None,
    package_dirs: Sequence[str | Path] | None = None,
    srdf: str | Path | None = None,
    tips: Sequence[str],
) -> Arms: ...


def load(
    source: str | Path,
    *,
    base: str | None = None,
    tip: str | None = None,
    locked: Mapping[str, float] | None = None,
    tip_offset: tuple[float, float, float] | None = None,
    package_dirs: Sequence[str | Path] | None = None,
    srdf: str | Path | None = None,
    tips: Sequence[str] | None = None,
) -> Arm | Arms:
    """Load an arm from a bundled robot name (see ``armik.robots()``), a URDF path, or the
    URDF's XML itself (a string that starts with ``<``, as ROS hands out
    ``robot_description``; see ``load_string``).

    The chain runs from ``base`` (default: the URDF root link) to ``tip`` (default: the
    catalogue tip, else ``tool0`` (REP 199), else a gripper's tool frame (the Panda URDF's
    ``panda_hand_tcp``) or hand, else the end of the longest chain of moving joints:
    docs/urdf.md; ``Arm.tip_reason`` says which and why). A joint named in ``locked``
    (joint name -> rad or m, within its URDF limits) is held at that value: off the chain,
    or on it, where it becomes a fixed transform and the results carry only the free
    joints (``Arm.locked`` lists them). Every other joint off the chain is held at its
    neutral value. ``tip_offset`` (m, in the tip frame) moves the tool point.
    ``package_dirs``: folders where ``package://`` mesh paths are looked up (for meshes:
    collision geometry, the viewer). ``srdf``: an SRDF file whose ``<disable_collisions>``
    pairs of links are not checked for self-collision. The arm's name is the catalogue
    name, else the URDF's ``<robot name>``.

    ``tips`` (instead of ``tip``): an ``armik.arms.Arms``, a chain per tip from one base,
    solved together (``Arms.solve({tip: target})``), sharing joints or not (``Arms.shared``).

    Raises ``URDFError``, ``FrameError``, ``JointError`` or ``OptionError`` (all
    ``ValueError``) naming the bad value and the fix.
    """
    if tips is not None:
        return _several(source, tips, tip, base=base, locked=locked, tip_offset=tip_offset,
                        package_dirs=package_dirs, srdf=srdf)  # fmt: skip
    if isinstance(source, str) and source.lstrip().startswith("<"):
        return load_string(
            source, base=base, tip=tip, locked=locked, tip_offset=tip_offset,
            package_dirs=package_dirs, srdf=srdf,
        )  # fmt: skip
    if not isinstance(source, (str, Path)):
        raise URDFError(
            f"source must be a robot name or a path to a URDF file (or the URDF's XML), "
            f"got {source!r}",
            path=str(source),
        )
    check_frames(base, tip, str(source))
    locked = check_locked(locked)
    tip_offset = check_offset(tip_offset)
    dirs = check_package_dirs(package_dirs)
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
        if not _exists(path) and path.suffix.lower() not in (".urdf", ".xml"):
            raise URDFError(
                f"{_shown(name)!r} is neither a bundled robot ({listing(CATALOGUE)}) nor an "
                f"existing URDF file: {did_you_mean(name, CATALOGUE)}check the name or the path",
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
    name = info.name if name_from_urdf and info.name else name
    arm = _built(
        model, info, name, str(path), base, tip, locked, tip_offset, dirs, srdf, given=str(source)
    )
    if not name_from_urdf and tip == spec.tip:
        arm.kinematics.tip_reason = f"the catalogue's tip for {name!r}"
    return arm


def _several(source: str | Path, tips: Sequence[str], tip: str | None, **kwargs: Any) -> Arms:
    """``load``'s ``tips``: one chain per tip, as an ``Arms``."""
    if tip is not None:
        raise OptionError(
            f"give tip= for one chain or tips= for several, not both (tip={tip!r})",
            option="tips",
            value=tips,
        )
    if isinstance(tips, str) or not tips or not all(isinstance(t, str) for t in tips):
        raise OptionError(
            f"tips must be a list of frame names, got {tips!r}", option="tips", value=tips
        )
    twice = sorted({t for t in tips if list(tips).count(t) > 1})
    if twice:
        raise OptionError(
            f"tips {list(tips)} name {twice} more than once: list each tip once",
            option="tips",
            value=tips,
        )
    return Arms({t: load(source, tip=t, **kwargs) for t in tips})


def load_string(
    xml: str,
    *,
    base: str | None = None,
    tip: str | None = None,
    locked: Mapping[str, float] | None = None,
    tip_offset: tuple[float, float, float] | None = None,
    package_dirs: Sequence[str | Path] | None = None,
    srdf: str | Path | None = None,
) -> Arm:
    """Load an arm from a URDF's XML text (ROS 2's ``robot_description``), with the same
    arguments, checks, errors and default tip as ``load`` of a file. The arm pickles with
    its text, so it travels to worker processes as a file-loaded arm does. Xacro is not
    expanded here: pass the expanded URDF (``xacro robot.urdf.xacro``)."""
    if not isinstance(xml, str):
        raise URDFError(f"xml must be the URDF's text (a str), got {type(xml).__name__}")
    check_frames(base, tip, "ROBOT")
    locked = check_locked(locked)
    tip_offset = check_offset(tip_offset)
    dirs = check_package_dirs(package_dirs)
    model, info = read_urdf_string(xml.lstrip(), STRING_SOURCE)  # <?xml ...?> comes first
    name = info.name or "robot"
    return _built(
        model, info, name, STRING_SOURCE, base, tip, locked, tip_offset, dirs, srdf, text=xml
    )


def _built(
    model: pin.Model,
    info: URDFInfo,
    name: str,
    source: str,
    base: str | None,
    tip: str | None,
    locked: Mapping[str, float] | None,
    tip_offset: tuple[float, float, float] | None,
    dirs: tuple[str, ...],
    srdf: str | Path | None,
    *,
    given: str | None = None,
    text: str | None = None,
) -> Arm:
    """The arm of a read URDF, its package folders and SRDF pairs set, and its recipe:
    ``given`` is what ``load`` was given (a robot name, a path; default ``source``),
    ``text`` the XML of ``load_string``."""
    kinematics = ArmModel(
        model,
        info,
        name=name,
        base=base,
        tip=tip,
        locked=locked or {},
        tip_offset=tip_offset,
        source=source,
    )
    kinematics.package_dirs = dirs
    if srdf is not None:
        kinematics.disabled_pairs = read_srdf(srdf, info.links)
        srdf = str(Path(srdf).resolve())
    kinematics._recipe = Recipe(
        source if given is None else given,
        base,
        tip,
        dict(locked or {}),
        kinematics.tip_offset,
        (),
        dirs,
        text=text,
        srdf=srdf,
    )
    return Arm(kinematics)


STRING_SOURCE = "<string>"  # Arm.source of an arm read from XML text


def _exists(path: Path) -> bool:
    """Whether ``path`` exists; False for a name the system cannot look up at all (too
    long, an embedded NUL): such a name is no file either."""
    try:
        return path.exists()
    except (OSError, ValueError):
        return False


def _shown(name: str) -> str:  # shortened for an error message: a long string is no name
    return name if len(name) <= 80 else name[:77] + "..."


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
    package_dirs: tuple[str, ...] = ()
    text: str | None = None  # the URDF itself, for an arm read from XML text
    srdf: str | None = None

    def locked_model(self, locked: object, example: str) -> ArmModel:
        """This recipe's arm model with ``locked``'s joints (name -> rad or m) locked too, within
        their replaced limits; ``example``: a joint for the error to name."""
        new = check_locked(locked)
        if new is None:
            raise JointError(
                "locked must map joint names to values (rad or m), e.g. "
                f"{{{example!r}: 0.0}}; got None",
                joint="None",
            )
        return replace(self, locked={**self.locked, **new}).build_model()

    def build_model(self) -> ArmModel:
        """The arm model this recipe builds (how an ``ArmModel`` unpickles)."""
        return self.build().kinematics

    def build(self) -> Arm:
        own = {name: (lo, hi) for name, lo, hi in self.limits}  # a joint's locked since too
        arm = (load if self.text is None else load_string)(
            self.source if self.text is None else self.text,
            base=self.base,
            tip=self.tip,
            locked={name: v for name, v in self.locked.items() if name not in own} or None,
            tip_offset=self.tip_offset,
            package_dirs=self.package_dirs or None,
            srdf=self.srdf,
        )
        model = relocked(arm.kinematics, self.locked, own)  # own: its free joints' limits too
        model._recipe = self
        return Arm(model)


class Arm:
    """One robot arm's chain and its solvers; built by ``armik.load``.

    Attributes (read-only): ``name``, ``source`` (the URDF's path, or "<string>"),
    ``dof``, ``joint_names``, ``joint_types``, ``lower``, ``upper`` (rad or m; -inf/+inf
    for continuous joints), ``neutral``, ``middle``, ``base``, ``tip``, ``tip_reason``
    (how the tip was chosen when none was given), ``locked`` (every joint locked by
    value, on or off the chain, name -> rad or m), ``info`` (what the URDF says: its tree,
    and ``info.notes`` on how it was read), ``model`` (the reduced Pinocchio model, not
    to be modified) and ``kinematics``, the arm model everything else reads
    (``armik.model.arm_model.ArmModel``: the tip offset, the joints locked on the chain,
    Pinocchio coordinates, the compiled chain, ...).
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
        # ``solve_one``'s route, inline: a warm solve's Python calls are its budget
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
        # ``solve_one``'s route, inline, as ``solve``'s
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
