"""A target measured plainly (no weights, no region, no aim) beyond what an arm's structure
allows, refused before the kernel runs: its rotation beyond every one the tip takes
(``orientations``: a gantry, a SCARA, a planar arm), its position beyond every one a chain
of prismatic joints reaches (``slides``) or beyond the heights along parallel turning axes
(``heights``: a planar arm's plane, a SCARA's quill travel). A target within reach first
passes cheap measures (``orientations.near``, ``slides.near``, ``heights.near``: a few
products with what is kept per arm; on plain floats for one target, vectorised over a
batch), and only one they do not pass is measured exactly, so that a solve on such an arm
pays a few microseconds for it where the target is reachable."""

from __future__ import annotations

import math

import numpy as np

from armik.model.arm_model import ArmModel
from armik.model.derived import Derived
from armik.problem.settings import SolverSettings
from armik.solvers.numeric import heights, orientations, slides

REACH_SLACK = 9  # in ``problem.pack_settings``' floats


def _bounded(arm: ArmModel) -> bool:
    return orientations.FAMILY(arm) is not None or slides.SLIDES(arm) is not None


# whether ``arm``'s structure bounds its targets at all (a family of rotations, or slides
# first): the solves of any other arm never call ``beyond``
BOUNDED: Derived[bool] = Derived("a structure that bounds the targets", _bounded)


def beyond(
    arm: ArmModel, R_t: np.ndarray | None, p_t: np.ndarray, opts: SolverSettings, sf: np.ndarray
) -> str | None:
    """Why a target measured plainly is beyond what ``arm``'s structure allows (an arm
    ``BOUNDED``): its rotation ``R_t`` (None: not measured)
    beyond the tip's (``orientations.refused``), or its position ``p_t`` beyond a gantry's
    (``slides.refused``) or its height beyond the tip's (``heights.refused``); for a target
    within the reach bound only (beyond it the kernel
    refuses it by its distance, as ``solve.far`` does); else None."""
    family, near = orientations.FAMILY(arm), slides.NEAR(arm)
    turned = True
    if R_t is not None and family is not None:
        turned = orientations.near_one(family, R_t, opts.tol_orientation)
    placed = near is None or slides.near_one(near, p_t, opts.tol_position)
    above = arm._derived.get(heights.HEIGHTS, _UNBUILT)
    if above is _UNBUILT:
        above = heights.HEIGHTS(arm)
    if above is not None and placed:
        placed = heights.height(above, p_t) <= 0.5 * opts.tol_position
    if turned and placed:
        return None
    return _exactly(arm, R_t, p_t, opts, sf, turned, placed)


def refusals(
    arm: ArmModel, R_t: np.ndarray | None, p_t: np.ndarray, opts: SolverSettings, sf: np.ndarray
) -> dict[int, str]:
    """{row: why} of a batch's targets (rotations ``R_t``, None: not measured; positions
    ``p_t``) that ``beyond`` refuses: the cheap measures over every row at once, then each
    row they do not pass alone."""
    turned, placed = _passed(arm, R_t, p_t, opts)
    found = {}
    for i in np.flatnonzero(~(turned & placed)).tolist():
        R = None if R_t is None else R_t[i]
        why = _exactly(arm, R, p_t[i], opts, sf, turned[i], placed[i])
        if why is not None:
            found[i] = why
    return found


def _passed(
    arm: ArmModel, R_t: np.ndarray | None, P: np.ndarray, opts: SolverSettings
) -> tuple[np.ndarray, np.ndarray]:
    """Where the rows' rotations (``R_t``, (m, 3, 3); None: not measured, every row) and
    positions (``P``, (m, 3)) pass the cheap measures."""
    every = np.ones(len(P), dtype=bool)
    family = orientations.FAMILY(arm)
    turned = every
    if R_t is not None and family is not None:
        turned = orientations.near(family, R_t, opts.tol_orientation)
    placed = every if slides.NEAR(arm) is None else slides.near(arm, P, opts.tol_position)
    if heights.HEIGHTS(arm) is not None:
        placed = placed & heights.near(arm, P, opts.tol_position)
    return turned, placed


_UNBUILT = object()  # an arm's ``heights.HEIGHTS`` not built yet (read as a dict: no call)


def _exactly(
    arm: ArmModel,
    R_t: np.ndarray | None,
    p_t: np.ndarray,
    opts: SolverSettings,
    sf: np.ndarray,
    turned: bool,
    placed: bool,
) -> str | None:
    """``beyond``, the measures passed (``turned``: the rotation's, ``placed``: the
    position's) skipped."""
    why = None
    if R_t is not None and not turned:
        why = orientations.refused(arm, R_t, opts)
    if why is None and not placed:
        why = slides.refused(arm, p_t, opts) or heights.refused(arm, p_t, opts)
    if why is None:
        return None
    ch = arm.kernel_chain.chain
    if math.dist(np.asarray(p_t).tolist(), ch.origin.tolist()) > ch.reach + sf[REACH_SLACK]:
        return None
    return why
