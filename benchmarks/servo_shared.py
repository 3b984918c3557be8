"""The servo over chains that share joints (``Arms.servo`` on TALOS's two hands, its torso
shared: ``armik.servo.union``) against Pink's ``solve_ik`` (daqp) with the same limits and
two frame tasks on the same model, interleaved in one run.

Streams at dt = 2 ms from a start configuration (``--seed``, within the limits):
``sway``, every joint swaying by up to 0.2 rad at 0.5 Hz and both hands' poses taken from
it (3000 ticks: every tick's targets are met by one configuration); ``circle``, both hands
on 5 cm circles at 0.5 Hz in the base's y-z plane, orientation held (3000 ticks: met where
the limits allow); ``reach``, the left hand 3 m along x for 1 s, then both hands back at
the start for 2 s (1500 ticks).

With ``--collisions``, armik alone on TALOS with its SRDF: both hands led in 1.5 s to
where the other is (2 s), with and without ``self_collision=True`` (margin 1 cm),
interleaved: the mean time of a tick and their ratio, by the wall clock and by the thread's
CPU time (which a loaded machine's other processes do not inflate).

Limits: the URDF's positions and velocities, 20 rad/s^2 on every joint. Reported per
stream and solver: the largest excess over each limit of the commanded sequence by finite
differences, the RMS of the larger hand's position error (after the first 0.1 s), the final
error, NaNs, the mean, median and p99 time of a tick and the mean CPU time of a tick; then
armik's over Pink's.

    PYTHONPATH=/tmp/peerpkgs python benchmarks/servo_shared.py [--seed 5] [--no-pink]
        [--collisions]
"""

from __future__ import annotations

import argparse
import os
import time
from importlib import metadata
from pathlib import Path

import numpy as np
import pinocchio as pin

import armik
from armik.servo.limits import DEFAULT_ACCELERATION
from armik.servo.streams import violations

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

DT = 0.002
TIPS = ("gripper_left_base_link", "gripper_right_base_link")
DAMPING = 1e-6


def talos(srdf: bool = False) -> armik.Arms:
    share = Path(str(metadata.distribution("example-robot-data").locate_file("cmeel.prefix")))
    data = share / "share/example-robot-data/robots/talos_data"
    pairs = data / "srdf/talos.srdf" if srdf else None
    return armik.load(data / "robots/talos_reduced.urdf", tips=list(TIPS), srdf=pairs)


def collisions() -> None:
    """The ``--collisions`` table (module docstring)."""
    robot = talos(srdf=True)
    q0 = robot.middle
    at = {t: robot.fk(q0, t).translation for t in TIPS}
    middle = 0.5 * (at[TIPS[0]] + at[TIPS[1]])
    goal = {TIPS[0]: middle + [0.0, -0.05, 0.0], TIPS[1]: middle + [0.0, 0.05, 0.0]}
    stream = [{t: at[t] + min(1.0, k / 750) * (goal[t] - at[t]) for t in TIPS} for k in range(1000)]
    robot.servo(q0, self_collision=True).step(stream[0])  # the compiled parts, once
    times: dict[str, list[float]] = {"without": [], "self_collision": []}
    cpu: dict[str, list[float]] = {"without": [], "self_collision": []}
    for _ in range(3):
        for name in times:
            servo = robot.servo(q0, dt=DT, self_collision=name != "without")
            t, c = time.perf_counter(), time.thread_time()
            servo.track(stream)
            times[name].append((time.perf_counter() - t) / len(stream) * 1e6)
            cpu[name].append((time.thread_time() - c) / len(stream) * 1e6)
    rows = servo._union._collisions
    pairs = len(rows.self_pairs)
    print(f"TALOS with its SRDF, self-collision: {len(rows.objects)} links' shapes, {pairs} pairs")
    a, b = np.mean(times["self_collision"]), np.mean(times["without"])
    print(f"hands meet: without {b:.0f} us a tick, self_collision {a:.0f} us, ratio {a / b:.0f}")
    a, b = np.mean(cpu["self_collision"]), np.mean(cpu["without"])
    print(f"  CPU time: without {b:.0f} us a tick, self_collision {a:.0f} us, ratio {a / b:.0f}")


def streams(robot, q0) -> dict[str, list[dict]]:
    sway = np.random.default_rng(1).uniform(-1.0, 1.0, robot.dof)
    qs = [q0 + 0.2 * np.sin(np.pi * k * DT) * sway for k in range(1, 3001)]
    qs = [np.clip(q, robot.lower, robot.upper) for q in qs]
    start = {t: robot.fk(q0, t) for t in TIPS}

    def circled(k: int) -> dict:
        a = np.pi * k * DT
        d = 0.05 * np.array([0.0, np.sin(a), np.cos(a) - 1.0])
        return {t: pin.SE3(T.rotation, T.translation + d) for t, T in start.items()}

    far = dict(start)
    far[TIPS[0]] = pin.SE3(start[TIPS[0]].rotation, start[TIPS[0]].translation + [3.0, 0, 0])
    return {
        "sway": [{t: robot.fk(q, t) for t in TIPS} for q in qs],
        "circle": [circled(k) for k in range(1, 3001)],
        "reach": [far] * 500 + [start] * 1000,
    }


