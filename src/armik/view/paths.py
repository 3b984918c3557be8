"""Paths on the page: the trace ``Viewer.play`` leaves, and paths side by side
(``Viewer.play_paths``): the results of several ``solve_path`` calls over the same
waypoints (``plan="follow"`` beside ``plan="global"``), stepped together.

Each path has a ghost of the robot in a colour of its own, labelled with the path's name
and the waypoint's status, and each tip's trace through the waypoints; its discontinuous
waypoints are marked by orange balls, its other failures by red ones. A "waypoint" slider
in the panel steps every ghost, its marks at the flagged waypoints.
"""

from __future__ import annotations

import math
import numbers
import threading
import time
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from armik.batch_result import BatchResult
from armik.errors import InputError, OptionError
from armik.status import Status
from armik.view.ghosts import GHOST_COLORS
from armik.view.nodes import BodyNodes
from armik.view.robot import Robot
from armik.view.scenery import REACHED, UNREACHED

if TYPE_CHECKING:
    import viser

JUMP, FAILED = (255, 140, 0), (220, 50, 50)


def draw_trace(scene, robot: Robot, batch: BatchResult) -> None:
    """``Viewer.play``'s trace: each tip's position at every waypoint of ``batch`` as a
    point (green reached, red not), joined by grey lines."""
    colors = np.where(batch.success[:, None], REACHED, UNREACHED).astype(np.uint8)
    s = robot.size
    for k, tip in enumerate(robot.tips):
        points = np.array([robot.fk(q, tip).translation for q in batch.q], dtype=np.float32)
        name = "/path" if k == 0 else f"/path{k}"
        scene.add_point_cloud(f"{name}/points", points, colors, point_size=0.02 * s,
                              point_shape="circle")  # fmt: skip
        if len(points) > 1:
            segments = np.stack([points[:-1], points[1:]], axis=1)
            scene.add_line_segments(f"{name}/line", segments, (120, 120, 120),
                                    thickness=0.004 * s)  # fmt: skip


def check_fps(fps: object) -> float:
    """``fps`` as a rate > 0 (frames a second); ``OptionError`` naming it otherwise."""
    try:
        rate = float(fps)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        rate = math.nan
    if not (math.isfinite(rate) and rate > 0):
        raise OptionError(f"fps must be a number > 0, got {fps!r}", option="fps", value=fps)
    return rate


def check_paths(robot: Robot, paths: object) -> dict[str, BatchResult]:
    """``paths`` as name -> ``BatchResult`` of this robot, all of one length; ``InputError``
    naming what is wrong and the fix."""
    if not isinstance(paths, Mapping) or not paths:
        raise InputError(
            "play_paths takes a mapping of names to solve_path results, e.g. "
            f'{{"follow": arm.solve_path(...), "global": ...}}, got {type(paths).__name__}'
        )
    if len(paths) > len(GHOST_COLORS):
        raise InputError(
            f"play_paths draws at most {len(GHOST_COLORS)} paths at once, got {len(paths)}"
        )
    for name, batch in paths.items():
        if not isinstance(batch, BatchResult):
            raise InputError(
                f"path {name!r} is a {type(batch).__name__}: give the BatchResult of "
                "solve_path(...)"
            )
        if batch.q.ndim != 2 or batch.q.shape[1] != robot.dof:
            raise InputError(
                f"path {name!r} holds configurations of shape {batch.q.shape[1:]}, not "
                f"({robot.dof},) of {robot.name!r}: give paths of the robot shown"
            )
    lengths = {name: len(b) for name, b in paths.items()}
    if len(set(lengths.values())) != 1 or 0 in lengths.values():
        raise InputError(
            f"the paths must go through the same waypoints, one row each, got lengths "
            f"{lengths}: solve each over the same poses"
        )
    return {str(name): b for name, b in paths.items()}


