"""Every reason text the pipeline gives a result, written once: the verdicts of single,
prepared and batch solves, collisions, paths, held joints, task lists and several tips
word their reasons here; solvers word their own claims, in these words where they share
them (a target beyond reach, a budget run out)."""

from __future__ import annotations

from typing import NamedTuple


def measured(pos: float | None, ori: float | None, tol_p: float, tol_r: float) -> str:
    """'position error 1e-07 m (tol 1e-05), orientation error ...': a measure in words
    (``pos`` None, ``ori`` None or NaN, as batches hold it: not measured, that part free)."""
    said = [] if pos is None else [f"position error {pos:.3g} m{_tol_text(tol_p)}"]
    if ori is not None and ori == ori:
        said.append(f"orientation error {ori:.3g} rad{_tol_text(tol_r)}")
    return ", ".join(said) or "no component measured (every one free)"


def outside_region(measured_text: str) -> str:
    """A measure of a target with a region (bounds, a cone): its errors are the distances
    outside it."""
    return f"outside the region: {measured_text}"


class Cone(NamedTuple):
    """An aim as its words name it: the cone's angle (rad) and what the tip's axis points
    along, the line to a point (``at_point``: a look-at) or a direction."""

    within: float
    at_point: bool = False

    @property
    def sight(self) -> str:
        return "the line to the point" if self.at_point else "its direction"


def region(
    pos: float | None, ori: float | None, tol_p: float, tol_r: float, cone: Cone | None
) -> str:
    """A measure of a target with a region (bounds, an aim): its errors are the distances
    outside it, within the tolerances "inside the region", else "outside" (NaN: not
    placed; ``pos`` None: the position free, not said). With an aim (``cone``) the
    orientation error is the tip axis' angle outside its cone, said in the aim's terms
    (``_axis``); an aim whose position is free is no region: its axis alone is said."""
    inside = (pos is None or pos <= tol_p) and (ori is None or ori <= tol_r)  # NaN: False
    where = "inside" if inside else "outside"
    if cone is None or ori is None or ori != ori:
        return f"{where} the region: {measured(pos, ori, tol_p, tol_r)}"
    if pos is None:
        return _axis(ori, cone, tol_r)
    return f"{where} the region: {measured(pos, None, tol_p, tol_r)}, {_axis(ori, cone, tol_r)}"


def _axis(ori: float, cone: Cone, tol_r: float) -> str:
    """The tip's axis ``ori`` rad outside its cone, in words: "within its cone of 0.1 rad
    around its direction", or its angle from the direction (the line to the point) where
    that is the measure: outside the cone, or a cone 0 wide."""
    if ori <= tol_r and cone.within > 0.0:
        return f"the tip's axis within its cone of {cone.within:.3g} rad around {cone.sight}"
    return f"{_off_axis(ori, cone)}{_tol_text(tol_r)}"


def _off_axis(ori: float, cone: Cone) -> str:
    """The tip's axis ``ori`` rad outside its ``cone``, in words: its angle from the
    direction (the line to the point)."""
    outside = f", outside its cone of {cone.within:.3g} rad" if cone.within > 0 else ""
    return f"the tip's axis {ori + cone.within:.3g} rad from {cone.sight}{outside}"


def best_outside(pos: float | None, ori: float | None, cone: Cone | None) -> str:
    """A failure's best attempt against a region: the distances outside it, each part
    where measured (None: free); with an aim (``cone``) the tip axis' angle, an aim whose
    position is free no region."""
    if cone is None or ori is None:
        return outside_region(best_errors(pos, ori))
    if ori > 0:
        axis = _off_axis(ori, cone)
    else:
        axis = f"the tip's axis within its cone of {cone.within:.3g} rad around {cone.sight}"
    return axis if pos is None else outside_region(f"position error {pos:.3g} m, {axis}")


CONVERGED = "converged after {} restart(s)"  # a numeric solver's claim: its restarts


_VERIFIED = "verified by forward kinematics: "


