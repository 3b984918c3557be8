"""Every answer of ``solve_all`` as a translucent ghost of the arm, labelled by its branch.

With a preference (``prefer=``), each answer carries its score (lower is better) and the
ghosts are coloured by it, green for the best through yellow to red for the worst (grey:
a failed answer, unscored), the score in the label: which branch a preference picks, and
by how much, at a glance."""

from __future__ import annotations

from typing import TYPE_CHECKING

from armik.result import IKResult
from armik.view.nodes import BodyNodes
from armik.view.stick import skeleton

if TYPE_CHECKING:
    import viser

    from armik.view.robot import Robot

GHOST_COLORS = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40),
                (148, 103, 189), (140, 86, 75), (227, 119, 194), (23, 190, 207)]  # fmt: skip
MAX_GHOSTS = 16
BEST, WORST = (44, 160, 44), (214, 39, 40)  # a scored ghost's colour runs between these
UNSCORED = (150, 150, 150)  # beside scored ones: an answer that failed (no score)


def score_colors(scores: list[float]) -> list[tuple[int, int, int]]:
    """Per score (lower is better), a colour from ``BEST`` through yellow to ``WORST`` by
    its place between the best and the worst; all ``BEST`` when they are equal."""
    lo, hi = min(scores), max(scores)
    middle = (230, 200, 40)
    colors = []
    for s in scores:
        t = 0.0 if hi - lo <= 1e-12 * max(1.0, abs(hi)) else (s - lo) / (hi - lo)
        a, b, u = (BEST, middle, 2 * t) if t <= 0.5 else (middle, WORST, 2 * t - 1)
        colors.append(tuple(round(x + (y - x) * u) for x, y in zip(a, b)))
    return colors  # type: ignore[return-value]


class Ghosts:
    """The ghosts of one arm's answers under ``/ghosts``, made as needed and reused."""

    def __init__(self, scene: viser.SceneApi, robot: Robot) -> None:
        self._scene, self._robot = scene, robot
        self.nodes: list[tuple[BodyNodes, viser.LabelHandle]] = []

    def draw(self, found: list[IKResult]) -> None:
        """One ghost per answer of ``found`` (at most ``MAX_GHOSTS``), the rest hidden."""
        robot, scene = self._robot, self._scene
        arm = robot.chains[robot.tips[0]]
        while len(self.nodes) < len(found):
            i = len(self.nodes)
            nodes = BodyNodes(scene, f"/ghosts/{i}", robot.body,
                              ghost=GHOST_COLORS[i % len(GHOST_COLORS)])  # fmt: skip
            self.nodes.append((nodes, scene.add_label(f"/ghosts/label{i}", "")))
        scores = [r.extra.get("score") for r in found]  # a failed answer has none
        known = [s for s in scores if s is not None]
        scored = bool(known)
        ranked = iter(score_colors(known) if scored else [])
        colors = [UNSCORED if s is None else next(ranked) for s in scores]
        for i, (nodes, label) in enumerate(self.nodes):
            shown = i < len(found)
            nodes.visible = label.visible = shown
            if shown:
                r = found[i]
                nodes.pose(robot.poses(r.q))
                nodes.tint(colors[i] if scored else GHOST_COLORS[i % len(GHOST_COLORS)])
                # at the middle joint: every answer shares the tip, not the elbow
                label.position = skeleton(arm, r.q).points[1 + arm.dof // 2]
                name = r.branch or f"solution {i + 1}"
                if scores[i] is not None:
                    name = f"{name}: score {scores[i]:.4g}"
                label.text = name if r.success else f"{name} ({r.status.value})"

    def hide(self) -> None:
        for nodes, label in self.nodes:
            nodes.visible = label.visible = False
