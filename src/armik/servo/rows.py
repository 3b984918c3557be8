"""The servo's step with collision rows ``C dq >= b`` besides the joints' boxes, compiled.

Each pair's row comes as its velocity damper (``armik.servo.collisions``: C dq >= -RATE dt
(d - margin)), and gives two rows here. Joint i braking from v_i at its acceleration limit
a_i turns v_i^2 / (2 a_i) on, which closes the pair by at most |C_i| of it (however the
witness points turn: a pair's normal swings as its nearest faces change), so the pair's
worst braking distance at the last tick's velocity w is R = sum_i |C_i| w_i^2 / (2 a_i).
With g = d - margin:

- the damper keeps the pair R off the margin, at most its gap: C dq >= -RATE dt (g -
  min(R, max(g, 0))), so that a pair sliding by at speed stays far enough off to go on at
  that speed rather than close in until no joint may move. Inside the margin (g < 0) it
  asks the pair out by at most ``sum_i |C_i| a_i dt^2 / 2``, half what its joints give a tick
  from rest: asked out by RATE dt |g| (TALOS's torso and upper arms, 14 mm apart at a 3
  cm margin: 0.3 mm a tick, 50 rad of its joints), pairs inside it asked what no step
  could give, their stiff penalties outweighing every braking row, and the pair came
  1.8 mm nearer;
- its braking: the pair closes this tick by no more than leaves room to stop,
  ``g + C v dt >= sum_i |C_i| v_i^2 / (2 a_i)``, the right side bounded over the
  acceleration box ``|v_i - w_i| <= a_i dt`` by its chord (exact at both ends), a row
  linear in v = dq / dt:

      sum_i (C_i - |C_i| w_i / (a_i dt)) dq_i >= sum_i |C_i| a_i dt^2 / 2 - R - max(g, R)

  A step that meets it leaves the next tick room for every joint to brake by a_i dt (the
  chord's end), which meets it again. Where the pair is nearer than R (it came among the
  rows too late), the row asks only that g - R not fall, which a step braking every joint
  always meets. The damper alone asked the pair to slow in proportion to its gap, faster
  than the joints could near the margin: TALOS's shoulder turning at 2 rad/s beside its
  torso, the share of one joint in its closing changing sign from one tick to the next,
  passed 0.55 mm inside it, every joint at its acceleration limit.
- inside the margin (by ``DEPTH`` in full, in proportion nearer it) the braking row also
  counts each joint's lever L_i (``|J_p2 - J_p1|``'s column: how fast the joint parts the
  witness points, which bounds how fast it turns C_i) growing over the braking turn s_i =
  v_i^2 / (2 a_i): ``L_i (s_i(v)^2 - s_i(w)^2) / 2`` more, its growth beyond the braking
  turn at this tick's velocity w_i, bounded over the acceleration box by a chord
  (``bent``; not the full ``L_i s_i^2 / 2``, which the tests below did not need). Counted
  with this tick's |C_i| alone, a shoulder turning past where the pair is widest along it
  (its C_i through zero) grew it as it braked, and TALOS's torso and right upper arm,
  14.1 mm apart inside a 3 cm margin, came 37 um nearer under targets wandering at random.

The box QP's step (``tick``) is kept where it meets every row. Otherwise the most violated
row (by its shortfall over its norm; a row of zeros, a pair no joint moves, never) joins
the step as a stiff quadratic penalty ``WEIGHT |C_r dq - b_r|^2 / |C_r|^2`` (a unit row: a
short lever's row had given way by 1e-5 m a tick; relative to
the damped normal matrix's Frobenius norm, a bound on its largest eigenvalue) and the box
QP is solved again, one row a pass: the boxes stay hard (the joint, velocity, acceleration
and braking limits always hold), a row holds to about 1 / WEIGHT of its size where the
boxes leave room for it. The braking row of a pair inside the margin is held ``FIRM`` times more
firmly still: a step braking every joint meets every braking row at once, and weighed
alike against the others' rows, TALOS's torso and right upper arm, 14.1 mm apart inside a
3 cm margin, its hands sent at each other, came 2.1 um nearer.
"""

from __future__ import annotations

import math

from numba import njit

from armik.kernel.linalg import cholesky_factor, cholesky_substitute
from armik.kernel.step import active_set
from armik.servo.box import SAFE
from armik.servo.box_qp import nearest_in_box
from armik.servo.layout import RATE

WEIGHT = 1e6
PASSES = 16  # rows added at most (two a pair: its damper, its braking)
SHORT = 1e-12  # rad: a row short by less is met
FIRM = 1e2  # a braking row inside the margin held this much more firmly than the others
DEPTH = 1e-3  # m inside its margin where a pair's braking counts its levers' growth in full


@njit(cache=True, nogil=True, inline="always")
def _inside(b, p, dt):
    """How far pair p is inside its margin, as a share of ``DEPTH`` (0 outside, at most 1)."""
    return min(max(b[p] / (RATE * dt * DEPTH), 0.0), 1.0)  # (b = -RATE dt (d - margin))


@njit(cache=True, nogil=True, inline="always")
def _coefficient(C, L, b, r, K, i, w, a, dt):
    """Row r's coefficient of dq_i: pair r's damper (r < K), else pair r - K's braking
    (w: the last tick's velocity, a: the acceleration limits kept to ``SAFE`` inside; L:
    the levers, for a pair inside its margin)."""
    if r < K:
        return C[r, i]
    p = r - K
    c = C[p, i]
    ai = a[i] * (1.0 - SAFE)
    h = ai * dt
    bend = _inside(b, p, dt) * L[p, i] * (w[i] ** 3 + w[i] * h * h) / (2.0 * ai * ai * dt)
    return c - abs(c) * w[i] / (ai * dt) - bend


