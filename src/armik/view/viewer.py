"""The browser viewer: an arm, its target, its answers, paths, reach maps and obstacles in a
viser scene, with a transform gizmo on the target that solves as it is dragged.

Everything is in the arm's base frame (m). The scene is served at ``Viewer.url`` until
``close()``; any number of browser tabs may watch it. viser is an optional dependency
(``pip install "armik[view]"``): without it ``armik.view`` raises ``ViewerError``.
"""

from __future__ import annotations

import contextlib
import io
import logging
import math
import socket
import threading
import time
import webbrowser
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import trimesh

from armik.batch_result import BatchResult
from armik.constraints.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Shape, Sphere
from armik.constraints.shapes_file import as_shapes
from armik.errors import ArmikError, InputError, OptionError, ViewerError
from armik.options import Options
from armik.problem.scores import parse_score
from armik.result import IKResult
from armik.solve.reach import ReachMap
from armik.solvers import registry
from armik.targets.pose import parse_target
from armik.view.nodes import BodyNodes, pose_of, wxyz_position
from armik.view.panel import Panel
from armik.view.scene import arm_body
from armik.view.stick import size, skeleton

if TYPE_CHECKING:
    import viser

    from armik.arm import Arm

log = logging.getLogger(__name__)

GHOST_COLORS = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40),
                (148, 103, 189), (140, 86, 75), (227, 119, 194), (23, 190, 207)]  # fmt: skip
MAX_GHOSTS = 16
OBSTACLE = (255, 150, 60)
REACHED, UNREACHED = (40, 170, 70), (220, 50, 50)


def import_viser():
    """The viser module, or ``ViewerError`` telling how to install it."""
    try:
        import viser
    except ImportError:
        raise ViewerError(
            'the viewer needs viser, an optional extra: pip install "armik[view]"'
        ) from None
    return viser


