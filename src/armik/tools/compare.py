"""Analytic versus numeric IK on the same seeded targets: accuracy, speed, success, branches.

``run`` measures; ``Report.text`` prints the tables; ``plot`` writes PNG figures with
matplotlib (the ``plot`` extra) on the Agg backend, never opening a window.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from armik.arm import Arm
from armik.kernel.tier import compiling
from armik.loading import load, load_string
from armik.model.random_arms import random_urdf
from armik.problem.settings import SolverSettings
from armik.solvers import registry
from armik.targets.pose import parse_target
from armik.tools.peers import EAIKPeer, PeerMissing, PeerUnavailable

BUDGET = 0.005  # s per numeric solve, as in the benchmark
TIGHT = 1e-12  # m, position tolerance on the 2-link arm


@dataclass
class Row:
    arm: str
    solver: str
    targets: int
    reachable: int
    success_rate: float  # % of reachable targets solved
    honest_failures: float  # % of unreachable targets reported as failures
    pos_err_median: float
    pos_err_max: float
    time_median_ms: float
    time_p95_ms: float
    same_branch_as_q0: float | None = None  # % (arms with a closed form)
    # rad: 2-link arm, to the closed form on q0's branch; 6R, to the nearest analytic branch
    max_diff_to_closed_form: float | None = None

    @classmethod
    def every_target_reachable(cls, arm: str, solver: str, ok, times_s, errors, **extra) -> Row:
        """A row for targets that are all reachable (6R targets from configurations)."""
        ms = np.asarray(times_s, dtype=float) * 1e3
        err = np.asarray(errors, dtype=float) if len(errors) else np.array([np.nan])
        return cls(
            arm=arm,
            solver=solver,
            targets=len(ms),
            reachable=len(ms),
            success_rate=100.0 * float(np.mean(ok)),
            honest_failures=100.0,
            pos_err_median=_stat(np.nanmedian, err),
            pos_err_max=_stat(np.nanmax, err),
            time_median_ms=float(np.median(ms)),
            time_p95_ms=float(np.percentile(ms, 95)),
            **extra,
        )

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass
class Report:
    rows: list[Row] = field(default_factory=list)
    samples: dict = field(default_factory=dict)  # per (arm, solver): raw arrays for plots
    singular: list[dict] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)  # what was not measured, and why

    def as_dict(self) -> dict:
        return {
            "rows": [r.as_dict() for r in self.rows],
            "near_boundary": self.singular,
            "notes": self.notes,
        }

    def text(self) -> str:
        lines = [
            "| arm | solver | targets | reachable | success % | failures reported % | "
            "pos err median (m) | pos err max (m) | time median (ms) | time p95 (ms) | "
            "lands on q0's branch % | max abs(q - closed form) (rad) |",
            "|" + "---|" * 12,
        ]
        for r in self.rows:

            def fmt(v, spec):
                return "-" if v is None else format(v, spec)

            lines.append(
                f"| {r.arm} | {r.solver} | {r.targets} | {r.reachable} | {r.success_rate:.1f} | "
                f"{r.honest_failures:.1f} | {r.pos_err_median:.1e} | {r.pos_err_max:.1e} | "
                f"{r.time_median_ms:.3f} | {r.time_p95_ms:.3f} | "
                f"{fmt(r.same_branch_as_q0, '.1f')} | {fmt(r.max_diff_to_closed_form, '.1e')} |"
            )
        lines.append(
            f"(planar_2link solved to {TIGHT:g} m; the others to the default 1e-6 "
            f"m / rad; numeric budget {BUDGET * 1e3:g} ms)"
        )
        lines.append(
            "(6R arms: q0 is the generating configuration disturbed by 0.4 rad; the last "
            "column is the largest distance, modulo 2 pi, to the nearest analytic branch; "
            "eaik: all solutions per call, without armik's verification)"
        )
        lines += self.notes
        if self.singular:
            lines += [
                "",
                "Near the stretched boundary of planar_2link (r = 1.8 m - d):",
                "| solver | d (m) | success | iterations | singular flag | q2 (rad) |",
                "|---|---|---|---|---|---|",
            ]
            for s in self.singular:
                lines.append(
                    f"| {s['solver']} | {s['d']:.0e} | {s['success']} | "
                    f"{s['iterations']} | {s['singular']} | {s['q2']:.2e} |"
                )
        return "\n".join(lines)


def _stat(f, values: np.ndarray) -> float:
    """``f`` of the finite values; NaN, without numpy's all-NaN warning, when there are none."""
    finite = values[np.isfinite(values)]
    return float(f(finite)) if finite.size else float("nan")


