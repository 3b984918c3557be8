"""Whether the servo's tick pays for being compiled: the floor of a pure-numpy tick on the
Panda (Pinocchio's FK and frame Jacobian, the pose error and its Jacobian, numpy's eigh and
the damped solve, clipped to a box: no braking, no box QP, no result) against the whole
``Servo.step`` (parsing, the compiled tick, the result). Best of five rounds of 5000 calls,
twice.

    python benchmarks/servo_numpy_floor.py
"""

import os
import time

import numpy as np
import pinocchio as pin

import armik
from armik.servo.streams import JUMP, START, moved

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

arm = armik.load("panda")
model, kin = arm.model, arm.kinematics
data = model.createData()
fid = kin.tip_frame_id
q = kin.to_pin(START["panda"])
T = moved(arm.fk(START["panda"]), JUMP)


def numpy_tick() -> np.ndarray:
    pin.framesForwardKinematics(model, data, q)
    J = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL)
    M = data.oMf[fid]
    R = T.rotation.T @ M.rotation
    e = np.concatenate([T.rotation.T @ (M.translation - T.translation), pin.log3(R)])
    A = np.vstack([R @ J[:3], pin.Jlog3(R) @ J[3:]])
    ev, V = np.linalg.eigh(A.T @ A)
    x = V @ ((V.T @ (A.T @ -e)) / (ev + 1e-9))
    return np.clip(x, -0.004, 0.004)


def best(f, n: int = 5000) -> float:
    times = []
    for _ in range(5):
        t = time.perf_counter()
        for _ in range(n):
            f()
        times.append((time.perf_counter() - t) / n * 1e6)
    return min(times)


servo = arm.servo(START["panda"])
servo.step(T)
for _ in range(2):
    print(
        f"numpy tick floor {best(numpy_tick):.1f} us; "
        f"armik Servo.step {best(lambda: servo.step(T)):.1f} us"
    )