class Viewer:
    """An arm in the browser (build it with ``armik.view``). Methods: ``show(q)``,
    ``set_target(T, q0=None)``, ``play(batch_result, fps=30)``, ``show_reach(reach_map)``,
    ``add_obstacles(shapes)``, ``wait()``, ``close()``; also a context manager.

    Attributes: ``arm``, ``url``, ``port``, ``solver`` (the name the viewer solves with),
    ``options`` (the solve options), ``q`` (the configuration shown, rad or m), ``result``
    (the last ``IKResult``), ``solutions`` (the answers drawn as ghosts), ``obstacles``.
    """

    _ghosts: list[tuple[BodyNodes, viser.LabelHandle]]  # here: __init__ has a local ``viser``

    def __init__(
        self,
        arm: Arm,
        *,
        port: int = 8080,
        host: str = "127.0.0.1",
        open_browser: bool = True,
        solver: str = "auto",
        q: object = None,
        **options: object,
    ) -> None:
        if not callable(getattr(arm, "solve", None)) or not hasattr(arm, "model"):
            raise InputError(f"the viewer takes an arm from armik.load(...), got {arm!r}")
        if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= 65535:
            raise OptionError(
                f"port must be a whole number in 0..65535 (0: any free port), got {port!r}",
                option="port",
                value=port,
            )
        registry.choose(solver, arm)  # SolverError for an unknown or inapplicable name
        # OptionError now rather than at the first drag
        Options.from_kwargs({k: v for k, v in options.items() if k != "prefer"})
        parse_score(options.get("prefer"))
        viser = import_viser()
        self.arm = arm
        self.solver = solver
        self.options = dict(options)
        self._lock = threading.RLock()
        self._closed = threading.Event()
        self._q = arm.seed(q) if q is not None else arm.middle.copy()
        self.result: IKResult | None = None
        self.solutions: list[IKResult] = []
        self.obstacles: list[Shape] = []
        self._target: object = None
        self._pending: object = None
        self._solving = False
        self._ghosts = []
        self._ghosts_on = False
        self._position_only = arm.dof < 6

        _check_port(host, port)
        with contextlib.redirect_stdout(io.StringIO()):  # viser's banner: the URL is self.url
            self._server = server = viser.ViserServer(
                host=host, port=port, label=f"armik: {arm.name}", verbose=False
            )
        self.host, self.port = host, int(server.get_port())
        if port and self.port != port:  # taken between the check and the bind
            server.stop()
            raise _port_error(host, port)
        try:
            self._build_scene()
        except BaseException:
            server.stop()
            raise
        log.info("viewer of %r at %s", arm.name, self.url)
        if open_browser:
            webbrowser.open(self.url)

    # -- the scene ------------------------------------------------------------------------

    def _build_scene(self) -> None:
        arm, scene = self.arm, self._server.scene
        s = self._size = size(arm)
        self.body = arm_body(arm)
        flat = arm.plane is not None and abs(arm.plane.normal[2]) > 0.9
        centre = arm.first_joint_origin + (0.0, 0.0, 0.0 if flat else 0.25 * s)
        view = np.array([0.3, -0.55, 1.0] if flat else [1.0, -1.25, 0.7])
        cam = self._server.initial_camera
        cam.position = centre + 1.5 * s * view / np.linalg.norm(view)
        cam.look_at = centre
        cam.up = (0.0, 0.0, 1.0)
        cell = 10 ** math.floor(math.log10(s / 2))
        scene.add_grid("/grid", width=4 * s, height=4 * s, cell_size=cell, section_size=10 * cell,
                       position=(0.0, 0.0, -1e-3 * s))  # fmt: skip
        self._arm_nodes = BodyNodes(scene, "/arm", self.body)
        self._tip = scene.add_frame("/tip", axes_length=0.12 * s, axes_radius=0.005 * s)
        self._gizmo = scene.add_transform_controls("/target", scale=0.3 * s)
        scene.add_frame("/target/axes", axes_length=0.08 * s, axes_radius=0.004 * s)
        self._mark = scene.add_icosphere("/target/mark", radius=0.02 * s, color=REACHED)
        self.panel = Panel(
            self._server.gui,
            arm,
            solver=self.solver,
            position_only=self._position_only,
            on_joints=self._slid,
            on_solver=self._chose_solver,
            on_ghosts=self._toggled_ghosts,
            on_position_only=self._toggled_position_only,
            on_prefer=self._chose_prefer,
            prefer=str(self.options.get("prefer") or "none"),
        )
        self._gizmo.on_update(lambda event: self._dragged(event.target))
        self.show(self._q)

    def _put(self, q: np.ndarray, failed: bool) -> None:
        """Draw the arm at ``q`` (red if ``failed``) with its tip frame and sliders."""
        poses = self.body.poses(self.arm, q)
        with self._server.atomic():
            self._arm_nodes.pose(poses)
            self._arm_nodes.mark_failed(failed)
            self._tip.wxyz, self._tip.position = wxyz_position(self.arm.fk(q).homogeneous)
        self.panel.set_q(q)
        self._q = np.array(q, dtype=float)

    def _place_target(self, T: np.ndarray, success: bool | None) -> None:
        self._gizmo.wxyz, self._gizmo.position = wxyz_position(T)
        self._mark.color = UNREACHED if success is False else REACHED

    # -- the API --------------------------------------------------------------------------

    @property
    def url(self) -> str:
        host = "localhost" if self.host in ("", "0.0.0.0", "::") else self.host
        return f"http://{host}:{self.port}"

    @property
    def q(self) -> np.ndarray:
        """The configuration shown (rad, m), a copy."""
        return self._q.copy()

    def show(self, q: object, *, failed: bool = False) -> None:
        """Put the arm at joints ``q`` (rad, m), drawn red if ``failed``; the target gizmo
        moves to its tip. Raises ``OptionError`` for a ``q`` of the wrong shape."""
        q = self.arm.check_q(q)
        with self._lock:
            self._put(q, failed)
            self._place_target(self.arm.fk(q).homogeneous, None)
            self.panel.show_note("joints set (FK)")

    def set_target(self, T: object, q0: object = None) -> IKResult:
        """Solve for target ``T`` (any form ``Arm.solve`` takes) from ``q0`` (default: the
        configuration shown) with the viewer's solver and options, and show the answer.
        Returns ``arm.solve(T, q0=..., solver=viewer.solver, **viewer.options)``'s result;
        the arm moves only when it succeeds (a failure is shown in the panel, the target
        marked red). Raises what ``Arm.solve`` raises for malformed input."""
        return self._solve(T, q0, place=True)

    def _solve(self, T: object, q0: object, place: bool) -> IKResult:
        with self._lock:
            seed = self._q if q0 is None else q0
            r = self.arm.solve(T, q0=seed, solver=self.solver, **self.options)
            self._target, self.result = T, r
            if place:
                self._place_target(parse_target(T, self.arm).se3().homogeneous, r.success)
            else:
                self._mark.color = REACHED if r.success else UNREACHED
            if r.success:
                self._put(r.q, False)
            self.panel.show_result(r, "target" if place else "dragged target")
            if self._ghosts_on:
                self._draw_ghosts(T, seed)
            return r

    def play(self, batch_result: BatchResult, fps: float = 30.0) -> None:
        """Walk every waypoint of a ``solve_path`` (or ``solve_batch``) result in order,
        ``fps`` a second; failed waypoints are drawn red, and the tip's path is drawn as
        points (green reached, red not). Blocks until the last waypoint is shown."""
        if not isinstance(batch_result, BatchResult):
            raise InputError(
                f"play takes the BatchResult of arm.solve_path(...), got "
                f"{type(batch_result).__name__}"
            )
        if batch_result.q.ndim != 2 or batch_result.q.shape[1] != self.arm.dof:
            raise InputError(
                f"the batch result holds configurations of shape {batch_result.q.shape[1:]}, "
                f"not ({self.arm.dof},) of arm {self.arm.name!r}: play a result of this arm"
            )
        try:
            fps = float(fps)
        except (TypeError, ValueError):
            fps = math.nan
        if not (math.isfinite(fps) and fps > 0):
            raise OptionError(f"fps must be a number > 0, got {fps!r}", option="fps", value=fps)
        n = len(batch_result)
        if n:
            self._draw_path(batch_result)
        for i in range(n):
            ok = bool(batch_result.success[i])
            self.show(batch_result.q[i], failed=not ok)
            reason = "" if ok else batch_result.reason(i)
            self.panel.show_note(f"waypoint {i + 1} of {n}: {batch_result.status[i]}", reason)
            if i + 1 < n:
                time.sleep(1.0 / fps)

    def _draw_path(self, batch: BatchResult) -> None:
        tips = np.array([self.arm.fk(q).translation for q in batch.q], dtype=np.float32)
        colors = np.where(batch.success[:, None], REACHED, UNREACHED).astype(np.uint8)
        scene = self._server.scene
        scene.add_point_cloud("/path/points", tips, colors, point_size=0.02 * self._size,
                              point_shape="circle")  # fmt: skip
        if len(tips) > 1:
            segments = np.stack([tips[:-1], tips[1:]], axis=1)
            scene.add_line_segments("/path/line", segments, (120, 120, 120),
                                    thickness=0.004 * self._size)  # fmt: skip

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
        X, Y, Z = np.meshgrid(reach_map.xs, reach_map.ys, reach_map.zs, indexing="ij")
        f = reach_map.fraction
        keep = np.isfinite(f) & ((f > 0) | unreached)
        points = np.stack([X[keep], Y[keep], Z[keep]], axis=1).astype(np.float32)
        self._server.scene.add_point_cloud(
            "/reach", points, reach_colors(f[keep]), point_size=0.2 * reach_map.resolution,
            point_shape="circle",
        )  # fmt: skip
        return len(points)

    def add_obstacles(self, shapes: list[Shape]) -> list[Shape]:
        """Draw obstacles: a list of shapes (``armik.Box``, ``Sphere``, ``Capsule``,
        ``Cylinder``, ``HalfSpace``, ``Mesh``, or their plain mappings,
        ``armik.constraints.shapes_file``), in the base frame (m). Returns every obstacle
        added so far. Pass the same shapes as ``obstacles=`` to solve clear of them."""
        shapes = as_shapes(shapes)
        scene = self._server.scene
        with self._lock:
            for shape in shapes:
                name = f"/obstacles/{len(self.obstacles)}"
                _draw_obstacle(scene, name, shape)
                self.obstacles.append(shape)
            return list(self.obstacles)

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
        with contextlib.redirect_stdout(io.StringIO()):  # viser's "server stopped"
            self._server.stop()
        deadline = time.monotonic() + 10.0
        while not _port_free(self.host, self.port) and time.monotonic() < deadline:
            time.sleep(0.05)

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self._closed.is_set() else self.url
        return f"Viewer({self.arm.name!r}, {state}, solver={self.solver!r})"

    # -- what the browser does ------------------------------------------------------------

    def _dragged(self, handle: viser.TransformControlsHandle) -> None:
        """The gizmo moved: solve for it, the latest pose first (drags come faster than
        numeric solves; the poses in between are skipped)."""
        T = pose_of(handle.wxyz, handle.position)
        with self._lock:
            self._pending = T.translation.copy() if self._position_only else T
            if self._solving:
                return
            self._solving = True
        while True:
            with self._lock:
                target, self._pending = self._pending, None
                if target is None:
                    self._solving = False
                    return
                try:
                    self._solve(target, None, place=False)
                except ArmikError as exc:
                    self.panel.show_note("target refused", str(exc))

    def _slid(self, q: np.ndarray) -> None:
        with self._lock:
            self.show(q)
            self.panel.show_note("joints set (sliders, FK)")

    def _chose_solver(self, name: str) -> None:
        with self._lock:
            self.solver = name
            if self._target is None:
                return
            try:
                self._solve(self._target, None, place=False)
            except ArmikError as exc:
                self.panel.show_note(f"solver {name!r} refused the target", str(exc))

    def _chose_prefer(self, name: str) -> None:
        with self._lock:
            if name == "none":
                self.options.pop("prefer", None)
            else:
                self.options["prefer"] = name
            if self._target is not None:
                self._solve(self._target, None, place=False)

    def _toggled_position_only(self, on: bool) -> None:
        self._position_only = bool(on)

    def _toggled_ghosts(self, on: bool) -> None:
        with self._lock:
            self._ghosts_on = bool(on)
            if on and self._target is not None:
                self._draw_ghosts(self._target, self._q)
            elif not on:
                for nodes, label in self._ghosts:
                    nodes.visible = label.visible = False
                self.solutions = []

    def _draw_ghosts(self, T: object, q0: object) -> None:
        """Every answer of ``solve_all`` as a translucent ghost labelled by its branch."""
        try:
            found = self.arm.solve_all(T, q0=q0, solver=self.solver, **self.options)
        except ArmikError as exc:
            self.panel.show_note("all solutions refused", str(exc))
            found = []
        self.solutions = found = found[:MAX_GHOSTS]
        scene = self._server.scene
        while len(self._ghosts) < len(found):
            i = len(self._ghosts)
            nodes = BodyNodes(scene, f"/ghosts/{i}", self.body,
                              ghost=GHOST_COLORS[i % len(GHOST_COLORS)])  # fmt: skip
            self._ghosts.append((nodes, scene.add_label(f"/ghosts/label{i}", "")))
        for i, (nodes, label) in enumerate(self._ghosts):
            shown = i < len(found)
            nodes.visible = label.visible = shown
            if shown:
                r = found[i]
                nodes.pose(self.body.poses(self.arm, r.q))
                # at the middle joint: every answer shares the tip, not the elbow
                label.position = skeleton(self.arm, r.q).points[1 + self.arm.dof // 2]
                name = r.branch or f"solution {i + 1}"
                label.text = name if r.success else f"{name} ({r.status.value})"


def reach_colors(fraction: np.ndarray) -> np.ndarray:
    """(n, 3) uint8: red at 0 through yellow to green at 1; grey where nothing was reached."""
    f = np.clip(np.asarray(fraction, float), 0, 1)[:, None]
    low, mid, high = np.array(UNREACHED), np.array([230, 200, 40]), np.array(REACHED)
    rgb = np.where(f < 0.5, low + (mid - low) * 2 * f, mid + (high - mid) * (2 * f - 1))
    rgb[f[:, 0] == 0] = (160, 160, 160)
    return rgb.round().astype(np.uint8)


def _port_error(host: str, port: int) -> ViewerError:
    return ViewerError(
        f"port {port} is in use on {host} (another viewer, or another program): pass another "
        f"port (--port {port + 1}, or port={port + 1}), or port 0 for any free one",
        port=port,
    )


def _check_port(host: str, port: int) -> None:
    if port and not _port_free(host, port):
        raise _port_error(host, port)


def _port_free(host: str, port: int) -> bool:
    """Whether a server could listen on ``host:port`` now (SO_REUSEADDR, as servers bind)."""
    try:
        family = socket.getaddrinfo(host or None, port, type=socket.SOCK_STREAM)[0][0]
    except socket.gaierror:
        family = socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind((host, port))
        except OSError:
            return False
    return True


def _draw_obstacle(scene, name: str, shape: Shape) -> None:
    """One obstacle in the scene, translucent, at its placement in the base frame."""
    wxyz, position = wxyz_position(shape.T)
    if isinstance(shape, Box):
        scene.add_box(name, color=OBSTACLE, dimensions=shape.size, opacity=0.6,
                      wxyz=wxyz, position=position)  # fmt: skip
    elif isinstance(shape, Sphere):
        scene.add_icosphere(name, radius=shape.radius, color=OBSTACLE, opacity=0.6,
                            position=shape.center)  # fmt: skip
    else:
        if isinstance(shape, Cylinder):
            mesh = trimesh.creation.cylinder(radius=shape.radius, height=shape.length)
        elif isinstance(shape, Capsule):
            mesh = trimesh.creation.capsule(radius=shape.radius, height=shape.length)
        elif isinstance(shape, HalfSpace):  # a wide slab under its surface
            n = np.asarray(shape.normal, dtype=float)
            mesh = trimesh.creation.box((4.0, 4.0, 0.02))
            z = np.array([0.0, 0.0, 1.0])
            T = trimesh.geometry.align_vectors(z, n)
            T[:3, 3] = n * (shape.offset - 0.01)
            wxyz, position = wxyz_position(T)
        else:
            assert isinstance(shape, Mesh)
            mesh = trimesh.load(shape.path, force="mesh")
            mesh.apply_scale(shape.scale)
        scene.add_mesh_simple(name, mesh.vertices, mesh.faces, color=OBSTACLE, opacity=0.6,
                              wxyz=wxyz, position=position)  # fmt: skip