def _planar_targets(arm: Arm, n: int, rng: np.random.Generator) -> np.ndarray:
    """Targets uniform in a disc 20 % larger than the reach: some are unreachable."""
    radius = 1.2 * arm.kinematics.reach * np.sqrt(rng.uniform(size=n))
    angle = rng.uniform(-math.pi, math.pi, size=n)
    return np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1)


def _measure(
    arm: Arm,
    solver: str,
    targets,
    q0s,
    reachable: np.ndarray,
    key: str,
    report: Report,
    closed_form: list | None = None,
    **options,
) -> Row:
    times, errors, successes, branch_hits, diffs = [], [], [], [], []
    for i, (target, q0) in enumerate(zip(targets, q0s)):
        t = time.perf_counter()
        r = arm.solve(target, q0=q0, solver=solver, timeout=BUDGET, seed=i, **options)
        times.append(time.perf_counter() - t)
        successes.append(r.success)
        if r.success:
            errors.append(r.position_error)
        if closed_form is not None and r.success and arm.dof == 2:
            same = np.sign(r.q[1]) == np.sign(q0[1])
            branch_hits.append(same)
            ref = closed_form[i]
            if ref is not None and same:
                d = np.asarray(r.q) - ref
                diffs.append(float(np.abs(np.arctan2(np.sin(d), np.cos(d))).max()))
    solved = np.array(successes)
    ms = np.array(times) * 1e3
    err = np.array(errors) if errors else np.array([np.nan])
    report.samples[key] = {"time_ms": ms, "pos_err": err, "success": solved}
    n_reach = int(reachable.sum())
    return Row(
        arm=arm.name,
        solver=solver,
        targets=len(targets),
        reachable=n_reach,
        success_rate=100.0 * solved[reachable].mean() if n_reach else float("nan"),
        honest_failures=100.0 * (~solved[~reachable]).mean() if (~reachable).any() else 100.0,
        pos_err_median=_stat(np.nanmedian, err),
        pos_err_max=_stat(np.nanmax, err),
        time_median_ms=float(np.median(ms)),
        time_p95_ms=float(np.percentile(ms, 95)),
        same_branch_as_q0=100.0 * float(np.mean(branch_hits)) if branch_hits else None,
        max_diff_to_closed_form=max(diffs) if diffs else None,
    )


# random arms of the 6R families no bundled arm belongs to: the general spherical wrist,
# three parallel axes without a wrist, and the two searches' families
RANDOM_FAMILIES = ("spherical", "three_parallel_free", "two_parallel", "two_intersecting")


