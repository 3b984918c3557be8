"""The servo (``Arm.servo``) against Pink's ``solve_ik`` (daqp) with the same limits, on the
same target streams, interleaved in one run (armik, then Pink, on each stream; the order
alternates between arms).

Streams at dt = 2 ms (``armik.servo.streams``), from each arm's start configuration:
``circle``, a 10 cm circle at 0.5 Hz in the base frame's y-z plane, orientation held (3000
ticks); ``jump``, the tip's pose 25 cm along y, held 2 s (1000 ticks); ``reach``, a target
3 m along x for 1 s, then the start pose again for 2 s (1500 ticks).

Limits: the URDF's positions and velocities and 20 rad/s^2 on every joint. Pink: a
``FrameTask`` on the tip (position and orientation costs 1, gain 1), ``ConfigurationLimit``,
``VelocityLimit`` and ``AccelerationLimit`` (its braking distance), ``solve_ik`` with daqp,
each tick integrated with ``pin.integrate``. Pink is optional: without it, armik alone.
Then, on the Panda, the circle with a 5 cm sphere on its way and a 1 cm margin (armik
alone, with and without ``obstacles=``): the smallest distance by ``arm.min_distance``.

Reported per arm, stream and solver: the largest excess over each limit of the commanded
q sequence by finite differences (0 = none), the tip's RMS position error (m, by armik's
FK of the commanded q; the circle's after its first 0.1 s, the arm starting at rest), the
final error, the ticks to settle within 1e-5 m (jump), NaNs, the mean, median and p99
time of a tick (the whole call: parsing, the step, the result), the mean CPU time of a
tick (the thread's CPU time over the stream's loop, per tick: the other processes' time
slices, which a loaded machine puts in the wall-clock mean's tail, do not count), the RMS
jerk of q (rad/s^3, third differences) and the fraction of q's power above 3 Hz (of its
detrended spectrum); then armik's mean, median and CPU mean over Pink's, per stream.

    PYTHONPATH=/tmp/peerpkgs python benchmarks/servo.py [--arms panda ur5 xarm7 abb_irb120]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import pinocchio as pin

import armik
from armik.servo.limits import DEFAULT_ACCELERATION
from armik.servo.streams import JUMP, START, circle, moved, violations

os.environ.setdefault("ARMIK_FIRST_CALLS", "compile")  # time compiled code, not Python runs

DT = 0.002
ARMS = ("panda", "ur5", "xarm7", "abb_irb120")
DAMPING = 1e-6  # Pink's solve_ik damping: its default, 1e-12, leaves daqp no solution on 7 joints


def streams(T0: pin.SE3) -> dict[str, list[pin.SE3]]:
    far = moved(T0, np.array([3.0, 0.0, 0.0]))
    return {
        "circle": circle(T0, 3000, DT),
        "jump": [moved(T0, JUMP)] * 1000,
        "reach": [far] * 500 + [T0] * 1000,
    }


SPHERE = np.array([0.0, 0.16, -0.16])  # m from the Panda's start tip: on its circle's way
MARGIN = 0.01


def run_armik(arm, q0, targets, **options):
    servo = arm.servo(q0, dt=DT, acceleration_limits=DEFAULT_ACCELERATION, **options)
    Q, times = np.empty((len(targets), arm.dof)), np.empty(len(targets))
    clock = time.perf_counter
    cpu = time.thread_time()
    for k, T in enumerate(targets):
        t = clock()
        s = servo.step(T)
        times[k] = clock() - t
        Q[k] = s.q
    return Q, times, None, (time.thread_time() - cpu) / len(targets)


def run_pink(arm, q0, targets):
    import pink
    from pink.limits import AccelerationLimit, ConfigurationLimit, VelocityLimit
    from pink.tasks import FrameTask

    model, kin = arm.model, arm.kinematics
    data = model.createData()
    frame = model.frames[kin.tip_frame_id].name
    task = FrameTask(frame, position_cost=1.0, orientation_cost=1.0, gain=1.0)
    accel = AccelerationLimit(model, np.full(model.nv, DEFAULT_ACCELERATION))
    limits = [ConfigurationLimit(model), VelocityLimit(model), accel]
    qp = kin.to_pin(q0)
    conf = pink.Configuration(model, data, qp)
    Q, times = np.full((len(targets), arm.dof), np.nan), np.empty(len(targets))
    clock = time.perf_counter
    failed = None
    cpu, ticks = time.thread_time(), len(targets)
    for k, T in enumerate(targets):
        t = clock()
        try:
            task.set_target(kin.T_world_base * T)
            v = pink.solve_ik(conf, [task], DT, solver="daqp", damping=DAMPING, limits=limits)
            qp = pin.integrate(model, qp, v * DT)
            conf.update(qp)
            accel.set_last_integration(v, DT)
        except Exception as exc:  # Pink raises when its QP has no solution
            failed = failed or f"tick {k}: {type(exc).__name__}"
            times[k] = clock() - t
            ticks = k + 1
            break
        times[k] = clock() - t
        Q[k] = kin.from_pin(qp)
    return Q, times, failed, (time.thread_time() - cpu) / ticks


def jitter(Q: np.ndarray) -> tuple[float, float]:
    """(RMS jerk rad/s^3, fraction of the detrended spectrum's power above 3 Hz)."""
    jerk = np.diff(Q, n=3, axis=0) / DT**3
    t = np.arange(Q.shape[0])
    X = Q - np.polyval(np.polyfit(t, Q, 1), t[:, None]) if Q.shape[0] > 2 else Q
    P = np.abs(np.fft.rfft(X, axis=0)) ** 2
    f = np.fft.rfftfreq(Q.shape[0], DT)
    total = P.sum()
    return float(np.sqrt(np.mean(jerk**2))), float(P[f > 3.0].sum() / total) if total else 0.0


def measure(arm, q0, name, targets, Q, times, failed, cpu):
    ok = np.isfinite(Q).all(axis=1)
    n_ok = int(ok.sum())
    Qv = Q[:n_ok]
    tips = arm.fk_batch(Qv)[:, :3, 3] if n_ok else np.empty((0, 3))
    goal = np.array([T.translation for T in targets[:n_ok]]).reshape(-1, 3)
    err = np.linalg.norm(tips - goal, axis=1)
    vmax = arm.model.velocityLimit
    if n_ok:
        over = violations(q0, Qv, arm.lower, arm.upper, vmax, DEFAULT_ACCELERATION, DT)
    else:
        over = dict.fromkeys(("position", "velocity", "acceleration"), float("nan"))
    skip = 50 if name == "circle" else 0
    rms = float(np.sqrt(np.mean(err[skip:] ** 2))) if n_ok > skip else float("nan")
    settled = np.flatnonzero(err > 1e-5)
    settle = (int(settled[-1]) + 1 if settled.size else 0) if name == "jump" else None
    jerk, high = jitter(Qv) if n_ok > 3 else (float("nan"), float("nan"))
    return {
        "over": over,
        "rms": rms,
        "final": float(err[-1]) if n_ok else float("nan"),
        "settle": settle,
        "nan": len(targets) - n_ok,
        "mean_us": float(np.mean(times[:n_ok]) * 1e6) if n_ok else float("nan"),
        "p99_us": float(np.percentile(times[:n_ok], 99) * 1e6) if n_ok else float("nan"),
        "median_us": float(np.median(times[:n_ok]) * 1e6) if n_ok else float("nan"),
        "cpu_us": cpu * 1e6,
        "jerk": jerk,
        "high": high,
        "failed": failed,
    }


def row(arm_name, stream, solver, m) -> str:
    o = m["over"]
    over = f"{o['position']:.1e} / {o['velocity']:.1e} / {o['acceleration']:.1e}"
    settle = "" if m["settle"] is None else f"{m['settle']}"
    fail = f" ({m['failed']})" if m["failed"] else ""
    return (
        f"| {arm_name} | {stream} | {solver}{fail} | {over} | {m['rms']:.2e} | {m['final']:.1e} "
        f"| {settle} | {m['mean_us']:.1f} | {m['median_us']:.1f} | {m['p99_us']:.1f} "
        f"| {m['cpu_us']:.1f} | {m['jerk']:.3g} | {m['high']:.1e} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--arms", nargs="+", default=list(ARMS))
    parser.add_argument("--no-pink", action="store_true", help="armik alone")
    args = parser.parse_args()
    try:
        import pink  # noqa: F401

        peers = not args.no_pink
    except ImportError:
        peers = False
        print("Pink is not importable: armik alone")
    print(
        "| arm | stream | solver | excess pos / vel / acc | RMS error (m) | final (m) "
        "| settle (ticks) | mean (us) | median (us) | p99 (us) | CPU mean (us) "
        "| RMS jerk (rad/s^3) | power > 3 Hz |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    ratios = []
    for i, name in enumerate(args.arms):
        arm = armik.load(name)
        q0 = START[name]
        arm.servo(q0).step(arm.fk(q0))  # compiled before the clock runs
        runners = [("armik", run_armik)] + ([("pink", run_pink)] if peers else [])
        if i % 2:
            runners.reverse()
        for stream, targets in streams(arm.fk(q0)).items():
            ms = {}
            for solver, run in runners:
                Q, times, failed, cpu = run(arm, q0, targets)
                ms[solver] = m = measure(arm, q0, stream, targets, Q, times, failed, cpu)
                print(row(name, stream, solver, m), flush=True)
            if peers:
                ratios.append((name, stream, ms["armik"], ms["pink"]))
    if ratios:
        print("\n| arm | stream | armik / Pink: mean | median | CPU mean |\n|---|---|---|---|---|")
        for name, stream, a, p in ratios:
            r = [a[key] / p[key] for key in ("mean_us", "median_us", "cpu_us")]
            print(f"| {name} | {stream} | {r[0]:.3f} | {r[1]:.3f} | {r[2]:.3f} |")
    if "panda" in args.arms:
        sphere_stream()


def sphere_stream() -> None:
    """The Panda's circle with a 5 cm sphere on its way, kept at a 1 cm margin (armik
    alone): the smallest distance by ``arm.min_distance`` on every commanded q."""
    arm, q0 = armik.load("panda"), START["panda"]
    T0 = arm.fk(q0)
    sphere = armik.Sphere(0.05, tuple(T0.translation + SPHERE))
    targets = circle(T0, 3000, DT)
    print("\n| Panda circle, 5 cm sphere | min distance (m) | excess pos / vel / acc "
          "| final (m) | mean (us) | median (us) | p99 (us) |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    for obstacles in (None, [sphere]):
        # a margin with no obstacle checks nothing and is refused: only beside the sphere
        options = {"obstacles": obstacles, "margin": MARGIN} if obstacles else {}
        Q, times, failed, cpu = run_armik(arm, q0, targets, **options)
        m = measure(arm, q0, "circle", targets, Q, times, failed, cpu)
        d = min(arm.min_distance(q, [sphere])[0] for q in Q)
        o = m["over"]
        print(
            f"| {'avoiding' if obstacles else 'not avoiding'} | {d:.4f} "
            f"| {o['position']:.1e} / {o['velocity']:.1e} / {o['acceleration']:.1e} "
            f"| {m['final']:.1e} | {m['mean_us']:.1f} | {m['median_us']:.1f} "
            f"| {m['p99_us']:.1f} |"
        )


if __name__ == "__main__":
    main()