def verified(claim_reason: str | None, measured_text: str) -> str:
    """The reason of a success: the solver's own words, then the measure."""
    reason = _VERIFIED + measured_text
    return f"{claim_reason}; {reason}" if claim_reason else reason


def claim_of(reason: str) -> str:
    """A success's reason (``verified``) without its measure: the solver's own words,
    for a verdict that measures the answer again (a held joint's whole arm)."""
    head, _, _ = reason.partition(_VERIFIED)
    return head.removesuffix("; ")


def outside_limits(violations: list[str]) -> str:
    """A claimed answer that reaches the target outside the joint limits (``violations``:
    ``ArmModel.limit_violations``)."""
    return "outside the joint limits: " + "; ".join(violations)


def check_failed(measured_text: str) -> str:
    """A claimed answer within the limits that Pinocchio's FK does not confirm."""
    return f"forward-kinematics check failed: {measured_text}"


def beyond_reach(distance: float, reach: float) -> str:
    """Why a target ``distance`` m from the first joint is out of reach (the proof a
    search's miss needs); by how much where the two read alike to 4 digits."""
    return (
        f"target is {distance:.4g} m from the first joint, beyond the arm's reach of at "
        f"most {reach:.4g} m{by_how_much(distance, reach, 4)}"
    )


def by_how_much(a: float, b: float, digits: int) -> str:
    """' (by 2e-06 m)': how far apart two lengths are where they read alike to ``digits``
    digits (a comparison of them would read false), else nothing."""
    alike = f"{a:.{digits}g}" == f"{b:.{digits}g}"
    return f" (by {abs(a - b):.3g} m)" if alike else ""


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


def best_errors(pos: float | None, ori: float | None) -> str:
    """The errors of a failure's best attempt, each only where the task measures it (None:
    that part not asked, where a 0 would read as reached)."""
    said = [] if pos is None else [f"position error {pos:.3g} m"]
    return ", ".join(said + ([] if ori is None else [f"orientation error {ori:.3g} rad"]))


def resting_on_limits(reason: str, joints: list[str]) -> str:
    """A failure's ``reason`` with the joints its best configuration rests on a limit of
    (``constraints.limits.on_limits``), where any does."""
    return f"{reason}; the best found rests on {', '.join(joints)}" if joints else reason


def search_missed(search: str, search_reason: str, solver: str, reason: str) -> str:
    """What "auto" says when the search it chose for every solution verified none and it
    went on to one answer from ``solver`` (each with its own reason)."""
    return (
        f"{search} (a search, not a proof) found no solution it could verify "
        f"({search_reason}); {solver}: {reason}"
    )


def claimed(status: str, measured_text: str) -> str:
    """A solver's claim other than converged, where it gave no words (a batch's row)."""
    return f"{status}: {measured_text}"


SELF_MOTION = "moved along the self-motion"  # a 7-joint answer moved for a preference
SLID = "slid out of contact"  # a colliding answer moved off its contact on a path


def held(joint: str, value: float, solver: str, reason: str, asked_for: str | None = None) -> str:
    """A 7-joint arm's answer with ``joint`` held at ``value`` (rad), the rest by ``solver``
    (``asked_for``: the whole arm's closed form asked for, which does not hold that joint)."""
    instead = "" if asked_for is None else f" ({asked_for} solves all seven, not six)"
    return f"joint {joint!r} held at {value:.6g} rad; the other six by {solver}{instead}: {reason}"


def off_hold(joint: str, at: float, value: float) -> str:
    """An answer whose held ``joint`` is not at its ``value``."""
    return f"joint {joint!r} at {at:.6g}, held at {value:.6g}"


def and_held(reason: str, joint: str, value: float) -> str:
    """``reason`` of a success with ``joint`` held at ``value``."""
    return f"{reason}; joint {joint!r} held at {value:.6g}"


def tasks_hold(tol_p: float, tol_r: float, restarts: int) -> str:
    """A task list's answer: every task within its region or tolerance."""
    return (
        f"every task holds (tol {tol_p:g} m, {tol_r:g} rad) after {restarts} restart(s); "
        "verified by forward kinematics"
    )