@compiling()  # times compiled code: a first call compiles, not run as Python
def run(
    n: int = 500,
    seed: int = 7,
    spatial: tuple[str, ...] = ("panda",),
    closed_form: tuple[str, ...] = ("ur5", "abb_irb120"),
    general: tuple[str, ...] = ("panda",),
    families: tuple[str, ...] = RANDOM_FAMILIES,
) -> Report:
    """Run every experiment; ``n`` targets each. ``spatial``: arms solved numerically only;
    ``closed_form``: 6R arms whose analytic family is compared with dls and qp;
    ``general``: 7R arms with their first joint locked at 0.3 rad, 6R arms no closed form
    fits (the Panda's joint 7 locked leaves a spherical shoulder: ``spherical_shoulder``),
    where the solver ``solve_all`` takes (``elimination_6r``, the searches behind it) is
    compared with dls and qp the same way;
    ``families``: kinds of random 6R arm (``armik.model.random_arms``) for the families no
    bundled arm belongs to, compared the same way."""
    report = Report()
    rng = np.random.default_rng(seed)

    # The 2-link arm: the closed form against the numeric solvers.
    arm2 = load("planar_2link")
    xy = _planar_targets(arm2, n, rng)
    r = np.linalg.norm(xy, axis=1)
    reachable = (r <= 1.8) & (r >= 0.2)
    # q0 alternates between an elbow-up and an elbow-down seed near the right answer's
    # shoulder angle, so the numeric solvers' branch choice can be read off.
    q0s = [
        np.array([math.atan2(p[1], p[0]), 0.8 if i % 2 == 0 else -0.8]) for i, p in enumerate(xy)
    ]
    closed = []
    for p, q0 in zip(xy, q0s):
        results = arm2.solve_all(p, solver="planar2r")
        same = [x for x in results if x.success and np.sign(x.q[1]) == np.sign(q0[1])]
        closed.append(np.asarray(same[0].q) if same else None)
    report.samples["distance"] = np.minimum(np.abs(r - 1.8), np.abs(r - 0.2)) * np.where(
        reachable, 1, -1
    )
    for solver in ("planar2r", "dls", "qp"):
        # A tight tolerance, so that the joints can be compared with the closed form.
        report.rows.append(
            _measure(
                arm2,
                solver,
                xy,
                q0s,
                reachable,
                f"planar_2link/{solver}",
                report,
                closed,
                tol_position=TIGHT,
            )
        )

    for d in (1e-3, 1e-6, 1e-9, 0.0):
        target = [1.8 - d, 0.0]
        for solver in ("planar2r", "dls", "qp"):
            res = arm2.solve(target, q0=[0.1, 0.3], solver=solver, timeout=BUDGET)
            report.singular.append(
                {
                    "solver": solver,
                    "d": d,
                    "success": res.success,
                    "iterations": res.iterations,
                    "singular": res.singular,
                    "q2": float(res.q[1]),
                }
            )

    # The 3-link planar arm: no closed form registered, the numeric solvers only.
    arm3 = load("planar_3link")
    xy3 = _planar_targets(arm3, n, rng)
    r3 = np.linalg.norm(xy3, axis=1)
    # Links 1.0, 0.8, 0.5: every point within 2.3 m is reachable without limits. The limits
    # of joints 2 and 3 (+-2.8 rad) may cut out points near the shoulder, so targets closer
    # than 0.3 m, whose answer is not known beforehand, are left out of this experiment.
    xy3 = xy3[r3 >= 0.3]
    reach3 = np.linalg.norm(xy3, axis=1) <= 2.3
    q03 = [arm3.middle] * len(xy3)
    for solver in ("dls", "qp"):
        report.rows.append(
            _measure(arm3, solver, xy3, q03, reach3, f"planar_3link/{solver}", report)
        )

    # 7 DOF arms: full poses of random reachable configurations, numeric solvers only.
    for name in spatial:
        arm = load(name)
        poses = [arm.fk(arm.random_q(rng)) for _ in range(n)]
        q0s = [arm.middle] * n
        for solver in ("dls", "qp", "auto"):
            report.rows.append(
                _measure(arm, solver, poses, q0s, np.ones(n, bool), f"{name}/{solver}", report)
            )

    # 6R arms with a closed form: the analytic family against dls and qp.
    for name in closed_form:
        _closed_form_arm(load(name), n, rng, report)
    for name in general:
        arm = load(name)
        locked = arm.with_locked({arm.joint_names[0]: 0.3})
        _closed_form_arm(locked, n, rng, report, label=f"{name} (joint 1 locked)")
    for kind in families:
        arm = load_string(random_urdf(kind, rng), base="world", tip="tool")
        _closed_form_arm(arm, n, rng, report, label=f"random {kind} arm")
    return report


def _wrapped(a: np.ndarray) -> np.ndarray:
    return np.abs(np.arctan2(np.sin(a), np.cos(a)))


