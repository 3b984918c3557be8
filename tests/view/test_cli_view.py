"""``armik view``: it serves the page, stops cleanly on Ctrl-C (exit 0, no traceback), and
a port in use is one line naming the port."""

from __future__ import annotations

import os
import queue
import re
import signal
import socket
import subprocess
import sys
import threading
import urllib.request

import pytest

pytest.importorskip("viser")

COMMAND = [sys.executable, "-m", "armik.tools.cli", "view"]


def start(*args: str) -> tuple[subprocess.Popen, queue.Queue]:
    proc = subprocess.Popen(
        [*COMMAND, *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONFAULTHANDLER": "1"},  # SIGABRT dumps every thread's stack
        # Ctrl-C as a terminal gives it: a run started in the background (nohup, `&`)
        # ignores SIGINT, and the child would inherit that
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    lines: queue.Queue = queue.Queue()
    threading.Thread(target=lambda: [lines.put(x) for x in proc.stdout], daemon=True).start()
    return proc, lines


def test_view_serves_until_ctrl_c_and_exits_cleanly():
    proc, lines = start("planar_2link", "--port", "0", "--no-browser")
    try:
        line = lines.get(timeout=300)  # the first line once the viewer is up
        url = re.search(r"http://\S+", line)
        assert url, line
        with urllib.request.urlopen(url.group(0), timeout=60) as page:
            assert page.status == 200 and b"<html" in page.read().lower()
        proc.send_signal(signal.SIGINT)
        try:
            code = proc.wait(timeout=120)
        except subprocess.TimeoutExpired:  # say where it hangs
            proc.send_signal(signal.SIGABRT)
            proc.wait()
            pytest.fail(f"no exit 120 s after Ctrl-C; stacks:\n{proc.stderr.read()[-8000:]}")
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    stderr = proc.stderr.read()
    assert code == 0, stderr
    assert "Traceback" not in stderr and "viewer stopped" in stderr


def test_view_on_a_port_in_use_is_one_line_naming_it():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        port = s.getsockname()[1]
        proc = subprocess.run(
            [*COMMAND, "planar_2link", "--port", str(port), "--no-browser"],
            capture_output=True,
            text=True,
            timeout=300,
        )
    assert proc.returncode == 2
    (line,) = proc.stderr.strip().splitlines()
    assert line.startswith("armik: error: port") and str(port) in line and "--port" in line


def test_view_on_a_host_of_another_machine_is_one_line_naming_it():
    """192.0.2.1 (TEST-NET) is no address of this machine: exit 2 with one line, where
    viser's server waited for ever."""
    proc = subprocess.run(
        [*COMMAND, "planar_2link", "--host", "192.0.2.1", "--port", "0", "--no-browser"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2, proc.stderr
    (line,) = proc.stderr.strip().splitlines()
    assert line.startswith("armik: error: cannot serve on host '192.0.2.1'") and "--host" in line


def test_view_obstacles_on_an_arm_without_collision_geometry_exit_2(tmp_path):
    """Refused before serving, as the docs say, where the viewer served and refused every
    drag."""
    shapes = tmp_path / "obstacles.json"
    shapes.write_text('[{"type": "sphere", "radius": 0.1, "center": [0.5, 0, 0]}]')
    proc = subprocess.run(
        [*COMMAND, "planar_2link", "--obstacles", str(shapes), "--port", "0", "--no-browser"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2, proc.stdout + proc.stderr
    (line,) = proc.stderr.strip().splitlines()
    assert "has no <collision> geometry" in line and "leave out --obstacles" in line, line


def test_view_reads_obstacles_from_a_json_file(tmp_path):
    bad = tmp_path / "obstacles.json"
    bad.write_text('[{"type": "cone"}]')
    proc = subprocess.run(
        [*COMMAND, "planar_2link", "--port", "0", "--no-browser", "--obstacles", str(bad)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2
    assert "obstacle 0: 'type' must be one of 'box', 'sphere'" in proc.stderr


def test_view_obstacles_are_drawn_and_avoided(tmp_path, monkeypatch):
    """``--obstacles`` is in the viewer's solve options, as ``armik.view(arm,
    obstacles=...)`` puts it: a drag whose plain answer hits the box is solved clear of it."""
    import json

    import numpy as np

    import armik
    from armik.constraints.shapes_file import read_shapes
    from armik.tools.cli.main import main
    from armik.view.viewer import Viewer

    shapes = [
        {"type": "halfspace", "normal": [0, 0, 1], "offset": 0},
        {"type": "box", "size": [0.2, 0.2, 0.3], "position": [0.45, -0.3, 0.15]},
    ]
    path = tmp_path / "obstacles.json"
    path.write_text(json.dumps(shapes))
    scene = read_shapes(str(path))
    served: list[Viewer] = []
    monkeypatch.setattr(Viewer, "wait", lambda self: served.append(self))
    monkeypatch.setattr(Viewer, "close", lambda self: None)  # closed below, once read
    assert main(["view", "ur5", "--obstacles", str(path), "--port", "0", "--no-browser"]) == 0
    (viewer,) = served
    try:
        assert len(viewer.obstacles) == 2 and viewer.options["obstacles"] == scene
        ur5 = armik.load("ur5")
        rng = np.random.default_rng(3)
        for _ in range(200):  # a target reached clear of the scene that plain solve hits
            q = ur5.random_q(rng)
            T = ur5.fk(q)
            if not ur5.in_collision(q, scene) and ur5.in_collision(
                ur5.solve(T, q0=ur5.middle).q, scene
            ):
                break
        else:
            pytest.fail("no target whose plain answer collides")
        r = viewer.set_target(T, q0=ur5.middle)
        assert r.success and not ur5.in_collision(r.q, scene)
    finally:
        monkeypatch.undo()
        viewer.close()


def test_view_takes_lock_as_the_other_commands_do(tmp_path, monkeypatch):
    """``--lock`` was refused by ``armik view`` alone of the commands that load an arm."""
    import armik
    from armik.tools.cli.main import main
    from armik.view.viewer import Viewer

    from ..test_arms import dual_irb120

    served: list[Viewer] = []
    monkeypatch.setattr(Viewer, "wait", lambda self: served.append(self))
    lock = ["--lock", "panda_joint7=0.3"]
    assert main(["view", "panda", *lock, "--port", "0", "--no-browser"]) == 0
    urdf = tmp_path / "cell.urdf"
    urdf.write_text(dual_irb120())
    tips = ["--tips", "l_tool0", "r_tool0", "--lock", "l_joint_6=0.5"]
    assert main(["view", str(urdf), *tips, "--port", "0", "--no-browser"]) == 0
    one, two = served
    assert one.robot.dof == 6 and one.robot.source.locked["panda_joint7"] == 0.3
    assert "panda_joint7" not in one.robot.joint_names
    cell = armik.load(urdf, tips=["l_tool0", "r_tool0"], locked={"l_joint_6": 0.5})
    assert "l_joint_6" not in cell.joint_names
    assert two.robot.source.joint_names == cell.joint_names
