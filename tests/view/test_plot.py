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