@njit(cache=True, nogil=True, inline="always")
def _bound(C, L, b, r, K, w, a, dt):
    """Row r's bound: pair r's damper's (r < K), else pair r - K's braking's."""
    p = r if r < K else r - K
    gap = -b[p] / (RATE * dt)  # m: d - margin, from the damper's bound
    reach = 0.0  # m: the pair's worst braking distance at w
    ends = 0.0  # the chord's excess at both ends, a dt^2 / 2 a joint
    for i in range(C.shape[1]):
        ai = a[i] * (1.0 - SAFE)
        reach += abs(C[p, i]) * 0.5 * w[i] * w[i] / ai
        ends += abs(C[p, i]) * 0.5 * ai * dt * dt
    if r < K:  # the damper toward the margin kept that far off
        if gap < 0.0:  # inside the margin: out by half what its joints give a tick
            return min(-RATE * dt * gap, ends)
        return -RATE * dt * (gap - min(reach, max(gap, 0.0)))
    inside = _inside(b, p, dt)
    if inside > 0.0:  # its levers' growth over the braking turn: the chord's, at w
        for i in range(C.shape[1]):
            ai = a[i] * (1.0 - SAFE)
            h2, w2 = (ai * dt) ** 2, w[i] * w[i]
            bent = 6.0 * w2 * h2 + h2 * h2 - 4.0 * (w2 * w2 + w2 * h2)
            ends += inside * L[p, i] * bent / (8.0 * ai * ai)
    return ends - reach - max(gap, reach)


@njit(cache=True, nogil=True, inline="always")
def _worst(C, L, b, dq, act, w, a, dt):
    """The row most short of its bound (over its norm: the step's distance from it) among
    those not yet added, or -1; a row of zeros (a pair no joint moves) never is."""
    n, K = dq.shape[0], C.shape[0]
    worst, most = -1, SHORT
    for r in range(2 * K):
        if act[r] != 0.0:
            continue
        s = norm2 = 0.0
        for i in range(n):
            c = _coefficient(C, L, b, r, K, i, w, a, dt)
            s += c * dq[i]
            norm2 += c * c
        if norm2 == 0.0:
            continue
        short = (_bound(C, L, b, r, K, w, a, dt) - s) / math.sqrt(norm2)
        if short > most:
            worst, most = r, short
    return worst


@njit(cache=True, nogil=True, no_cfunc_wrapper=True, _nrt=False)  # type: ignore[call-overload]
def with_rows(C, b, L, w, a, dt, Hl, xf, lb, ub, dq, act, Hp, Gi, gp, xp, unit, iscratch, mats,
              vecs):  # fmt: skip
    """dq (in place): the step within the boxes [lb, ub] nearest xf in the metric of the
    damped normal matrix ``Hl``, with the violated rows of ``C dq >= b`` (the dampers) and
    their braking rows (the module docstring; w the last tick's velocity, a the
    acceleration limits, dt the time step) as penalties; returns whether a row was
    added. ``act`` (twice the rows), ``Hp``, ``Gi`` (n x n), ``gp``, ``xp``,
    ``unit`` (n) are scratch, as are ``iscratch`` (4, n) ints, ``mats`` (2, n, n) and
    ``vecs`` (3, n)."""
    n = dq.shape[0]
    top = 0.0
    for i in range(n):
        for j in range(n):
            top += Hl[i, j] * Hl[i, j]
    weight = WEIGHT * math.sqrt(top)
    K = C.shape[0]
    for r in range(2 * K):
        act[r] = 0.0
    added = False
    side, held, sub, free = iscratch[0], iscratch[1], iscratch[2], iscratch[3]
    for _ in range(PASSES):
        r = _worst(C, L, b, dq, act, w, a, dt)
        if r < 0:
            break
        act[r] = 1.0
        added = True
        for i in range(n):  # Hp = Hl + weight sum c c^T; gp = Hl xf + weight sum c b
            for j in range(n):
                Hp[i, j] = Hl[i, j]
        for i in range(n):
            s = 0.0
            for j in range(n):
                s += Hp[i, j] * xf[j]
            gp[i] = s
        for r in range(2 * K):
            if act[r] == 0.0:
                continue
            norm2 = 0.0  # each row as a unit one: held alike however long its levers
            for i in range(n):
                norm2 += _coefficient(C, L, b, r, K, i, w, a, dt) ** 2
            wr = weight / norm2 * (FIRM if r >= K and b[r - K] > 0.0 else 1.0)
            br = _bound(C, L, b, r, K, w, a, dt)
            for i in range(n):
                ci = _coefficient(C, L, b, r, K, i, w, a, dt)
                gp[i] += wr * ci * br
                for j in range(n):
                    Hp[i, j] += wr * ci * _coefficient(C, L, b, r, K, j, w, a, dt)
        for i in range(n):
            free[i] = 1
        if not cholesky_factor(Hp, free, mats[0]):
            break
        for c in range(n):  # Gi = Hp^-1
            for i in range(n):
                unit[i] = 1.0 if i == c else 0.0
            cholesky_substitute(mats[0], unit, free, vecs[0])
            for i in range(n):
                Gi[i, c] = vecs[0, i]
        for i in range(n):
            s = 0.0
            for j in range(n):
                s += Gi[i, j] * gp[j]
            xp[i] = s
        if not active_set(
            Gi, xp, lb, ub, xp, side, held, sub, mats[1], vecs[1], vecs[2], mats[0], dq
        ):  # cycled: the primal method, which cannot
            nearest_in_box(Hp, xp, lb, ub, dq, side, sub, mats[1], vecs[1], vecs[2])
        for i in range(n):
            dq[i] = min(max(dq[i], lb[i]), ub[i])
    return added
