"""The viewer from Python: set_target is arm.solve, play walks every waypoint, close frees
the port, the panel and ghosts follow the answers, bad input is refused with a fix."""

from __future__ import annotations

import dataclasses
import logging
import socket
import time
from types import SimpleNamespace

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.solve.reach import ReachMap
from armik.view.ghosts import BEST, GHOST_COLORS, UNSCORED, WORST
from armik.view.nodes import pose_of

from ..conftest import arm

pytest.importorskip("viser")

SAME = [f.name for f in dataclasses.fields(armik.IKResult) if f.name not in ("time", "extra")]


@pytest.fixture
def viewer():
    v = armik.view(arm("abb_irb120"), port=0, open_browser=False)
    yield v
    v.close()


def assert_same_answer(a: armik.IKResult, b: armik.IKResult) -> None:
    """Field for field, the time of the call aside."""
    for name in SAME:
        x, y = getattr(a, name), getattr(b, name)
        if isinstance(x, np.ndarray):
            assert np.array_equal(x, y), name
        else:
            assert x == y, name


def test_set_target_returns_what_arm_solve_returns(viewer):
    a = viewer.arm
    start = a.random_q(1)
    viewer.show(start)
    T = a.fk(a.random_q(2))
    r = viewer.set_target(T)  # from the configuration shown
    assert r.success
    assert_same_answer(r, a.solve(T, q0=start, solver="auto"))
    assert np.array_equal(viewer.q, r.q) and viewer.result is r
    q0 = a.random_q(4)
    assert_same_answer(viewer.set_target(T.homogeneous, q0=q0), a.solve(T.homogeneous, q0=q0))


def test_set_target_uses_the_viewers_solver_and_options():
    a = arm("abb_irb120")
    with armik.view(a, port=0, open_browser=False, solver="dls", iteration_budget=400) as v:
        T = a.fk(a.random_q(6))
        r = v.set_target(T)
        assert r.solver == "dls"
        assert_same_answer(r, a.solve(T, q0=a.middle, solver="dls", iteration_budget=400))


def test_a_failed_target_leaves_the_arm_where_it_was(viewer):
    before = viewer.q
    r = viewer.set_target(pin.SE3(np.eye(3), np.array([5.0, 0, 0])))
    assert not r.success and r.status == "unreachable"
    assert np.array_equal(viewer.q, before)
    assert viewer.panel.reason.value == r.reason
    assert viewer.panel._fields["status"].value == "unreachable"


def test_the_panel_shows_the_answer_and_the_sliders_the_joints(viewer):
    a = viewer.arm
    r = viewer.set_target(a.fk(a.random_q(7)))
    fields = {attr: h.value for attr, h in viewer.panel._fields.items()}
    assert fields["status"] == "converged" and fields["solver"] == r.solver
    assert fields["branch"] == r.branch and fields["iterations"] == str(r.iterations)
    assert np.allclose(viewer.panel.slider_q(), r.q)
    q = a.random_q(8)
    viewer.show(q)
    assert np.allclose(viewer.panel.slider_q(), q) and np.array_equal(viewer.q, q)


def test_dragging_the_gizmo_solves_from_the_configuration_shown(viewer):
    a = viewer.arm
    start = a.random_q(9)
    viewer.show(start)
    T = a.fk(a.random_q(10))
    x, y, z, w = pin.Quaternion(T.rotation).coeffs()
    viewer._dragged(SimpleNamespace(wxyz=(w, x, y, z), position=tuple(T.translation)))
    expected = a.solve(pose_of((w, x, y, z), T.translation), q0=start)
    assert_same_answer(viewer.result, expected)
    assert np.array_equal(viewer.q, expected.q)


def test_ghosts_are_every_solution_of_solve_all(viewer):
    a = viewer.arm
    T = a.fk(a.random_q(11))
    viewer.set_target(T)
    q_shown = viewer.q
    viewer._toggled_ghosts(True)
    expected = a.solve_all(T, q0=q_shown)
    assert [r.branch for r in viewer.solutions] == [r.branch for r in expected]
    assert len(expected) > 1
    for got, want in zip(viewer.solutions, expected):
        assert np.array_equal(got.q, want.q)
    labels = [label.text for _, label in viewer._ghosts.nodes if label.visible]
    assert labels == [r.branch if r.success else f"{r.branch} ({r.status.value})" for r in expected]
    viewer._toggled_ghosts(False)
    assert viewer.solutions == [] and not any(n.visible for n, _ in viewer._ghosts.nodes)