def _closed_form_arm(
    arm: Arm, n: int, rng: np.random.Generator, report: Report, label: str | None = None
) -> None:
    """Targets from random configurations; q0 is the generating configuration disturbed by
    0.4 rad (normal, per joint), so "q0's branch" is the closed form's answer nearest q0.
    A numeric answer lands on it when it equals it modulo 2 pi (1e-4 rad); its distance to
    the nearest analytic branch is the largest joint difference modulo 2 pi (so a numeric
    answer the analytic solver did not find shows as a large distance). ``label``: the
    rows' arm name (the arm's own by default)."""
    name = label or arm.name
    kin = arm.kinematics
    family = registry.choose("auto", kin, parse_target(arm.fk(arm.middle), kin), every=True).name
    qs = [arm.random_q(rng) for _ in range(n)]
    poses = [arm.fk(q) for q in qs]
    q0s = [np.clip(q + rng.normal(0.0, 0.4, arm.dof), arm.lower, arm.upper) for q in qs]
    best = [arm.solve(T, q0=q0, solver=family) for T, q0 in zip(poses, q0s)]
    branches = [[r.q for r in arm.solve_all(T, solver=family) if r.success] for T in poses]
    for solver in (family, "dls", "qp"):
        times, errors, successes, hits, dists = [], [], [], [], []
        for i, (T, q0) in enumerate(zip(poses, q0s)):
            t = time.perf_counter()
            r = arm.solve(T, q0=q0, solver=solver, timeout=BUDGET, seed=i)
            times.append(time.perf_counter() - t)
            successes.append(r.success)
            if not r.success:
                continue
            errors.append(r.position_error)
            if best[i].success:
                hits.append(_wrapped(r.q - best[i].q).max() < 1e-4)
            if branches[i]:
                dists.append(min(_wrapped(r.q - b).max() for b in branches[i]))
        row = Row.every_target_reachable(
            name,
            solver,
            successes,
            times,
            errors,
            same_branch_as_q0=100.0 * float(np.mean(hits)) if hits else None,
            max_diff_to_closed_form=max(dists) if dists else None,
        )
        report.samples[f"{name}/{solver}"] = {
            "time_ms": np.array(times) * 1e3,
            "pos_err": np.array(errors) if errors else np.array([np.nan]),
            "success": np.array(successes),
        }
        report.rows.append(row)
    report.rows.append(_solve_all_row(arm, family, poses, q0s, name))
    peer = _eaik_row(arm, qs, report.notes)
    if peer is not None:
        report.rows.append(peer)


def _solve_all_row(arm: Arm, family: str, poses: list, q0s: list, name: str) -> Row:
    """``solve_all`` with the closed form: every branch, each verified; success when one
    is, errors of the best."""
    times, ok, errors = [], [], []
    for T, q0 in zip(poses, q0s):
        t = time.perf_counter()
        results = arm.solve_all(T, q0=q0, solver=family)
        times.append(time.perf_counter() - t)
        ok.append(results[0].success)
        errors.append(results[0].position_error)
    return Row.every_target_reachable(name, f"{family} (solve_all)", ok, times, errors)


def _eaik(arm: Arm, notes: list[str]):
    """EAIK's model of ``arm`` (``armik.tools.peers``: its decomposition and its FK checked
    against armik's), None when EAIK does not apply or is not installed (then said once in
    ``notes``, with what to install: an empty column alone does not say why)."""
    try:
        return EAIKPeer(arm, tol=1e-6).robot
    except PeerMissing as exc:
        if f"eaik not timed: {exc}" not in notes:
            notes.append(f"eaik not timed: {exc}")
        return None
    except PeerUnavailable:
        return None


def _eaik_row(arm: Arm, qs: list, notes: list[str]) -> Row | None:
    """EAIK (closed form, C++ through Python bindings) on the same configurations, all
    solutions per call, timed in the same run; None when it is not installed or does not
    apply. Its success: one of its solutions reproduces the pose by its own
    forward kinematics within 1e-6."""
    robot = _eaik(arm, notes)
    if robot is None:
        return None
    times, ok, errors = [], [], []
    for q in qs:
        T = robot.fwdKin(np.asarray(q))
        t = time.perf_counter()
        sol = robot.IK(T)
        times.append(time.perf_counter() - t)
        errs = [np.abs(robot.fwdKin(x)[:3, 3] - T[:3, 3]).max() for x in sol.Q]
        ok.append(bool(errs) and min(errs) < 1e-6)
        if errs:
            errors.append(min(errs))
    return Row.every_target_reachable(arm.name, "eaik (peer)", ok, times, errors)


