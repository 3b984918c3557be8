"""``armik.load``: a URDF (a bundled robot's name, a path, or the XML itself) read into an
``Arm``, and the recipe an arm pickles as, rebuilt from in worker processes and by
``Arm.with_locked``."""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, overload

import pinocchio as pin

from armik.arm import Arm
from armik.arms import Arms
from armik.constraints.srdf import read_srdf
from armik.errors import ArmikWarning, JointError, OptionError, URDFError, did_you_mean, listing
from armik.model.arm_model import ArmModel
from armik.model.catalogue import CATALOGUE, entry
from armik.model.reduce import check_frames, check_locked, check_offset, check_package_dirs
from armik.model.relock import relocked
from armik.model.urdf import URDFInfo, read_urdf, read_urdf_string


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
        # the URDF read again: what reading it notes was said when the arm was first loaded
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ArmikWarning)
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
