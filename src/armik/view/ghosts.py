"""Every answer of ``solve_all`` as a translucent ghost of the arm, labelled by its branch."""

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
        for i, (nodes, label) in enumerate(self.nodes):
            shown = i < len(found)
            nodes.visible = label.visible = shown
            if shown:
                r = found[i]
                nodes.pose(robot.poses(r.q))
                # at the middle joint: every answer shares the tip, not the elbow
                label.position = skeleton(arm, r.q).points[1 + arm.dof // 2]
                name = r.branch or f"solution {i + 1}"
                label.text = name if r.success else f"{name} ({r.status.value})"

    def hide(self) -> None:
        for nodes, label in self.nodes:
            nodes.visible = label.visible = False
