"""A servo over chains that share joints (a torso, a lift): one step over their union.

``Arms.servo`` on tips whose chains share a joint ticks this instead of one ``Servo`` per
chain: every tip's target is stacked over the union's joints (``armik.model.union``'s, in
its base frame), and one damped least-squares step goes toward all of them at once,
within the velocity box of ``armik.servo.box`` on every joint (position, velocity,
acceleration and braking limits). A tip's target is anything a chain's own servo takes
(``armik.servo.table``: a pose, a position, ``armik.Pose(..., bounds=)``, ``Axis``,
``LookAt``, a list of them on the tip), its rows those of a chain's own servo. What a
chain's own servo does, this does the same way (``armik.servo.step``): the damping grows
near a singularity and with the error, the joints that the tasks leave free are pulled
toward ``q0``, the step corrects ``gain`` of the error a tick, and obstacles
(``obstacles=``, ``margin=``) are kept at the margin by each chain's collision rows
(``armik.servo.collisions``), their columns in the union's.

The rows and the step are one compiled call (``armik.servo.union_tick``); a plain pose's
row is written there, any other target is read here once a tick.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from armik.checked import configuration
from armik.errors import OptionError, TargetError
from armik.frozen import frozen
from armik.model.union import Union
from armik.model.value_checks import violation as _violation
from armik.servo import layout as k
from armik.servo.fixed import never_moved, structural_ranks
from armik.servo.limits import (
    time_step,
)
from armik.servo.result import STATUSES, ServoStep
from armik.servo.servo import ON_TARGET, Commanded, at_rest, curvature
from armik.servo.table import table
from armik.servo.union_collisions import union_rows
from armik.servo.union_tick import allocate, python_views, rows_at, stacked, tick

KEYWORDS: tuple[str, ...] = ("dt", "velocity_limits", "acceleration_limits", "gain")
KEYWORDS += ("tol_position", "tol_orientation", "obstacles", "self_collision", "margin")


class UnionServo(Commanded):
    """One servo over the union of ``chains`` (tip -> its ``ArmModel``) held in ``union``,
    at rest at ``q0`` (one value per joint of ``union.joint_names``)."""

    def __init__(
        self,
        union: Union,
        chains: Mapping[str, object],
        q0: object,
        *,
        dt: object = 0.002,
        velocity_limits: object = None,
        acceleration_limits: object = None,
        gain: object = 1.0,
        tol_position: float = ON_TARGET,
        tol_orientation: float = ON_TARGET,
        obstacles: object = None,
        self_collision: object = False,
        margin: object = 0.01,
    ) -> None:
        self.union, self.tips = union, tuple(chains)
        self._chains = dict(chains)
        self.joint_names = union.joint_names
        n = union.dof
        self.dt = time_step(dt)
        q = configuration("q0", q0, self.joint_names)  # one finite value per joint
        if not union.within_limits(q, 0.0):
            outside = [
                _violation(name, v, lo, hi)
                for name, v, lo, hi in zip(self.joint_names, q, union.lower, union.upper)
                if not lo <= v <= hi
            ]
            raise OptionError(
                "q0 must lie within the joint limits (a servo never commands a position "
                "outside them): " + "; ".join(outside),
                option="q0",
                value=q0,
            )
        # the chains' kernel arrays one after the other, and their joints' union columns
        arms = [chains[tip] for tip in self.tips]
        flats = [arm.kernel_chain.flat for arm in arms]  # type: ignore[attr-defined]
        self._cols = [
            np.array([self.joint_names.index(j) for j in arm.joint_names], dtype=np.int64)  # type: ignore[attr-defined]
            for arm in arms
        ]
        at = np.array(
            [
                np.cumsum([0] + [f.packed.shape[0] for f in flats]),
                np.cumsum([0] + [f.kind.shape[0] for f in flats]),
                np.cumsum([0] + [len(c) for c in self._cols]),
            ],
            dtype=np.int64,
        )
        packed = np.concatenate([f.packed for f in flats])
        kinds = np.concatenate([f.kind for f in flats])
        self._mem, self._imem = allocate(n, packed, kinds, at, np.concatenate(self._cols))
        views = python_views(self._mem, self._imem)
        self._state, self._cfg, self._out, self._tables, self._H, self._counts, fixed, ranks = views
        for t, arm in enumerate(arms):
            fixed[t] = never_moved(arm)  # type: ignore[arg-type]
            ranks[t] = structural_ranks(arm)  # type: ignore[arg-type]
        at_rest(
            self._state, self._cfg, union, q, self.dt, velocity_limits, acceleration_limits,
            gain, tol_position, tol_orientation,
        )  # fmt: skip
        self._cfg[k.CURVE] = curvature(arms)
        self._no_rows = np.zeros((0, 2 * n + 1))
        self._collisions = union_rows(
            arms,  # type: ignore[arg-type]
            self._cols,
            n,
            obstacles,
            self_collision,
            margin,
            self.dt,
        )

    def step(self, targets: Mapping[str, object]) -> ServoStep:
        """One tick toward every tip's target (anything a chain's own servo takes); raises
        ``TargetError`` naming the tip whose target it cannot read."""
        counts, H = self._counts, self._H
        for t, tip in enumerate(self.tips):
            target = targets[tip]
            if type(target) is pin.SE3:  # a pose's row is written by the compiled tick
                H[t] = target.homogeneous  # type: ignore[attr-defined]
                counts[t] = 0
            elif type(target) is np.ndarray and target.shape == (4, 4) and target.dtype == float:
                H[t] = target
                counts[t] = 0
            else:
                self._read(t, target)
        near = self._rows()
        bad = tick(self._mem, self._imem, near)
        while bad >= 0:  # a 4x4 the parser does not keep as given: read it here
            self._read(bad, targets[self.tips[bad]])
            bad = tick(self._mem, self._imem, near)
        command = self._state[: k.ACC + 1].copy()  # q, dq, ddq: one read-only copy
        command.flags.writeable = False
        pos, ori, code, j, sigma, conflict = self._out.tolist()
        return frozen(
            ServoStep,
            q=command[k.Q],
            dq=command[k.V],
            ddq=command[k.ACC],
            status=STATUSES[int(code)],
            joint=self.joint_names[int(j)] if j >= 0 else None,
            position_error=None if pos != pos else pos,  # NaN: not measured
            orientation_error=None if ori != ori else ori,
            sigma=sigma,
            conflict=conflict != 0.0,
            tips=None,
        )

    def rows_at(self, targets: Mapping[str, object], q: np.ndarray) -> tuple[np.ndarray, ...]:
        """(E, A): the stacked rows toward ``targets`` at the union's joint values q and
        their Jacobian over the union's joints, as a tick builds them (for tests)."""
        for t, tip in enumerate(self.tips):
            self._read(t, targets[tip])
        rows = rows_at(np.array(q, dtype=float), self._mem, self._imem)
        E, A = stacked(self._mem, self._imem)
        return E[:rows].copy(), A[:rows].copy()

    def _read(self, t: int, target: object) -> None:
        """Tip t's target parsed into its rows of the tables."""
        tip = self.tips[t]
        try:
            rows = table(target, self._chains[tip])  # type: ignore[arg-type]
        except TargetError as error:
            raise TargetError(f"the target of tip {tip!r}: {error}") from None
        o = t * k.MAX_TASKS
        self._tables[o : o + len(rows)] = rows
        self._counts[t] = len(rows)
