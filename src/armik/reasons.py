"""Every reason text a result can carry, written once: the verdicts of single, prepared and
batch solves and the solvers' own claims all word their reasons here."""

from __future__ import annotations


def measured(pos: float, ori: float | None, tol_p: float, tol_r: float) -> str:
    """'position error 1e-07 m (tol 1e-05), orientation error ...': a measure in words
    (``ori`` None or NaN, as batches hold it: not measured)."""
    text = f"position error {pos:.3g} m{_tol_text(tol_p)}"
    if ori is None or ori != ori:
        return text
    return f"{text}, orientation error {ori:.3g} rad{_tol_text(tol_r)}"


def outside_region(measured_text: str) -> str:
    """A measure of a target with a region (bounds, a cone): its errors are the distances
    outside it."""
    return f"outside the region: {measured_text}"


def verified(claim_reason: str | None, measured_text: str) -> str:
    """The reason of a success: the solver's own words, then the measure."""
    reason = f"verified by forward kinematics: {measured_text}"
    return f"{claim_reason}; {reason}" if claim_reason else reason


def outside_limits(violations: list[str]) -> str:
    """A claimed answer that reaches the target outside the joint limits (``violations``:
    ``ArmModel.limit_violations``)."""
    return "outside the joint limits: " + "; ".join(violations)


def check_failed(measured_text: str) -> str:
    """A claimed answer within the limits that Pinocchio's FK does not confirm."""
    return f"forward-kinematics check failed: {measured_text}"


def beyond_reach(distance: float, reach: float) -> str:
    """Why a target ``distance`` m from the first joint is out of reach (the proof a
    search's miss needs)."""
    return (
        f"target is {distance:.4g} m from the first joint, beyond the arm's reach of at "
        f"most {reach:.4g} m"
    )


def unreachable(distance: float, reach: float) -> str:
    """A target beyond the reach bound (m), refused before any iteration."""
    return f"{beyond_reach(distance, reach)}; q is the seed, unchanged"


def budget(timeout: float, iteration_budget: int | None, restarts: str) -> str:
    """The budget a numeric solve ran out of, in words (``restarts``: "12 restarts", or
    "at most 5 restarts" where the count is not kept)."""
    if iteration_budget is not None:
        return f"the iteration budget ({iteration_budget} iterations, {restarts})"
    return f"the time budget ({timeout:g} s of CPU time, {restarts})"


def not_converged(why: str, best: str) -> str:
    """No answer within ``why`` (the budget or the restart limit, in words); ``best``: the
    errors of the best attempt."""
    return f"no solution within {why}; best found: {best}; the target may be out of reach"


def search_missed(solver: str, reason: str) -> str:
    """What "auto" says when the search it chose for every solution verified none and it
    went on to one answer from another solver (``reason``: the search's own)."""
    return f"{solver} (a search) verified no solution ({reason})"


def jump(why: str, answer: str, measured_text: str) -> str:
    """A waypoint reached only by a move larger than ``max_joint_step`` (``discontinuous``):
    ``why`` in words, ``answer`` what q is, ``measured_text`` its measure."""
    return f"reachable only by a jump: {why}; q is {answer}, verified: {measured_text}"


def moved(joint: str, size: float, unit: str, start: str, step: float) -> str:
    """A step beside its bound: 'moves panda_joint5 by 1.44 rad from the previous
    waypoint's answer (max_joint_step 0.3)'."""
    return f"moves {joint} by {size:.3g} {unit} from {start} (max_joint_step {step:g})"


def _pair_text(pair: tuple[str, str] | None, distance: float) -> str:
    if pair is None:
        return "no pair to check"
    gap = f"{distance:.3g} m apart" if distance >= 0 else f"overlapping by {-distance:.3g} m"
    return f"{pair[0]} and {pair[1]} {gap}"


def in_collision(pair: tuple[str, str] | None, distance: float, margin: float) -> str:
    """A verified answer whose closest checked pair is nearer than ``margin`` (m)."""
    return f"in collision: {_pair_text(pair, distance)} (margin {margin:g} m)"


def clear(pair: tuple[str, str] | None, distance: float, margin: float) -> str:
    """What a collision-checked success adds to its reason: the closest pair."""
    return f"collision-free: closest {_pair_text(pair, distance)} (margin {margin:g} m)"


def _tol_text(tol: float) -> str:
    """' (tol 1e-05)': ``measured``'s tolerance text, formatted once per tolerance."""
    text = _TOL_TEXT.get(tol)
    if text is None:
        text = f" (tol {tol:g})"
        if len(_TOL_TEXT) > 64:
            _TOL_TEXT.clear()
        _TOL_TEXT[tol] = text
    return text


_TOL_TEXT: dict[float, str] = {}
