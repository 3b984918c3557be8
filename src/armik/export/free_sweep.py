"""The sweep over a free joint in ``N_ik.c`` (``solver_file.Rows.sweep``): the rows at the
middle of the limits, else at the free joint's other values as the family's kernel sweeps
it, the first that gives a verified row kept; a family that settles its rows
(``Rows.settle``) settles the rows of the value chosen."""

from __future__ import annotations

ROWS = "    n = sweep(R, p, @HELD_ARG@W, C, S, key, &taken);"

# the rows of a family with free joints (``Rows.sweep``): at the middle of the limits, else
# at the first of the free joint's other values that gives a verified row, as
# ``spherical_wrist.kernel`` and ``three_parallel.kernel`` sweep it
SWEEP = """
/* The first free joint's index in the order the closed form sweeps them. */
static int swept_joint(int mask)
{
@ORDER@
}

/* The rows at the middle of the limits, judged; where a joint is free there and none is
   verified, the rows at the free joint's other values (FREE_SWEEP over a turn within its
   limits, nearest the middle first: +step, -step, +2 step, ...), the first that gives a
   verified row kept. Returns the number of rows, judged (bit r of *taken: row r refused). */
static int sweep(mat3 R, vec3 p, @HELD_PARAM@double W[][DOF], double C[][DOF],
                 double S[][DOF], double *key, int *taken)
{
    double seed[DOF], step = 2.0 * IK_PI / FREE_SWEEP, lo, hi, value;
    int mask = 0, unused = 0, n, m, j, k;
    n = rows(R, p, @HELD_ARG@MID, &mask, W, C, S);
    if (judge(n, W, C, S, R, p, key, taken) > 0 || mask == 0 || n == 0) return n;
    j = swept_joint(mask);
    lo = LO[j] > MID[j] - IK_PI ? LO[j] : MID[j] - IK_PI;
    hi = HI[j] < MID[j] + IK_PI ? HI[j] : MID[j] + IK_PI;
    for (k = 0; k < DOF; k++) seed[k] = MID[k];
    for (k = 1; k <= FREE_SWEEP; k++) {
        value = MID[j] + (k % 2 ? step * ((k + 1) / 2) : -step * (k / 2));
        if (!(lo <= value && value <= hi)) continue;
        seed[j] = value;
        m = rows(R, p, @HELD_ARG@seed, &unused, W, C, S);
        *taken = 0;
        if (judge(m, W, C, S, R, p, key, taken) > 0) return m;
    }
    return 0;  /* no value gives a verified row */
}
"""


# ``SWEEP`` where the family settles its rows once the free joints' values are chosen
# (``Rows.settle``), as its kernel's rows are settled after its sweep: at the chosen
# value, or at the middle where no value gives a verified row
SETTLED = """
/* Rows 0 to n - 1 once the free joints' values are chosen: @SETTLE@'s pass, judged again. */
static int settled(int n, double W[][DOF], double C[][DOF], double S[][DOF], mat3 R, vec3 p,
                   double *key, int *taken)
{
    @SETTLE@(W, C, S, n);
    *taken = 0;
    judge(n, W, C, S, R, p, key, taken);
    return n;
}
"""


def _settled(sweep: str, settle: str) -> str:
    """``SWEEP`` with each set of rows it returns passed through ``settle`` (``SETTLED``)."""
    call = "settled({}, W, C, S, R, p, key, taken)"
    replaced = {
        "|| n == 0) return n;": f"|| n == 0)\n        return {call.format('n')};",
        "> 0) return m;": f"> 0) return {call.format('m')};",
        "    return 0;  /* no value gives a verified row */": (
            "    n = rows(R, p, @HELD_ARG@MID, &mask, W, C, S);  /* none does: the middle's */\n"
            f"    return {call.format('n')};"
        ),
    }
    for old, new in replaced.items():
        assert sweep.count(old) == 1, old  # the text this module writes
        sweep = sweep.replace(old, new)
    return SETTLED.replace("@SETTLE@", settle) + sweep


def _order(order: tuple[int, ...]) -> str:
    """``SWEEP``'s function choosing the joint to sweep from the free joints' bits."""
    *first, last = order
    lines = [f"    if (mask & (1 << {j})) return {j};" for j in first]
    return "\n".join([*lines, f"    return {last};"])


def source(order: tuple[int, ...], settle: str = "") -> str:
    """The C of ``sweep`` over the free joints ``order`` (in the order the family's kernel
    sweeps them), its rows passed through the C function ``settle`` when named."""
    sweep = SWEEP.replace("@ORDER@", _order(order))
    return _settled(sweep, settle) if settle else sweep
