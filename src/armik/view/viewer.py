"""The browser viewer: a robot (one arm, or several tips of one robot), its targets and
their tolerance regions, its answers, paths, reach maps and obstacles in a viser scene,
with a transform gizmo on each tip's target that solves as it is dragged.

Everything is in the robot's base frame (m). The scene is served at ``Viewer.url`` until
``close()``; any number of browser tabs may watch it. viser is an optional dependency
(``pip install "armik[view]"``): without it ``armik.view`` raises ``ViewerError``.
"""

from __future__ import annotations

import logging
import math
import threading
import time
import webbrowser
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from armik.batch_result import BatchResult
from armik.constraints.shapes import Shape
from armik.constraints.shapes_file import as_shapes
from armik.errors import ArmikError, InputError, OptionError
from armik.problem.scores import parse_score
from armik.result import IKResult
from armik.solve.reach import ReachMap
from armik.solve.read import options as read_options
from armik.view import follow, regions, server
from armik.view.ghosts import MAX_GHOSTS, Ghosts
from armik.view.nodes import BodyNodes, pose_of, wxyz_position
from armik.view.panel import Panel
from armik.view.paths import PathPlayer, check_fps, check_paths, draw_trace
from armik.view.robot import Robot
from armik.view.scenery import REACHED, UNREACHED, draw_obstacle, draw_reach
from armik.view.targets import dragged, gizmo_pose, per_tip, tasks_of

if TYPE_CHECKING:
    import viser

log = logging.getLogger(__name__)