def run_armik(robot, q0, targets):
    servo = robot.servo(q0, dt=DT, acceleration_limits=DEFAULT_ACCELERATION)
    Q, times = np.empty((len(targets), robot.dof)), np.empty(len(targets))
    cpu = time.thread_time()
    for k, goal in enumerate(targets):
        t = time.perf_counter()
        Q[k] = servo.step(goal).q
        times[k] = time.perf_counter() - t
    return Q, times, None, (time.thread_time() - cpu) / len(targets)


def run_pink(robot, q0, targets):
    import pink
    from pink.limits import AccelerationLimit, ConfigurationLimit, VelocityLimit
    from pink.tasks import FrameTask

    union = robot._joint()
    model = union.model
    assert model.nq == model.nv == robot.dof  # TALOS: no continuous joint
    tasks = {t: FrameTask(t, position_cost=1.0, orientation_cost=1.0, gain=1.0) for t in TIPS}
    accel = AccelerationLimit(model, np.full(model.nv, DEFAULT_ACCELERATION))
    limits = [ConfigurationLimit(model), VelocityLimit(model), accel]
    qp = union.to_pin(q0)
    conf = pink.Configuration(model, model.createData(), qp)
    world = union.T_base_world.inverse()
    Q, times = np.full((len(targets), robot.dof), np.nan), np.empty(len(targets))
    failed, ticks, cpu = None, len(targets), time.thread_time()
    for k, goal in enumerate(targets):
        t = time.perf_counter()
        try:
            for tip, task in tasks.items():
                task.set_target(world * goal[tip])
            v = pink.solve_ik(
                conf, list(tasks.values()), DT, solver="daqp", damping=DAMPING, limits=limits
            )
            qp = pin.integrate(model, qp, v * DT)
            conf.update(qp)
            accel.set_last_integration(v, DT)
        except Exception as exc:  # Pink raises when its QP has no solution
            failed, ticks = f"tick {k}: {type(exc).__name__}", k + 1
            times[k] = time.perf_counter() - t
            break
        times[k] = time.perf_counter() - t
        Q[k] = qp
    return Q, times, failed, (time.thread_time() - cpu) / ticks


def measure(robot, q0, vmax, targets, Q, times, failed, cpu) -> dict:
    done = ~np.isnan(Q).any(axis=1)
    err = np.array([
        max(np.linalg.norm(robot.fk(q, t).translation - g[t].translation) for t in TIPS)
        for q, g in zip(Q[done], targets)
    ])  # fmt: skip
    over = violations(q0, Q[done], robot.lower, robot.upper, vmax, DEFAULT_ACCELERATION, DT)
    ticks = times[: int(done.sum()) or 1] * 1e6
    return {
        "over": over,
        "rms": float(np.sqrt(np.mean(err[50:] ** 2))) if len(err) > 50 else float("nan"),
        "final": float(err[-1]) if len(err) else float("nan"),
        "failed": failed,
        "mean": float(ticks.mean()),
        "median": float(np.median(ticks)),
        "p99": float(np.percentile(ticks, 99)),
        "cpu": cpu * 1e6,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--no-pink", action="store_true")
    parser.add_argument("--collisions", action="store_true")
    args = parser.parse_args()
    if args.collisions:
        collisions()
        return
    try:
        import pink  # noqa: F401

        peers = not args.no_pink
    except ImportError:
        peers = False
    robot = talos()
    q0 = robot.random_q(args.seed) * 0.3
    q0 = np.clip(q0, robot.lower, robot.upper)
    warm = robot.servo(q0)
    warm.step({t: robot.fk(q0, t) for t in TIPS})  # the compiled parts, once
    vmax = warm.velocity_limits  # the URDF's
    print(f"TALOS, tips {list(TIPS)}, shared {list(robot.shared)}, {robot.dof} joints")
    runners = [("armik", run_armik)] + ([("pink", run_pink)] if peers else [])
    for i, (name, stream) in enumerate(streams(robot, q0).items()):
        got = {}
        for solver, run in runners if i % 2 == 0 else runners[::-1]:
            got[solver] = measure(robot, q0, vmax, stream, *run(robot, q0, stream))
        for solver, m in got.items():
            o = m["over"]
            print(
                f"{name:7s} {solver:6s} over pos/vel/acc {o['position']:.1e}/{o['velocity']:.1e}/"
                f"{o['acceleration']:.1e}  rms {m['rms']:.2e} m  final {m['final']:.2e} m  "
                f"mean {m['mean']:.0f} us  median {m['median']:.0f}  p99 {m['p99']:.0f}  "
                f"cpu {m['cpu']:.0f} us" + (f"  FAILED {m['failed']}" if m["failed"] else "")
            )
        if "pink" in got:
            a, p = got["armik"], got["pink"]
            print(
                f"{name:7s} armik/pink mean {a['mean'] / p['mean']:.3f}  median "
                f"{a['median'] / p['median']:.3f}  cpu {a['cpu'] / p['cpu']:.3f}"
            )


if __name__ == "__main__":
    main()