def unmoved(task: str, frame: str, error: str) -> str:
    """A task on a frame no joint moves, which does not hold: no configuration meets it."""
    return (
        f"{task} is on frame {frame!r}, which none of the arm's joints moves, and is not met "
        f"there ({error}): no configuration meets it; q is the start"
    )


def tasks_missed(restarts: int, iterations: int, closest: str) -> str:
    """A task list with no answer found within the budget; ``closest``: each task's error."""
    return (
        f"no configuration meeting every task found within the budget ({restarts} "
        f"restart(s), {iterations} iterations), which does not show the tasks "
        f"impossible; closest: {closest}; q is that configuration"
    )


def on_centre(reason: str) -> str:
    """A task list answered by its centre's compiled answer (``reason``: that answer's)."""
    return f"{reason}; every task holds on it"


def preferred(reason: str, score: str, said: str, moved: bool, secondary: bool = False) -> str:
    """A task list's answer with a preference ``score`` (or a secondary posture), ``said``
    its value in the score's words (``Score.words``), moved along the tasks' null space or
    not."""
    how = (
        "moved along the tasks' null space"
        if moved
        else "no move along the tasks' null space lowered it"
    )
    prefix = "secondary posture" if secondary else f"prefer={score}"
    return f"{reason}; {prefix}: {said} ({how})"


def ranked_first(reason: str, score: str, said: str, count: int, variant: bool) -> str:
    """The best of ``count`` verified answers by the preference ``score``, ``said`` its
    value in the score's words; ``variant``: a 2 pi turn of the answer found."""
    turned = " (a 2 pi variant within the limits)" if variant else ""
    return f"{reason}; prefer={score}: {said}, ranked among {count} verified{turned}"


def tips_beyond(beyond: dict[str, str], others: list[str], status: str, reason: str) -> str:
    """Several tips, some beyond reach (tip -> why), the ``others`` solved without them."""
    said = "; ".join(f"tip {tip!r}: {why}" for tip, why in beyond.items())
    if others:
        said += f"; the other tips {others}, solved without it: {status} ({reason})"
    return said


def _pair_text(pair: tuple[str, str] | None, distance: float) -> str:
    if pair is None:
        return "no pair to check"
    gap = f"{distance:.3g} m apart" if distance > 0 else f"overlapping by {-distance:.3g} m"
    return f"{pair[0]} and {pair[1]} {gap if distance != 0 else 'touching'}"


def in_collision(pair: tuple[str, str] | None, distance: float, margin: float) -> str:
    """A verified answer whose closest checked pair is nearer than ``margin`` (m): in
    collision where it overlaps (``distance`` the depth, negative) or touches, else apart
    but closer than the margin."""
    said = "in collision" if distance <= 0 else "closer than the margin"
    return f"{said}: {_pair_text(pair, distance)} (margin {margin:g} m)"


def clear(pair: tuple[str, str] | None, distance: float, margin: float) -> str:
    """What a collision-checked success adds to its reason: the closest pair."""
    return f"collision-free: closest {_pair_text(pair, distance)} (margin {margin:g} m)"


def and_clear(reason: str, pair: tuple[str, str] | None, distance: float, margin: float) -> str:
    """``reason`` of a collision-checked success, with its closest pair (``clear``)."""
    return f"{reason}; {clear(pair, distance, margin)}"


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


def measured_apart(
    reason: str,
    pos: float | None,
    ori: float | None,
    weighted: bool,
    axis: Cone | None = None,
) -> str:
    """A result whose verdict measured other than the distances to the target (weights on
    the axes, a region): its reason, then those distances, what ``position_error`` and
    ``orientation_error`` report: the tip's to the target's position and the angle to its
    rotation, or, where the orientation distance is the tip axis' angle to its direction
    (``axis``: an aim at a point or along a direction, an ``armik.Axis``), in those terms
    (``_aim_apart``); a part the target has not (None, NaN) unsaid."""
    said = f"{reason} (on the weighted axes)" if weighted else reason
    if axis is not None:
        return said + _aim_apart(pos, ori, axis)
    parts = _parts(pos, ori)
    return f"{said}; the tip is {parts} from the target" if parts else said