def test_with_a_preference_the_ghosts_are_coloured_by_score(viewer):
    """solve_all(prefer=) ranks the branches best first: the first ghost is the best's
    colour, the last the worst's, each label carries the score."""
    a = viewer.arm
    T = a.fk(a.random_q(12))  # 8 branches within the limits
    viewer.set_target(T)
    viewer._chose_prefer("manipulability")
    viewer._toggled_ghosts(True)
    expected = a.solve_all(T, q0=viewer.q, prefer="manipulability")
    scores = [r.extra["score"] for r in expected if r.success]
    assert len(scores) > 2 and scores == sorted(scores) and scores[0] < scores[-1]
    assert [r.branch for r in viewer.solutions] == [r.branch for r in expected]
    shown = [(nodes, label) for nodes, label in viewer._ghosts.nodes if label.visible]
    colors = [tuple(nodes._solid[0].color) for nodes, _ in shown]
    ok = [c for c, r in zip(colors, expected) if r.success]
    assert ok[0] == BEST and ok[-1] == WORST
    assert all(c == UNSCORED for c, r in zip(colors, expected) if not r.success)
    for (_, label), r in zip(shown, expected):
        if r.success:
            assert label.text == f"{r.branch}: score {r.extra['score']:.4g}"
    viewer._chose_prefer("none")  # back to the branches' own colours
    viewer._toggled_ghosts(False)
    viewer._toggled_ghosts(True)
    assert tuple(viewer._ghosts.nodes[0][0]._solid[0].color) == GHOST_COLORS[0]


def test_play_walks_every_waypoint_and_marks_the_failed_ones(viewer, monkeypatch):
    a = viewer.arm
    q = a.random_q(12)
    T = a.fk(q)
    line = [pin.SE3(T.rotation, T.translation + [0, 0.005 * k, 0]) for k in range(12)]
    line[7] = pin.SE3(T.rotation, np.array([3.0, 0, 0]))  # out of reach: a failed waypoint
    path = a.solve_path(line, q)
    assert not path.success.all() and path.success.any()
    shown = []
    show = viewer.show

    def recording(q, failed=False):
        shown.append((q, failed))
        show(q, failed=failed)

    monkeypatch.setattr(viewer, "show", recording)
    viewer.play(path, fps=1000)
    assert len(shown) == len(path) == len(line)
    for i, (q_i, failed) in enumerate(shown):
        assert np.array_equal(q_i, path.q[i]) and failed == (not path.success[i])
    assert np.array_equal(viewer.q, path.q[-1])
    assert viewer.panel.message.value.startswith(f"waypoint {len(line)} of {len(line)}")


def test_close_frees_the_port():
    v = armik.view(arm("planar_2link"), port=0, open_browser=False)
    port = v.port
    assert port > 0 and v.url == f"http://127.0.0.1:{port}"
    v.close()
    with socket.socket() as s:  # no SO_REUSEADDR: the port is free, not merely lingering
        s.bind(("127.0.0.1", port))
    v.close()  # twice is harmless


def test_a_stray_connection_is_one_line_not_a_traceback(caplog):
    """A plain TCP probe (connect, send nothing or no HTTP, close): websockets fails the
    opening handshake; armik says so in one line and the viewer goes on serving."""
    caplog.set_level(logging.INFO)
    with armik.view(arm("planar_2link"), port=0, open_browser=False) as v:
        for payload in (b"", b"hello\r\n\r\n"):
            with socket.create_connection(("127.0.0.1", v.port)) as s:
                s.sendall(payload)
        deadline = time.monotonic() + 30.0  # the server's thread logs it when it reads
        while len(_stray(caplog)) < 2 and time.monotonic() < deadline:
            time.sleep(0.02)
        with socket.create_connection(("127.0.0.1", v.port)) as s:  # still serving
            s.sendall(b"GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")
            assert s.recv(64).startswith(b"HTTP/1.1 200")
    said = _stray(caplog)
    assert len(said) == 2 and all(r.levelno == logging.WARNING for r in said)
    assert "while reading HTTP request line" in said[0].getMessage()
    assert "invalid HTTP request line: hello" in said[1].getMessage()
    assert all(r.exc_info is None and "\n" not in r.getMessage() for r in said)
    assert not [r for r in caplog.records if r.name.startswith("websockets") and r.exc_info]


def _stray(caplog) -> list[logging.LogRecord]:
    return [r for r in caplog.records if "no valid HTTP request" in r.getMessage()]


def test_a_port_in_use_is_one_line_naming_the_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        port = s.getsockname()[1]
        with pytest.raises(armik.ViewerError) as info:
            armik.view(arm("planar_2link"), port=port, open_browser=False)
    message = str(info.value)
    assert f"port {port} is in use" in message and "--port" in message and "\n" not in message
    assert info.value.port == port


@pytest.mark.parametrize("host", ["192.0.2.1", "no such host.invalid"])
def test_a_host_it_cannot_serve_on_is_one_line_naming_it(host):
    """An address of another machine (192.0.2.1: TEST-NET, nobody's) or a name that does not
    resolve: refused before viser's server starts, which would wait on it for ever."""
    from armik.view.server import check_host

    with pytest.raises(armik.ViewerError) as info:
        check_host(host)
    message = str(info.value)
    assert f"host {host!r}" in message and "--host 127.0.0.1" in message and "\n" not in message
    check_host("127.0.0.1")  # this machine's: nothing said


