"""A servo's per-joint limits, checked: velocity (the URDF's, or given) and acceleration
(given, else ``DEFAULT_ACCELERATION``), and the tick's time step."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from armik.errors import OptionError
from armik.model.arm_model import ArmModel
from armik.model.union import Union

# rad/s^2 (m/s^2 for a prismatic joint) on every joint where none is given: URDF has no
# acceleration limits; 20 is within what industrial and collaborative arms allow on their
# wrist joints and below it on most (give your arm's own: the Panda's are 7.5-20)
DEFAULT_ACCELERATION = 20.0
MAX_DT = 1.0  # s: a longer tick is no servo loop


def time_step(dt: object) -> float:
    """``dt`` (s) as a float in (0, ``MAX_DT``]; raises ``OptionError`` otherwise."""
    value = _real(dt)
    if not 0.0 < value <= MAX_DT:
        raise OptionError(
            f"dt must be the tick's period in seconds, in (0, {MAX_DT:g}], got {dt!r}: "
            "e.g. dt=0.002 for a 500 Hz loop",
            option="dt",
            value=dt,
        )
    return value


def gain_of(gain: object) -> float:
    """``gain`` (the fraction of the error corrected a tick) as a float in (0, 1]; raises
    ``OptionError`` otherwise."""
    g = _real(gain)
    if not 0.0 < g <= 1.0:
        raise OptionError(
            f"gain must be in (0, 1] (the fraction of the error corrected a tick), got {gain!r}",
            option="gain",
            value=gain,
        )
    return g


def tolerance_of(name: str, value: object) -> float:
    """A tolerance of being on target (``tol_position`` m, ``tol_orientation`` rad) as a
    float in (0, 1]; raises ``OptionError`` otherwise (NaN would never be on target)."""
    tol = _real(value)
    if not 0.0 < tol <= 1.0:
        raise OptionError(
            f"{name} must be in (0, 1] (m or rad: within it of the target a tick is on "
            f"target), got {value!r}",
            option=name,
            value=value,
        )
    return tol


def _real(value: object) -> float:
    """``value`` as a float where it is a real number (a numpy one too; not a bool, a
    string or None), else NaN, which every range check refuses."""
    real = (int, float, np.integer, np.floating)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, real):
        return math.nan
    return float(value)


def urdf_velocities(arm: ArmModel | Union) -> np.ndarray:
    """Each joint's URDF velocity limit (rad/s, m/s); inf where the URDF gives none (0)."""
    m = arm.model
    ids = [j for j in range(1, m.njoints) if m.joints[j].nq > 0]
    out = np.array([float(m.velocityLimit[m.joints[j].idx_v]) for j in ids])
    return np.where(out > 0.0, out, math.inf)


def mimic_own(arm: ArmModel | Union, value: Any, urdf: bool, default: float) -> list:
    """(driver index, |multiplier|, the mimic joint's own limit) per mimic joint of ``arm``:
    its own limit is ``value`` where that is one number (every joint's), else its URDF
    velocity limit (``urdf``; inf where the URDF gives none) or ``default``. A union has no
    mimic joints (``armik.model.union`` refuses them)."""
    mimics = getattr(arm, "mimics", ())
    if not mimics:
        return []
    m = arm.physical_model  # type: ignore[union-attr]
    one = np.ndim(value) == 0 and not isinstance(value, dict) and value is not None
    out = []
    for x in mimics:
        if one:
            own = _positive(value, "limit")
        elif urdf:
            own = float(m.velocityLimit[m.joints[m.getJointId(x.name)].idx_v])
            own = own if own > 0.0 else math.inf
        else:
            own = default
        out.append((arm.joint_index(x.driver), abs(x.multiplier), own))
    return out


def through_mimics(limits: np.ndarray, mimics: list) -> np.ndarray:
    """``limits`` (per driving joint) narrowed so that every mimic joint keeps its own: a
    driver moves a mimic joint |multiplier| times as fast, so its limit is at most the
    mimic's divided by |multiplier| (``mimic_own``'s triples)."""
    out = limits.copy()
    for k, multiplier, own in mimics:
        out[k] = min(out[k], own / multiplier)
    return out


def per_joint(value: object, arm: ArmModel | Union, name: str, default: np.ndarray) -> np.ndarray:
    """``value`` as one positive limit per joint: None gives ``default``, a number every
    joint, else one per joint (a mapping: joint name -> limit, the others ``default``'s)."""
    if value is None:
        out = default.copy()
    elif isinstance(value, dict):
        out = default.copy()
        for joint, limit in value.items():
            out[arm.joint_index(joint)] = _positive(limit, f"{name}[{joint!r}]")
    else:
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise OptionError(
                f"{name} must be a number or {arm.dof} numbers, got {value!r}",
                option=name,
                value=value,
            ) from None
        if arr.ndim == 0:
            arr = np.full(arm.dof, float(arr))
        if arr.shape != (arm.dof,):
            raise OptionError(
                f"{name} must be a number or one per joint ({arm.dof}: "
                f"{', '.join(arm.joint_names)}), got shape {arr.shape}",
                option=name,
                value=value,
            )
        out = np.array([_positive(x, name) for x in arr.tolist()])
    if not np.isfinite(out).all() and name != "velocity_limits":
        raise OptionError(f"{name} must be finite, got {out.tolist()}", option=name, value=value)
    return out


def _positive(x: object, name: str) -> float:
    try:
        value = float(x)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        value = math.nan
    if not value > 0.0:
        unit = "rad/s^2 or m/s^2" if name.startswith("acceleration") else "rad/s or m/s"
        raise OptionError(
            f"{name} must be positive ({unit} per joint), got {x!r}",
            option=name,
            value=x,
        )
    return value