def _aim_apart(pos: float | None, ori: float | None, axis: Cone) -> str:
    """'; the tip is x m from the target, its axis y rad from its direction': the distances
    of a target that aims the tip's axis. A position it has not (None) unsaid, the axis
    then alone, where its cone has a width: 0 wide, the verdict's words said that angle
    already."""
    said = "" if ori is None or ori != ori else f"{ori:.3g} rad from {axis.sight}"
    if pos is None or pos != pos:
        return f"; the tip's axis is {said}" if said and axis.within > 0.0 else ""
    where = f"; the tip is {pos:.3g} m from the target"
    return f"{where}, its axis {said}" if said else where


def tips_apart(reason: str, pos: float | None, ori: float | None) -> str:
    """A row of several tips some of whose verdicts measured other than the distances (a
    tip's region, weights): its reason (the worst tip's measure), then the largest of the
    tips' distances to their targets, what ``position_error`` and ``orientation_error``
    report (None, NaN: no tip's target holds that part)."""
    parts = _parts(pos, ori)
    return (
        f"{reason}, the worst of what the tips' verdicts measured; every tip is at most "
        f"{parts} from its target"
    )


def tasks_apart(reason: str, pos: float | None, ori: float | None) -> str:
    """A task list with regions: its reason, then the largest distance of a task's frame
    to its target, what ``position_error`` and ``orientation_error`` report (None, NaN:
    no task holds that part)."""
    said = _parts(pos, ori) or f"{pos or 0.0:.3g} m"
    return f"{reason}; each task's frame is at most {said} from its target"


def _parts(pos: float | None, ori: float | None) -> str:
    """'x m, y rad', a part not measured (None, NaN) left out; '' where nothing is left."""
    said = [] if pos is None or pos != pos else [f"{pos:.3g} m"]
    if not (ori is None or ori != ori):
        said.append(f"{ori:.3g} rad")
    return ", ".join(said)


def orientation_unreachable(angle: float, fixed: bool, tol: float) -> str:
    """A target rotation ``angle`` rad (at least) from every rotation the tip takes, its
    chain's structure bounding them (``fixed``: no joint turns), beyond ``tol``
    (``tol_orientation``), refused before any iteration."""
    takes = (
        "the one orientation the tip has (no joint turns)"
        if fixed
        else "every orientation the tip takes (all its turning joints are parallel)"
    )
    return (
        f"the target's orientation is {angle:.3g} rad from {takes}, beyond tol_orientation "
        f"({tol:g} rad); q is the seed, unchanged"
    )


def slides_unreachable(distance: float, tol: float) -> str:
    """A position ``distance`` m (at least) from every one a chain of prismatic joints only
    reaches within its limits, beyond ``tol`` (``tol_position``), refused before any
    iteration."""
    return (
        f"the target is {distance:.3g} m from every position the tip reaches (its joints all "
        f"slide, within their limits), beyond tol_position ({tol:g} m); q is the seed, "
        "unchanged"
    )


def tip_apart(reason: str, task, pos: float | None, ori: float | None, weighted: bool) -> str:
    """``measured_apart`` for one task on the tip (``Task``): an aim's (an axis, a look-at)
    in the aim's terms."""
    return measured_apart(reason, pos, ori, weighted, task.cone_words())


def frame_apart(reason: str, task, pos: float | None, ori: float | None, weighted: bool) -> str:
    """``measured_apart`` for one task on a frame other than the tip: that frame's
    distance to its target, an aim's (an axis alone) its axis' angle from its direction."""
    frame = str(task.frame)
    cone = task.cone_words()
    if cone is not None and ori is not None:
        return f"{reason}; frame {frame!r} has its axis {ori:.3g} rad from {cone.sight}"
    said = f"{reason} (on the weighted axes)" if weighted else reason
    return f"{said}; frame {frame!r} is {_parts(pos, ori) or f'{pos or 0.0:.3g} m'} from the target"


