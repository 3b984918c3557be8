"""armik.plot draws a stick figure into a PNG (or an axes) without a browser."""

from __future__ import annotations

import numpy as np
import pytest

import armik

from ..conftest import arm

pytest.importorskip("matplotlib")


def drawn_pixels(path) -> int:
    """Pixels that differ from the picture's most common colour (its background)."""
    from PIL import Image

    pixels = np.asarray(Image.open(path).convert("RGB")).reshape(-1, 3)
    colours, counts = np.unique(pixels, axis=0, return_counts=True)
    background = colours[counts.argmax()]
    return int((np.abs(pixels.astype(int) - background).max(axis=1) > 40).sum())


def test_plot_writes_a_png_with_the_arm_on_it(tmp_path):
    a = arm("panda")
    path = armik.plot(a, a.middle, tmp_path / "panda.png")
    assert path == tmp_path / "panda.png" and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert drawn_pixels(path) > 2000


def test_plot_of_a_solution_and_its_branches(tmp_path):
    a = arm("ur5")
    T = a.fk(a.random_q(1))
    solutions = a.solve_all(T, q0=a.middle)
    assert len(solutions) > 1
    lone = armik.plot(a, solutions[0], tmp_path / "one.png")
    every = armik.plot(a, solutions[0], tmp_path / "all.png", others=solutions[1:], target=T)
    assert drawn_pixels(every) > drawn_pixels(lone) > 2000


def test_plot_into_an_axes_and_bad_input(tmp_path):
    from matplotlib.figure import Figure

    a = arm("planar_2link")
    ax = Figure().add_subplot(projection="3d")
    assert armik.plot(a, [0.3, 0.4], ax=ax, title="two links") is ax
    assert ax.get_title() == "two links"
    with pytest.raises(armik.InputError, match="path"):
        armik.plot(a, [0.3, 0.4])
    with pytest.raises(armik.OptionError):
        armik.plot(a, [0.3, 0.4, 0.5], tmp_path / "x.png")


def test_plot_names_a_missing_folder_and_an_ax_that_is_not_3d(tmp_path):
    from matplotlib.figure import Figure

    a = arm("ur5")
    with pytest.raises(armik.InputError, match="folder .*missing.* does not exist"):
        armik.plot(a, a.middle, tmp_path / "missing" / "arm.png")
    for ax in (5, Figure().add_subplot()):  # a number, a 2D axes
        with pytest.raises(armik.InputError, match="ax must be a matplotlib 3D axes"):
            armik.plot(a, a.middle, ax=ax)


def test_plot_names_a_file_kind_matplotlib_does_not_write(tmp_path):
    a = arm("ur5")
    with pytest.raises(armik.InputError, match=r"matplotlib writes no \.xyz file.*name it \.png"):
        armik.plot(a, a.middle, tmp_path / "arm.xyz")
    assert not list(tmp_path.iterdir())
    assert armik.plot(a, a.middle, tmp_path / "arm.svg").stat().st_size > 1000


def test_plot_marks_a_task_list_target(tmp_path):
    """A task list (a form Arm.solve takes) is drawn: its Pose and Position tasks marked."""
    from matplotlib.figure import Figure

    a = arm("ur5")
    T = a.fk(a.random_q(1))
    tasks = [armik.Pose(T), armik.Position((0.3, 0.2, 0.3))]
    path = armik.plot(a, a.middle, tmp_path / "tasks.png", target=tasks)
    assert drawn_pixels(path) > drawn_pixels(armik.plot(a, a.middle, tmp_path / "arm.png"))

    def lines(target) -> int:
        ax = Figure().add_subplot(projection="3d")
        return len(armik.plot(a, a.middle, ax=ax, target=target).lines)

    bare = lines(None)
    assert lines(tasks) == bare + 4  # a frame's three dashed axes and a cross
    assert lines(T) == bare + 3 and lines([armik.Position((0.3, 0.2, 0.3))]) == bare + 1


def test_plot_names_a_folder_path_and_writes_the_png_it_returns(tmp_path):
    """A folder as the path is refused naming a file in it; a name without a suffix is
    written as name.png, the path returned; configurations that are not ones are refused
    naming which."""
    ur5 = armik.load("ur5")
    q = ur5.middle
    with pytest.raises(armik.InputError, match="is a folder"):
        armik.plot(ur5, q, tmp_path)
    out = armik.plot(ur5, q, tmp_path / "shot")
    assert out == tmp_path / "shot.png" and out.is_file()
    with pytest.raises(armik.OptionError, match=r"others\[0\]"):
        armik.plot(ur5, q, tmp_path / "o.png", others=[1, 2])


def test_plot_names_a_path_others_or_an_angle_it_cannot_take(tmp_path):
    """Each in an armik error naming it, where matplotlib or pathlib raised a TypeError."""
    ur5 = armik.load("ur5")
    q = ur5.middle
    bad = [({"path": 5}, "path must be a file name"),
           ({"others": 5}, "others must be a list"),
           ({"others": ur5.solve(ur5.fk(q))}, "others must be a list"),
           ({"elev": "a"}, "elev must be an angle"),
           ({"azim": float("nan")}, "azim must be an angle")]  # fmt: skip
    for kwargs, words in bad:
        where = kwargs.pop("path", tmp_path / "bad.png")
        with pytest.raises(armik.OptionError, match=words):
            armik.plot(ur5, q, where, **kwargs)
    assert not list(tmp_path.iterdir())  # refused before anything was written
    out = armik.plot(ur5, q, str(tmp_path / "ok.png"), others=np.array([q]), elev=np.float64(10))
    assert out.is_file()