@compiling()  # times compiled code: a first call compiles, not run as Python
def speed(
    names: tuple[str, ...] = ("ur5", "abb_irb120"),
    n: int = 500,
    seed: int = 7,
    notes: list[str] | None = None,
) -> list[dict]:
    """Median times (us) of the closed form alone (the compiled kernel and its ranking, as
    ``solve`` runs it, before verification), of ``solve`` and
    ``solve_all`` with it (verification included) and of EAIK's all-solutions ``IK`` (when
    installed; else said in ``notes``), measured in one loop, interleaved target by target
    so that machine load hits them alike."""
    notes = [] if notes is None else notes
    rng = np.random.default_rng(seed)
    rows = []
    for name in names:
        arm = load(name)
        kin = arm.kinematics
        family = registry.choose(
            "auto", kin, parse_target(arm.fk(arm.middle), kin), every=True
        ).name
        qs = [arm.random_q(rng) for _ in range(n)]
        poses = [arm.fk(q) for q in qs]
        peer = _eaik(arm, notes)
        mats = [peer.fwdKin(np.asarray(q)) for q in qs] if peer is not None else []
        opts = SolverSettings()
        # the closed form's prepared runner (what a prepared solve calls): compiled kernel
        # and ranking, no verification
        prepare = registry.get(family).prepare_pose
        if prepare is None:
            raise TypeError(f"{name}'s solver {family!r} has no prepared runner to time")
        run_pose = prepare(kin, opts, False)
        if run_pose is None:
            raise TypeError(f"{name}'s solver {family!r} declines a plain pose to time")
        mats_armik = [T.homogeneous for T in poses]
        for T in poses[:20]:  # warm up: compiled kernels loaded, caches filled
            arm.solve(T, solver=family)
            arm.solve_all(T, solver=family)
        t_run, t_one, t_all, t_peer, ok = [], [], [], [], 0
        for i, T in enumerate(poses):
            t = time.perf_counter()
            run_pose(mats_armik[i], arm.middle, 0)
            t_run.append(time.perf_counter() - t)
            t = time.perf_counter()
            r = arm.solve(T, solver=family)
            t_one.append(time.perf_counter() - t)
            t = time.perf_counter()
            arm.solve_all(T, solver=family)
            t_all.append(time.perf_counter() - t)
            if peer is not None:
                t = time.perf_counter()
                peer.IK(mats[i])
                t_peer.append(time.perf_counter() - t)
            ok += r.success
        us = [1e6 * float(np.median(t)) if t else None for t in (t_one, t_all, t_peer, t_run)]
        rows.append(
            {
                "arm": name,
                "solver": family,
                "targets": n,
                "solved": ok,
                "solve_us": us[0],
                "solve_all_us": us[1],
                "eaik_us": us[2],
                "closed_form_us": us[3],
            }
        )
    return rows


def speed_table(rows: list[dict]) -> str:
    lines = [
        "| arm | solver | solved | closed form alone (us) | solve (us) | solve_all (us) | "
        "EAIK all solutions (us) | solve / EAIK | solve_all / EAIK |",
        "|" + "---|" * 9,
    ]
    for r in rows:
        e = r["eaik_us"]

        def ratio(x, e=e):
            return "-" if e is None else f"{x / e:.2f}"

        lines.append(
            f"| {r['arm']} | {r['solver']} | {r['solved']}/{r['targets']} | "
            f"{r['closed_form_us']:.1f} | {r['solve_us']:.1f} | "
            f"{r['solve_all_us']:.1f} | {'-' if e is None else f'{e:.1f}'} | "
            f"{ratio(r['solve_us'])} | {ratio(r['solve_all_us'])} |"
        )
    lines.append(
        "(medians, interleaved target by target; solve and solve_all include parsing and "
        "verification; 'closed form alone' is the prepared solver's compiled call for one "
        "4x4 pose (every solution, ranked nearest q0) and its Python wrapper, before "
        "verification)"
    )
    return "\n".join(lines)


__all__ = ["Report", "Row", "run", "speed", "speed_table"]