def test_an_ipv6_host_is_bracketed_in_the_url():
    with armik.view(arm("planar_2link"), port=0, host="::1", open_browser=False) as v:
        assert v.url == f"http://[::1]:{v.port}"


def test_show_reach_draws_the_reached_voxels(viewer):
    xs = ys = zs = np.array([-0.1, 0.0, 0.1])
    fraction = np.full((3, 3, 3), np.nan)
    fraction[1, 1, :] = [0.0, 0.5, 1.0]
    m = ReachMap(arm="abb_irb120", xs=xs, ys=ys, zs=zs, fraction=fraction, orientations=2,
                 resolution=0.1, solver="spherical", time=0.0, solves=6)  # fmt: skip
    assert viewer.show_reach(m) == 2
    assert viewer.show_reach(m, unreached=True) == 3


def test_obstacles_are_drawn_and_kept(viewer):
    shapes = viewer.add_obstacles(
        [armik.Box(size=(0.2, 0.2, 0.2), pose=(0.5, 0, 0.3)),
         {"type": "sphere", "radius": 0.1, "center": [0.3, 0.3, 0.5]},
         armik.Cylinder(0.05, 0.4, pose=(0.3, -0.3, 0.2)),
         armik.Capsule(0.05, 0.3, pose=(0.3, 0.3, 0.2)),
         armik.HalfSpace((0, 0, 1), -0.5)]
    )  # fmt: skip
    assert shapes == viewer.obstacles and isinstance(shapes[1], armik.Sphere)
    with pytest.raises(armik.InputError, match="list of shapes"):
        viewer.add_obstacles(armik.Sphere(0.1))
    with pytest.raises(armik.InputError, match="radius"):
        viewer.add_obstacles([{"type": "sphere", "radius": -1}])
    assert viewer.add_obstacles(None) == shapes  # None, as obstacles=None: nothing added


def test_obstacles_on_an_arm_without_collision_geometry_refused_at_once():
    a = arm("planar_2link")  # no <collision> in its URDF
    with pytest.raises(armik.CollisionError, match="no <collision> geometry"):
        armik.view(a, port=0, open_browser=False, obstacles=[armik.Sphere(0.1, (0.5, 0, 0))])
    with pytest.raises(armik.CollisionError, match="no <collision> geometry"):
        armik.view(a, port=0, open_browser=False, self_collision=True)


def test_a_host_that_is_no_string_is_named():
    from armik.view.server import check_host

    with pytest.raises(armik.ViewerError, match="host must be a name or an address.*got 5"):
        check_host(5)  # type: ignore[arg-type]


def test_bad_input_is_refused_with_the_fix(viewer):
    a = viewer.arm
    with pytest.raises(armik.OptionError, match="fps"):
        viewer.play(a.solve_batch(np.array([a.fk(a.middle).homogeneous])), fps=0)
    with pytest.raises(armik.InputError, match="BatchResult"):
        viewer.play([a.middle])
    with pytest.raises(armik.OptionError):
        viewer.show([0.0, 1.0])
    with pytest.raises(armik.OptionError, match="port"):
        armik.view(a, port=-1, open_browser=False)
    with pytest.raises(armik.SolverError, match="unknown solver"):
        armik.view(a, port=0, open_browser=False, solver="nope")
    with pytest.raises(armik.InputError, match="armik.load"):
        armik.view("abb_irb120", port=0, open_browser=False)
    with pytest.raises(armik.OptionError, match=r"^q must have 6 values") as caught:
        armik.view(a, port=0, open_browser=False, q=[0.0, 1.0])  # the keyword, not q0
    assert caught.value.option == "q"


def test_the_panel_prefers_and_shows_the_score():
    """A viewer opened with prefer= solves as arm.solve with it, the panel shows the score,
    and choosing another preference re-solves the target."""
    a = arm("abb_irb120")
    with armik.view(a, port=0, open_browser=False, prefer="manipulability") as v:
        T = a.fk(a.random_q(9))
        r = v.set_target(T)
        assert_same_answer(r, a.solve(T, q0=a.middle, prefer="manipulability"))
        assert v.panel._fields["score"].value == f"{r.extra['score']:.3g}"
        assert v.panel.prefer.value == "manipulability"
        v._chose_prefer("limits")
        assert v.result.extra["score"] == a.solve(T, q0=r.q, prefer="limits").extra["score"]
        v._chose_prefer("none")
        assert "prefer" not in v.options and v.panel._fields["score"].value == "-"
    with pytest.raises(armik.InputError, match="prefer must be"):
        armik.view(a, port=0, open_browser=False, prefer="best")
