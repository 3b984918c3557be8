"""Other IK libraries, timed on armik's own targets by ``armik bench --peers``.

- ``rtb``: the Robotics Toolbox for Python's C++ Levenberg-Marquardt solver ``ik_LM`` with
  its defaults (30 iterations x 100 searches, joint limits on), its tolerance on the
  residual E = |e|^2 / 2 set to 0.5 tol^2 so that a success means errors under ``tol``.
  The robot is built from the arm's own URDF file (visual and collision elements removed,
  because the Toolbox resolves their mesh packages through xacro; kinematics untouched)
  from the arm's base to its tip (plus the tip offset as its tool), and its FK is checked
  against armik's on random configurations before any timing.
- ``eaik``: EAIK's closed-form solver (``UrdfRobot.IK``) on 6R arms it decomposes. Its end
  frame differs from the arm's tip by a constant transform, fitted at q = 0 and checked on
  random configurations; of its exact solutions, the one within armik's limits nearest q0
  is kept.

Only the library's own call is timed (``Peer.elapsed``). Both are optional
(``pip install armik[peers]``). Every answer is judged by armik's FK check, never by the
peer's own claim.
"""

from __future__ import annotations

import os
import re
import tempfile
import time
from dataclasses import dataclass, field

import numpy as np

from armik.arm import Arm
from armik.errors import OptionError

PEERS = ("rtb", "eaik")
FK_AGREEMENT = 1e-9  # m and rotation-matrix entries: the peer's FK must match armik's


INSTALL = 'pip install "armik[peers]"'


class PeerUnavailable(Exception):
    """The peer is not installed or does not apply to this arm (the message says why)."""


class PeerMissing(PeerUnavailable):
    """The peer's library is not installed: the message names the extra that installs it."""

    def __init__(self, library: str) -> None:
        super().__init__(f"{library} is not installed: {INSTALL}")


@dataclass
class Peer:
    """A peer solver. ``solve`` returns joint values (rad, m) for a 4x4 target in the arm's
    base frame and sets ``elapsed`` (s) to the time of the library's own call, without
    armik's adaptation around it (choosing among EAIK's solutions, for example)."""

    name: str
    arm: Arm
    iterations: list[int] = field(default_factory=list)
    elapsed: float | None = None

    def solve(self, T_base_target: np.ndarray, q0: np.ndarray) -> np.ndarray:
        raise NotImplementedError


def _check_fk(arm: Arm, fk, name: str) -> None:
    rng = np.random.default_rng(0)
    worst = 0.0
    for _ in range(20):
        q = arm.random_q(rng)
        worst = max(worst, float(np.abs(arm.fk(q).homogeneous - fk(q)).max()))
    if not worst <= FK_AGREEMENT:
        raise PeerUnavailable(f"{name}'s FK differs from armik's by {worst:.3g} on {arm.name}")


def _kinematics_only(path: str) -> str:
    """A copy of the URDF without visual and collision elements (a temporary file)."""
    with open(path) as f:
        text = f.read()
    text = re.sub(r"<(visual|collision)\b.*?</\1>", "", text, flags=re.S)
    text = re.sub(r"<(visual|collision)\b[^>]*/>", "", text)
    fd, out = tempfile.mkstemp(suffix=".urdf", prefix="armik_peer_")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    return out


class RTBPeer(Peer):
    def __init__(self, arm: Arm, tol: float) -> None:
        super().__init__("rtb", arm)
        try:
            import roboticstoolbox as rtb
            from spatialmath import SE3
        except ImportError:
            raise PeerMissing("roboticstoolbox-python") from None
        path = _kinematics_only(arm.kinematics.source)
        try:
            robot = rtb.Robot.URDF(path)
            self.ets = robot.ets(start=arm.base, end=arm.tip)
        except Exception as exc:  # the Toolbox's own parser errors
            raise PeerUnavailable(f"the Robotics Toolbox cannot build {arm.name}: {exc}") from None
        finally:
            os.unlink(path)
        if self.ets.n != arm.dof:
            raise PeerUnavailable(f"the Toolbox's chain has {self.ets.n} joints, armik's {arm.dof}")
        if arm.kinematics.tip_offset is not None:  # the tool point, as a last fixed transform
            self.ets = self.ets * rtb.ET.SE3(SE3(*arm.kinematics.tip_offset))
        self.tol = 0.5 * tol * tol  # E = |e|^2 / 2 < tol^2 / 2: each error under tol
        _check_fk(arm, self.fk, "the Robotics Toolbox")

    def fk(self, q: np.ndarray) -> np.ndarray:
        return self.ets.fkine(q).A

    def solve(self, T_base_target: np.ndarray, q0: np.ndarray) -> np.ndarray:
        t = time.perf_counter()
        sol = self.ets.ik_LM(
            T_base_target, q0=q0, ilimit=30, slimit=100, tol=self.tol, joint_limits=True
        )
        self.elapsed = time.perf_counter() - t
        self.iterations.append(int(sol.iterations))
        return np.asarray(sol.q, dtype=float)


class EAIKPeer(Peer):
    def __init__(self, arm: Arm, tol: float) -> None:
        super().__init__("eaik", arm)
        try:
            from eaik.IK_URDF import UrdfRobot
        except ImportError:
            raise PeerMissing("EAIK") from None
        try:
            self.robot = UrdfRobot(arm.kinematics.source)
        except Exception as exc:  # EAIK refuses what it cannot decompose
            raise PeerUnavailable(f"EAIK does not apply to {arm.name}: {exc}") from None
        if not self.robot.hasKnownDecomposition():
            raise PeerUnavailable(f"EAIK knows no decomposition of {arm.name}")
        B = arm.kinematics.T_base_world.homogeneous
        q = np.zeros(arm.dof)
        try:
            self.E = np.linalg.inv(B @ self.robot.fwdKin(q)) @ arm.fk(q).homogeneous
        except Exception as exc:
            raise PeerUnavailable(f"EAIK's chain does not match {arm.name}: {exc}") from None
        self.B_inv = np.linalg.inv(B)
        self.E_inv = np.linalg.inv(self.E)
        _check_fk(arm, lambda q: B @ self.robot.fwdKin(q) @ self.E, "EAIK")

    def solve(self, T_base_target: np.ndarray, q0: np.ndarray) -> np.ndarray:
        T = self.B_inv @ T_base_target @ self.E_inv
        t = time.perf_counter()
        sol = self.robot.IK(T)
        self.elapsed = time.perf_counter() - t
        self.iterations.append(0)
        best, best_d = None, np.inf
        for q, ls in zip(sol.Q, sol.is_LS):
            if ls:
                continue
            q = self.arm.kinematics.nearest_equivalent(np.asarray(q, dtype=float), q0)
            if not self.arm.within_limits(q):
                continue
            d = float(np.linalg.norm(q - q0))
            if d < best_d:
                best, best_d = q, d
        if best is None:
            return np.array(sol.Q[0], dtype=float) if len(sol.Q) else q0.copy()
        return best


def make(name: str, arm: Arm, tol: float) -> Peer:
    """The peer ``name`` for ``arm``; raises ``PeerUnavailable`` with the reason."""
    if name == "rtb":
        return RTBPeer(arm, tol)
    if name == "eaik":
        return EAIKPeer(arm, tol)
    raise OptionError(f"unknown peer {name!r}; peers: {', '.join(PEERS)}", option="peers")