class Viewer:
    """A robot in the browser (build it with ``armik.view``): an ``Arm``, or an ``Arms``
    (``armik.load(..., tips=[...])``: the whole robot, a gizmo per tip, every tip solved
    at once). Methods: ``show(q)``, ``set_target(T, q0=None)``, ``play(batch_result,
    fps=30)``, ``play_paths({name: batch_result})``, ``show_reach(reach_map)``,
    ``add_obstacles(shapes)``, ``wait()``, ``close()``; also a context manager.

    Attributes: ``arm`` (the ``Arm`` or ``Arms`` given), ``robot`` (what the viewer reads
    of it: tips, joints, parts), ``url``, ``port``, ``solver`` (the name the viewer solves
    with), ``options`` (the solve options), ``q`` (the configuration shown, rad or m),
    ``targets`` (tip -> its target), ``result`` (the last ``IKResult``), ``solutions``
    (the answers drawn as ghosts), ``regions`` (the tolerance regions drawn), ``paths``
    (the ``PathPlayer`` of ``play_paths``, or None), ``obstacles``.
    """

    def __init__(
        self,
        arm: object,
        *,
        port: int = 8080,
        host: str = "127.0.0.1",
        open_browser: bool = True,
        solver: str = "auto",
        q: object = None,
        **options: object,
    ) -> None:
        robot = Robot(arm)  # InputError for anything but an Arm or an Arms
        if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
            raise OptionError(
                f"port must be a whole number in 0..65535 (0: any free port), got {port!r}",
                option="port",
                value=port,
            )
        robot.check_solver(solver)  # SolverError for an unknown or inapplicable name
        robot.check_collisions(options)  # CollisionError for an arm without <collision>s
        # OptionError now rather than at the first drag
        checked = read_options({k: v for k, v in options.items() if k != "prefer"})
        self._tol = (checked.tol_position, checked.tol_orientation)
        parse_score(options.get("prefer"))
        server.import_viser()
        self.arm = arm
        self.robot = robot
        self.solver = solver
        self.options = dict(options)
        self._lock = threading.RLock()
        self._closed = threading.Event()
        if q is None:
            self._q = robot.middle.copy()
        elif robot.several:
            self._q = np.clip(robot.check_q(q), robot.lower, robot.upper)
        else:
            self._q = robot.chains[robot.tips[0]].seed(robot.check_q(q))  # named q
        self.targets: dict[str, object] = {}
        self.result: IKResult | None = None
        self.solutions: list[IKResult] = []
        self.regions: list[regions.Region] = []
        self.paths: PathPlayer | None = None
        self.obstacles: list[Shape] = []
        self._region_nodes: list = []
        self._pending: dict[str, object] = {}
        self._solving = False
        self._ghosts_on = False
        self._follower: follow.Follower | None = None  # the servo mode (``follow``)
        self._following = threading.Event()  # set: the servo mode's thread is to stop
        self._position_only = min(a.dof for a in robot.chains.values()) < 6

        self._server, self.port = server.start(host, port, f"armik: {robot.name}")
        self.host = host
        try:
            self._build_scene()
        except BaseException:
            self._server.stop()
            raise
        log.info("viewer of %r at %s", robot.name, self.url)
        if open_browser:
            webbrowser.open(self.url)

    # -- the scene ------------------------------------------------------------------------

    def _build_scene(self) -> None:
        robot, scene = self.robot, self._server.scene
        s = self._size = robot.size
        flat = robot.plane is not None and abs(robot.plane.normal[2]) > 0.9
        centre = robot.centre + (0.0, 0.0, 0.0 if flat else 0.25 * s)
        view = np.array([0.3, -0.55, 1.0] if flat else [1.0, -1.25, 0.7])
        cam = self._server.initial_camera
        cam.position = centre + 1.5 * s * view / np.linalg.norm(view)
        cam.look_at = centre
        cam.up = (0.0, 0.0, 1.0)
        cell = 10 ** math.floor(math.log10(s / 2))
        scene.add_grid("/grid", width=4 * s, height=4 * s, cell_size=cell, section_size=10 * cell,
                       position=(0.0, 0.0, -1e-3 * s))  # fmt: skip
        self._arm_nodes = BodyNodes(scene, "/arm", robot.body)
        self._ghosts = Ghosts(scene, robot)
        self._tip_frames: dict[str, viser.FrameHandle] = {}
        self._gizmos: dict[str, viser.TransformControlsHandle] = {}
        self._marks: dict[str, viser.IcosphereHandle] = {}
        for k, tip in enumerate(robot.tips):
            # one tip keeps the names it always had; several are numbered in tips' order
            n = str(k) if robot.several else ""
            tip_name, target = f"/tip{n}", f"/target{n}"
            self._tip_frames[tip] = scene.add_frame(tip_name, axes_length=0.12 * s,
                                                    axes_radius=0.005 * s)  # fmt: skip
            gizmo = self._gizmos[tip] = scene.add_transform_controls(target, scale=0.3 * s)
            scene.add_frame(f"{target}/axes", axes_length=0.08 * s, axes_radius=0.004 * s)
            self._marks[tip] = scene.add_icosphere(f"{target}/mark", radius=0.02 * s,
                                                   color=REACHED)  # fmt: skip
            if robot.several:
                scene.add_label(f"{target}/label", tip)
            gizmo.on_update(self._on_drag(tip))
        self.panel = Panel(
            self._server.gui,
            robot,
            solver=self.solver,
            position_only=self._position_only,
            on_joints=self._slid,
            on_solver=self._chose_solver,
            on_ghosts=self._toggled_ghosts,
            on_position_only=self._toggled_position_only,
            on_prefer=self._chose_prefer,
            on_follow=self._toggled_follow,
            prefer=self.options.get("prefer"),
        )
        self.show(self._q)

    def _put(self, q: np.ndarray, failed: bool) -> None:
        """Draw the robot at ``q`` (red if ``failed``) with its tip frames, sliders and
        regions."""
        robot = self.robot
        with self._server.atomic():
            self._arm_nodes.pose(robot.poses(q))
            self._arm_nodes.mark_failed(failed)
            if not self._arm_nodes.visible:  # hidden by play_paths
                self._arm_nodes.visible = True
            for tip, frame in self._tip_frames.items():
                frame.wxyz, frame.position = wxyz_position(robot.fk(q, tip).homogeneous)
        self.panel.set_q(q)
        self._q = np.array(q, dtype=float)
        self._draw_regions()

    def _place_gizmo(self, tip: str, ok: bool | None) -> None:
        """``tip``'s gizmo at its target's anchor (or the tip), its ball red if not ``ok``."""
        T = gizmo_pose(self.targets.get(tip), self.robot, self._q, tip)
        self._gizmos[tip].wxyz, self._gizmos[tip].position = wxyz_position(T)
        self._marks[tip].color = UNREACHED if ok is False else REACHED

    def _draw_regions(self) -> None:
        """Every task list's regions (``armik.view.regions``) at the configuration shown."""
        shapes: list[regions.Region] = []
        for k, tip in enumerate(self.robot.tips):
            for j, task in enumerate(tasks_of(self.targets.get(tip)) or ()):
                T = self.robot.frame_pose(self._q, tip, task)
                shapes += regions.task_regions(task, T, self._size, f"/regions/{k}/{j}")
        old = self._region_nodes
        self._region_nodes = regions.draw(self._server.scene, shapes, self._size)
        names = {h.name for h in self._region_nodes}
        for handle in old:  # a node added again under its name replaced the old one
            if handle.name not in names:
                handle.remove()
        self.regions = shapes

    # -- the API --------------------------------------------------------------------------

    @property
    def url(self) -> str:
        host = "localhost" if self.host in ("", "0.0.0.0", "::") else self.host
        return f"http://{f'[{host}]' if ':' in host else host}:{self.port}"  # IPv6: [::1]

    @property
    def q(self) -> np.ndarray:
        """The configuration shown (rad, m), a copy."""
        return self._q.copy()

    def show(self, q: object, *, failed: bool = False) -> None:
        """Put the robot at joints ``q`` (rad, m), drawn red if ``failed``; the gizmos move
        to the tips. Raises ``OptionError`` for a ``q`` of the wrong shape."""
        q = self.robot.check_q(q)
        with self._lock:
            self._put(q, failed)
            for tip, gizmo in self._gizmos.items():
                gizmo.wxyz, gizmo.position = wxyz_position(self.robot.fk(q, tip).homogeneous)
                self._marks[tip].color = REACHED
            self.panel.show_note("joints set (FK)")
            if self._follower is not None:  # the servo mode goes on from the arm shown
                self._follower.restart(q)

    def set_target(self, T: object, q0: object = None) -> IKResult:
        """Solve for target ``T`` from ``q0`` (default: the configuration shown) with the
        viewer's solver and options, and show the answer. One arm: ``T`` is any target
        ``Arm.solve`` takes (a pose, a position, a task list, whose tolerance regions are
        drawn); several tips: ``{tip: target, ...}``. Returns what ``arm.solve(T, q0=...,
        solver=viewer.solver, **viewer.options)`` returns; the robot moves only when it
        succeeds (a failure is shown in the panel, the target marked red). Raises what the
        solve raises for malformed input, ``InputError`` for a robot's targets not given
        per tip."""
        return self._solve(per_tip(T, self.robot), q0, "target")

    def _solve(
        self, targets: dict[str, object], q0: object, what: str, held: tuple = ()
    ) -> IKResult:
        """Solve ``targets`` and show the answer (``what``: the panel's "target" row); the
        gizmos of ``held`` (being dragged) stay where the user holds them."""
        with self._lock:
            seed: object = self._q if q0 is None else q0
            r = self.robot.solve(targets, seed, self.solver, self.options)
            self.targets, self.result = dict(targets), r
            if r.success:
                self._put(r.q, False)
                if self._follower is not None:  # set_target in the servo mode
                    self._follower.restart(r.q)
            else:
                self._draw_regions()
            verified = self.robot.tip_results(r, self._tol)
            for tip in self.robot.tips:
                if tip not in held:
                    ok = verified[tip][0] if tip in verified else None
                    self._place_gizmo(tip, ok if tip in targets else None)
                elif tip in verified:
                    self._marks[tip].color = REACHED if verified[tip][0] else UNREACHED
            self.panel.show_result(r, what, self._tol)
            if self._ghosts_on:
                self._draw_ghosts(seed)
            return r

    def play(self, batch_result: BatchResult, fps: float = 30.0) -> None:
        """Walk every waypoint of a ``solve_path`` (or ``solve_batch``) result in order,
        ``fps`` a second; failed waypoints are drawn red, and each tip's path is drawn as
        points (green reached, red not). Blocks until the last waypoint is shown."""
        if not isinstance(batch_result, BatchResult):
            raise InputError(
                f"play takes the BatchResult of arm.solve_path(...), got "
                f"{type(batch_result).__name__}"
            )
        if batch_result.q.ndim != 2 or batch_result.q.shape[1] != self.robot.dof:
            raise InputError(
                f"the batch result holds configurations of shape {batch_result.q.shape[1:]}, "
                f"not ({self.robot.dof},) of {self.robot.name!r}: play a result of this arm"
            )
        fps = check_fps(fps)
        n = len(batch_result)
        if n:
            draw_trace(self._server.scene, self.robot, batch_result)
        for i in range(n):
            ok = bool(batch_result.success[i])
            self.show(batch_result.q[i], failed=not ok)
            reason = "" if ok else batch_result.reason(i)
            self.panel.show_note(f"waypoint {i + 1} of {n}: {batch_result.status[i]}", reason)
            if i + 1 < n:
                time.sleep(1.0 / fps)

    def play_paths(self, paths: Mapping[str, BatchResult], fps: float | None = None) -> PathPlayer:
        """Show several ``solve_path`` results over the same waypoints side by side, e.g.
        ``{"follow": arm.solve_path(poses, q0), "global": arm.solve_path(poses, q0,
        plan="global")}``: a ghost of the robot per path, each tip's trace, discontinuous
        waypoints marked orange and other failures red, and a "waypoint" slider in the
        panel that steps them together (``armik.view.paths``). The solid robot is hidden
        until it is shown again (``show``, ``set_target``, the sliders). With ``fps``,
        walks every waypoint first (blocking). Returns the ``PathPlayer`` (``show(i)``,
        ``play(fps)``, ``remove()``), also ``viewer.paths``; raises ``InputError`` for
        paths of another robot or of different lengths."""
        paths = check_paths(self.robot, paths)
        rate = None if fps is None else check_fps(fps)
        with self._lock:
            if self.paths is not None:
                self.paths.remove()
            self._arm_nodes.visible = False
            self.paths = player = PathPlayer(self._server, self.robot, paths, self._lock)
        if rate is not None:
            player.play(rate)
        return player

    def show_reach(self, reach_map: ReachMap | str | Path, *, unreached: bool = False) -> int:
        """Draw a reach map (``armik.solve.reach``, or the path of its .npz) as a point
        cloud: one point per voxel coloured from red (few orientations reached) to green
        (all); voxels reached in no orientation only if ``unreached`` (grey). Returns the
        number of points drawn."""
        if isinstance(reach_map, (str, Path)):
            reach_map = ReachMap.load(reach_map)
        if not isinstance(reach_map, ReachMap):
            raise InputError(
                f"show_reach takes a ReachMap (armik reach ... -o map.npz, or "
                f"armik.solve.reach.reachability), got {type(reach_map).__name__}"
            )
        return draw_reach(self._server.scene, reach_map, unreached)

    def add_obstacles(self, shapes: list[Shape]) -> list[Shape]:
        """Draw obstacles: a list of shapes (``armik.Box``, ``Sphere``, ``Capsule``,
        ``Cylinder``, ``HalfSpace``, ``Mesh``, or their plain mappings,
        ``armik.constraints.shapes_file``), in the base frame (m). Returns every obstacle
        added so far. Pass the same shapes as ``obstacles=`` to solve clear of them."""
        shapes = as_shapes(() if shapes is None else shapes)  # None: nothing to draw
        scene = self._server.scene
        with self._lock:
            for shape in shapes:
                draw_obstacle(scene, f"/obstacles/{len(self.obstacles)}", shape)
                self.obstacles.append(shape)
            return list(self.obstacles)

    def follow(self, on: bool = True, **servo_options: object) -> follow.Follower | None:
        """The servo mode: with ``on``, a dragged target is followed by the servo
        (``Arm.servo`` from the configuration shown, with ``servo_options``: ``dt``,
        ``velocity_limits``, ``acceleration_limits``, ``obstacles``, ...), every joint within
        its limits at every tick, 30 frames a second (``armik.view.follow``), instead of
        solved; off, drags solve again. Returns the ``Follower`` (None when off). Raises
        what ``Arm.servo`` raises for bad options or a robot it does not take."""
        with self._lock:
            self._following.set()  # the running mode's thread ends
            self._follower = None
            if not on:
                self.panel.follow.value = False  # type: ignore[misc]
                return None
            tips = tuple(self.robot.tips)
            follower = follow.Follower(self.robot.source, self._q, tips, **servo_options)
            self._follower, self._following = follower, threading.Event()
            self.panel.follow.value = True  # type: ignore[misc]
            follower.aim(self.targets)
        threading.Thread(
            target=follow.run, args=(follower, self._followed, self._following), daemon=True
        ).start()
        return follower

    def _followed(self, step) -> None:
        """Draw the servo's step (a frame of the servo mode)."""
        with self._lock:
            last = None if self._follower is None else self._follower.last
            if self._closed.is_set() or last is None or step is not last:
                return  # closed, or the servo restarted since this step
            self._put(last.q, False)
            self.panel.show_note(f"servo: {last.status}", last.reason)

    def wait(self) -> None:
        """Block until Ctrl-C or ``close()`` from another thread, then close."""
        try:
            while not self._closed.wait(0.25):
                pass
        except KeyboardInterrupt:
            pass
        finally:
            self.close()

    def close(self) -> None:
        """Stop serving and free the port (waits, up to 10 s, until it can be bound)."""
        with self._lock:
            if self._closed.is_set():
                return
            self._closed.set()
            self._following.set()
        server.stop(self._server, self.host, self.port)

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self._closed.is_set() else self.url
        tips = f", tips={list(self.robot.tips)}" if self.robot.several else ""
        return f"Viewer({self.robot.name!r}{tips}, {state}, solver={self.solver!r})"

    # -- what the browser does ------------------------------------------------------------

    def _dragged(self, handle: viser.TransformControlsHandle, tip: str | None = None) -> None:
        """A gizmo moved: solve every tip's target with it, the latest pose first (drags
        come faster than numeric solves; the poses in between are skipped)."""
        tip = self.robot.tips[0] if tip is None else tip
        T = pose_of(handle.wxyz, handle.position)
        with self._lock:
            self._pending[tip] = T
            if self._solving:
                return
            self._solving = True
        while True:
            with self._lock:
                moved, self._pending = self._pending, {}
                if not moved:
                    self._solving = False
                    return
                targets = dict(self.targets)
                for t, pose in moved.items():
                    targets[t] = dragged(targets.get(t), pose, self._position_only, t)
                if self._follower is not None:  # the servo mode: followed, not solved
                    self.targets = targets
                    self._follower.aim(targets)
                    continue
                try:
                    self._solve(targets, None, "dragged target", held=tuple(moved))
                except ArmikError as exc:
                    self.panel.show_note("target refused", str(exc))

    def _on_drag(self, tip: str):
        return lambda event: self._dragged(event.target, tip)

    def _slid(self, q: np.ndarray) -> None:
        with self._lock:
            self.show(q)
            self.panel.show_note("joints set (sliders, FK)")

    def _chose_solver(self, name: str) -> None:
        with self._lock:
            self.solver = name
            if not self.targets:
                return
            try:
                self._solve(self.targets, None, f"target, with solver {name!r}")
            except ArmikError as exc:
                self.panel.show_note(f"solver {name!r} refused the target", str(exc))

    def _chose_prefer(self, name: object) -> None:
        with self._lock:
            before = self.options.pop("prefer", None)
            self.options.update({} if name == "none" else {"prefer": name})
            try:
                if self.targets:
                    self._solve(self.targets, None, "target, with the preference chosen")
            except ArmikError as exc:  # manipulability over shared joints: as it was
                self.options.pop("prefer", None)
                self.options.update({} if before is None else {"prefer": before})
                self.panel.refused_prefer(before, f"prefer {name!r} refused", str(exc))

    def _toggled_position_only(self, on: bool) -> None:
        self._position_only = bool(on)

    def _toggled_follow(self, on: bool) -> None:
        try:
            self.follow(on)
        except ArmikError as exc:
            self.panel.show_note("the servo refused this robot", str(exc))
            self.panel.follow.value = False  # type: ignore[misc]

    def _toggled_ghosts(self, on: bool) -> None:
        with self._lock:
            self._ghosts_on = bool(on)
            if on and self.targets:
                self._draw_ghosts(self._q)
            elif not on:
                self._ghosts.hide()
                self.solutions = []

    def _draw_ghosts(self, q0: object) -> None:
        """Every answer of ``solve_all`` for the target (one arm) as a ghost."""
        if self.robot.several:
            return  # solve_all is one arm's
        (target,) = self.targets.values()
        arm = self.robot.source
        try:
            found = arm.solve_all(target, q0=q0, solver=self.solver, **self.options)  # type: ignore[attr-defined]
        except ArmikError as exc:
            self.panel.show_note("all solutions refused", str(exc))
            found = []
        self.solutions = found = found[:MAX_GHOSTS]
        self._ghosts.draw(found)
