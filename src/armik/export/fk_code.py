"""The forward kinematics of an exported solver as straight-line C: the product of
exponentials over the arm's axis lines at q = 0 (``Axes``), written out term by term with
the arm's numbers in place, so that the terms an axis along a base axis makes zero (most
arms' axes) are not computed at all. ``N_fk`` and the verdict of every row call it.

An entry is a constant (a float) or the name of a C variable; a product with a zero is
dropped, with a one is the other factor. Components below ``NOISE`` (the rounding of a
rotation by pi/2 in a URDF's ``rpy``) count as zero: they move the tip by less than 1e-15 m.
"""

from __future__ import annotations

import re

import numpy as np

from armik.export.c_source import num
from armik.model.geometry import Axes

NOISE = 1e-15
_NAME = re.compile(r"\b[ecs]\d+\b")

Entry = float | str


def _clean(x: float) -> float:
    return 0.0 if abs(x) < NOISE else float(x)


class _Writer:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self.count = 0

    def let(self, terms: list[tuple[Entry, Entry]], constant: float = 0.0) -> Entry:
        """The entry sum(a * b) + constant: a constant when every term is, else a new
        variable (or an existing one, for a single term times one)."""
        text, value = [], constant
        for a, b in terms:
            if isinstance(a, float) and isinstance(b, float):
                value += a * b
            elif a == 0.0 or b == 0.0:
                continue
            elif a == 1.0 or b == 1.0:
                text.append(str(b if a == 1.0 else a))
            elif a == -1.0 or b == -1.0:
                text.append(f"-{b if a == -1.0 else a}")
            else:
                x, y = (a, b) if isinstance(b, float) else (b, a)
                text.append(f"{x} * {num(y) if isinstance(y, float) else y}")
        if not text:
            return _clean(value)
        if value != 0.0:
            text.append(num(value))
        if len(text) == 1 and not text[0].startswith("-") and " " not in text[0]:
            return text[0]
        self.count += 1
        name = f"e{self.count}"
        expr = " + ".join(text).replace("+ -", "- ")
        self.lines.append(f"    const double {name} = {expr};")
        return name


def _rotation(w: _Writer, k: np.ndarray, i: int) -> list[Entry]:
    """rot(k, q[i]) = c I + (1 - c) k k^T + s [k]x, each entry d + a c + b s."""
    x, y, z = (_clean(v) for v in k)
    kk = np.outer([x, y, z], [x, y, z])
    skew = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    out: list[Entry] = []
    for r in range(3):
        for col in range(3):
            d = _clean(kk[r, col])
            a = _clean((1.0 if r == col else 0.0) - kk[r, col])
            b = _clean(skew[r, col])
            out.append(w.let([(a, f"c{i}"), (b, f"s{i}")], d))
    return out


def _times(w: _Writer, A: list[Entry], B: list[Entry]) -> list[Entry]:
    return [
        w.let([(A[3 * r + m], B[3 * m + col]) for m in range(3)])
        for r in range(3)
        for col in range(3)
    ]


def _apply(w: _Writer, A: list[Entry], v: np.ndarray) -> list[Entry]:
    return [w.let([(A[3 * r + m], _clean(v[m])) for m in range(3)]) for r in range(3)]


def _live(lines: list[str], used: str) -> list[str]:
    """The lines whose variable the outputs ``used`` need, directly or through later lines
    (an unused variable is an error under -Wall -Werror)."""
    needed = set(_NAME.findall(used))
    kept = []
    for line in reversed(lines):
        name, expr = line.split("=", 1)
        if name.split()[-1] in needed:
            kept.append(line)
            needed |= set(_NAME.findall(expr))
    return kept[::-1]


def _value(e: Entry) -> str:
    return num(e) if isinstance(e, float) else e


def source(ax: Axes) -> str:
    """``static void fk_cs(const double *c, const double *s, mat3 *R, vec3 *p)``: the tip's
    rotation and position at the joint values whose cosines and sines are c and s; and
    ``fk(q, R, p)``, the same at joint values q (rad)."""
    points = np.asarray(ax.points, dtype=float)
    dof = len(points)
    p = [points[0]] + [points[i] - points[i - 1] for i in range(1, dof)]
    p.append(np.asarray(ax.tip_position, dtype=float) - points[-1])
    w = _Writer()
    for i in range(dof):
        w.lines.append(f"    const double c{i} = c[{i}];")
        w.lines.append(f"    const double s{i} = s[{i}];")
    A = _rotation(w, ax.directions[0], 0)
    x = [_clean(v) for v in p[0]]
    for i in range(dof):
        if i > 0:
            A = _times(w, A, _rotation(w, ax.directions[i], i))
        step = _apply(w, A, p[i + 1])
        x = [w.let([(1.0, a), (1.0, b)]) for a, b in zip(x, step)]
    R = _times(w, A, [_clean(v) for v in np.asarray(ax.tip_rotation).ravel()])
    rows = ", ".join(_value(e) for e in R)
    where = ", ".join(_value(e) for e in x)
    body = "\n".join(_live(w.lines, f"{rows}, {where}"))
    return (
        "/* The tip's rotation and position at the joint values of cosines c and sines s: the\n"
        "   product of exponentials over the axis lines, written out with the arm's numbers. */\n"
        "static void fk_cs(const double *c, const double *s, mat3 *R, vec3 *p)\n{\n"
        f"{body}\n    const mat3 A = {{{{{rows}}}}};\n    const vec3 x = {{{{{where}}}}};\n"
        "    *R = A;\n    *p = x;\n}\n\n"
        "static void fk(const double *q, mat3 *R, vec3 *p)\n{\n"
        f"    double c[{dof}], s[{dof}];\n    int i;\n"
        f"    for (i = 0; i < {dof}; i++) {{\n"
        "        c[i] = cos(q[i]);\n        s[i] = sin(q[i]);\n    }\n"
        "    fk_cs(c, s, R, p);\n}\n"
    )