class PathPlayer:
    """The paths on the page (module docstring). ``show(i)`` puts every ghost at waypoint
    ``i``; ``play(fps)`` walks them all; ``remove()`` takes it all away. Attributes:
    ``paths``, ``index`` (the waypoint shown), ``flagged`` (name -> the waypoints marked)."""

    def __init__(
        self,
        server: viser.ViserServer,
        robot: Robot,
        paths: dict[str, BatchResult],
        lock: threading.RLock,
    ) -> None:
        self._server, self._robot, self._lock = server, robot, lock
        self.paths = paths
        self.n = len(next(iter(paths.values())))
        self.index = 0
        self.flagged: dict[str, np.ndarray] = {}
        self._removed = False
        scene, s = server.scene, robot.size
        self._nodes: list = []
        self._ghosts: list[tuple[BodyNodes, viser.LabelHandle]] = []
        for k, (name, batch) in enumerate(paths.items()):
            color = GHOST_COLORS[k % len(GHOST_COLORS)]
            ghost = BodyNodes(scene, f"/paths/{k}/ghost", robot.body, ghost=color, opacity=0.35)
            label = scene.add_label(f"/paths/{k}/label", name)
            self._ghosts.append((ghost, label))
            tips = self.tip_points(batch)  # (tips, n, 3)
            if self.n > 1:
                segments = np.concatenate([np.stack([t[:-1], t[1:]], axis=1) for t in tips])
                self._nodes.append(scene.add_line_segments(
                    f"/paths/{k}/trace", segments.astype(np.float32), color,
                    thickness=0.004 * s))  # fmt: skip
            jumps = batch.status_code == Status.DISCONTINUOUS.code
            failed = ~batch.success & ~jumps
            self.flagged[name] = np.flatnonzero(~batch.success)
            for what, mask, rgb in (("jumps", jumps, JUMP), ("failed", failed, FAILED)):
                if mask.any():
                    points = tips[:, mask].reshape(-1, 3).astype(np.float32)
                    self._nodes.append(scene.add_point_cloud(
                        f"/paths/{k}/{what}", points, rgb, point_size=0.04 * s,
                        point_shape="circle", precision="float32"))  # fmt: skip
        marks = sorted({int(i) for f in self.flagged.values() for i in f})
        self._folder = server.gui.add_folder("paths")
        with self._folder:
            self.slider = server.gui.add_slider(
                "waypoint", 0, max(self.n - 1, 1), 1, 0, marks=tuple(marks) or None,
                disabled=self.n == 1,
            )  # fmt: skip
            self.texts = {name: server.gui.add_text(name, "", disabled=True) for name in paths}

        def slid(event) -> None:
            if event.client is not None:  # not a value the server set itself
                self.show(int(event.target.value))

        self.slider.on_update(slid)
        self.show(0)

    def tip_points(self, batch: BatchResult) -> np.ndarray:
        """(tips, n, 3): each tip's position (m) at each waypoint of ``batch``."""
        robot = self._robot
        return np.array(
            [[robot.fk(q, tip).translation for q in batch.q] for tip in robot.tips]
        ).reshape(len(robot.tips), len(batch), 3)

    def show(self, i: int) -> None:
        """Every ghost at waypoint ``i`` (0-based), its label and panel row saying the
        waypoint's status (and the reason of a failure)."""
        whole = isinstance(i, numbers.Integral) and not isinstance(i, bool)
        if not whole or not 0 <= i < self.n:
            raise InputError(f"waypoint {i!r} is not one of 0..{self.n - 1} (a whole number)")
        i = int(i)
        robot = self._robot
        with self._lock, self._server.atomic():
            self.index = i
            for k, ((ghost, label), (name, batch)) in enumerate(
                zip(self._ghosts, self.paths.items())
            ):
                q = batch.q[i]
                ghost.pose(robot.poses(q))
                # stacked above the tip: the ghosts' tips often coincide
                lift = np.array([0.0, 0.0, 0.06 * k * robot.size])
                label.position = robot.fk(q, robot.tips[0]).translation + lift
                status = str(batch.status[i])
                label.text = f"{name}: {status}"
                reason = "" if batch.success[i] else f" ({batch.reason(i)})"
                self.texts[name].value = f"{i + 1}/{self.n} {status}{reason}"  # type: ignore[misc]
            self.slider.value = i  # type: ignore[misc]

    def play(self, fps: float = 30.0) -> None:
        """Walk every waypoint in order, ``fps`` a second; blocks until the last.
        ``OptionError`` for an ``fps`` that is no number > 0."""
        rate = check_fps(fps)
        for i in range(self.n):
            self.show(i)
            if i + 1 < self.n:
                time.sleep(1.0 / rate)

    def remove(self) -> None:
        """Take the ghosts, traces, marks and slider off the page (once)."""
        with self._lock:
            if self._removed:
                return
            self._removed = True
            for ghost, label in self._ghosts:
                ghost.remove()
                label.remove()
            for node in self._nodes:
                node.remove()
            self._ghosts, self._nodes = [], []
            self._folder.remove()