def chains_collide(pair: tuple[str, str] | None, distance: float, margin: float) -> str:
    """Several tips on chains that share no joint, each verified and clear alone (the
    other chains held where it was cut): the robot at their answers side by side is not."""
    together = in_collision(pair, distance, margin)
    return (
        f"every tip reached, but the chains' answers together are {together} (each chain "
        "was checked alone, the other chains held where it was cut)"
    )


def not_together(reason: str, option: object) -> str:
    """Tips placed relative to each other on chains that share no joint, solved one chain
    after another and failing: ``reason``, and why every chain at once was not tried."""
    return (
        f"{reason}; every chain at once (the task solver) was not tried: it does not take {option}="
    )


def height_unreachable(distance: float, tol: float) -> str:
    """A target ``distance`` m (along the turning joints' common axis) from every height a
    chain whose turning axes are all parallel reaches within its limits, beyond ``tol``
    (``tol_position``), refused before any iteration."""
    return (
        f"the target is {distance:.3g} m, along the axis its turning joints share, from every "
        f"height the tip reaches (turning about parallel axes keeps it; its slides within "
        f"their limits change it), beyond tol_position ({tol:g} m); q is the seed, unchanged"
    )


def slides_wrist_unreachable(distance: float, wrist: float, tol: float) -> str:
    """A position ``distance`` m (at least) from every one a chain reaches whose slides
    come before its turning joints, these reaching at most ``wrist`` m from the first one's
    origin, beyond ``tol`` (``tol_position``), refused before any iteration."""
    return (
        f"the target is {distance:.3g} m from every position the tip reaches (its slides, "
        f"within their limits, carry its turning joints, which reach at most {wrist:.3g} m "
        f"from the first one), beyond tol_position ({tol:g} m); q is the seed, unchanged"
    )


def apart_collide(pair: tuple[str, str] | None, distance: float, margin: float) -> str:
    """Several tips on chains that share no joint, each verified and clear alone (against
    the obstacles and its own links, those another chain moves left to it): the robot at
    their answers side by side is not."""
    together = in_collision(pair, distance, margin)
    return (
        f"every tip reached, but the chains' answers together are {together} (each chain "
        "was checked alone, against the obstacles and its own links)"
    )


def left_collide(pair: tuple[str, str] | None, distance: float, margin: float, left) -> str:
    """Several tips on chains that share no joint, each given tip verified and clear, the
    chains of the tips ``left`` out of the targets keeping q0's values: the robot's
    configuration is not clear of the obstacles."""
    together = in_collision(pair, distance, margin)
    return (
        f"every tip given reached, but the robot's configuration is {together}: the chains "
        f"of tips {list(left)}, given no target, keep q0's values, which no solve moved "
        "clear (give those tips a target, or a q0 clear of the obstacles)"
    )


def left_out_fails(tip: str, why: str) -> str:
    """A constraint given by ``tip``, a tip given no target on chains that share no joint,
    failing at the values its chain keeps from q0: its check's ``why``."""
    return f"tip {tip!r}, given no target, keeps q0's values, where {why}"


def outside_own_box(name: str, joint: str, value: float, lower: float, upper: float) -> str:
    """An answer outside the ``box`` of a user's constraint class ``name``, at ``joint``."""
    return f"constraint {name}: {joint} at {value:.6g}, outside its box [{lower:.6g}, {upper:.6g}]"


def held_link(link: str, joints: tuple[str, ...], tip: str) -> str:
    """A checked link whose own ``joints`` are no joints of the chain to ``tip``: they keep
    the values the chain was loaded with, the chain's joints only carry it."""
    shown = ", ".join(joints[:3]) + (", ..." if len(joints) > 3 else "")
    return (
        f"link {link!r} is held: its joints ({shown}) are none of this chain's and keep the "
        "values it was loaded with, so an answer moves that link only as the joints that "
        "carry it move; lock them where the link is clear when loading the chain: "
        f"armik.load(urdf, tip={tip!r}, locked={{{joints[0]!r}: value}}) "
        "(docs/several-tips.md)"
    )
