"""The viewer in a real browser: headless Debian Chromium renders viser's WebGL on the CPU
(SwiftShader). The arm is drawn, it moves on the page after ``set_target``, and the panel is
in the page. Every wait is for a condition, with a generous timeout; nothing is timed."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.view.panel import FIELDS

from ..conftest import arm
from . import browser

pytest.importorskip("viser")
pytest.importorskip("websockets.sync.client")
pytest.importorskip("PIL")
if browser.available():
    pytest.skip(browser.available(), allow_module_level=True)

WAIT = 180.0  # s: a first page load renders slowly on two busy cores


def view_region(image: np.ndarray) -> np.ndarray:
    """True on the pixels of the 3D view that no overlay covers: left of the panel (which
    floats over the right of the view) and outside viser's software-WebGL notice."""
    keep = np.zeros(image.shape[:2], bool)
    keep[:, : int(0.71 * image.shape[1])] = True
    keep[:170, :330] = False  # the notice, top left
    keep[-90:, :90] = False  # the orientation widget, bottom left
    return keep


def axis_pixels(image: np.ndarray) -> np.ndarray:
    """The stick figure's orange joint axes (stick.REVOLUTE_AXIS, lit and shaded)."""
    r, g, b = (image[..., k].astype(int) for k in range(3))
    orange = (r > 170) & (g > 70) & (g < 190) & (b < 90) & (r - g > 50)
    return orange & view_region(image)


def off_background(image: np.ndarray) -> np.ndarray:
    """Pixels of the view far from its commonest colour (the page's background)."""
    region = image[view_region(image)]
    colours, counts = np.unique(region, axis=0, return_counts=True)
    background = colours[counts.argmax()].astype(int)
    far = np.abs(image.astype(int) - background).max(axis=2) > 60
    return far & view_region(image)


@pytest.fixture(scope="module")
def page():
    a = arm("abb_irb120")  # no meshes: the stick figure, whose colours are known
    viewer = armik.view(a, port=0, open_browser=False)
    try:
        with browser.Browser() as chromium:
            chromium.open(viewer.url)
            yield viewer, chromium
    finally:
        viewer.close()


def settled(chromium) -> np.ndarray | None:
    """A screenshot once two in a row show the same axes (the scene has stopped changing)."""
    first = chromium.screenshot()
    second = chromium.screenshot()
    same = np.array_equal(axis_pixels(first), axis_pixels(second))
    return second if same and axis_pixels(second).sum() >= 50 else None


def test_the_arm_is_drawn(page):
    viewer, chromium = page
    image = browser.poll(lambda: settled(chromium), WAIT)
    assert image is not None, "no joint axis appeared in the 3D view"
    assert axis_pixels(image).sum() >= 50
    assert off_background(image).sum() >= 1000  # rods, balls, frames: not an empty view
    # The same scene without the arm: the pixels the arm covered go back to the background.

    def without_axes() -> np.ndarray | None:
        shot = chromium.screenshot()
        return shot if axis_pixels(shot).sum() < 10 else None

    viewer._arm_nodes.visible = False
    try:
        bare = browser.poll(without_axes, WAIT)
    finally:
        viewer._arm_nodes.visible = True
    assert bare is not None, "the arm did not disappear when hidden"
    arm_pixels = off_background(image) & ~off_background(bare)
    assert arm_pixels.sum() >= 500


def test_set_target_moves_the_arm_on_the_page(page):
    viewer, chromium = page
    a = viewer.arm
    viewer.show(a.middle)
    before = browser.poll(lambda: settled(chromium), WAIT)
    assert before is not None
    old = axis_pixels(before)
    q = a.middle + np.array([1.2, 0.5, -0.6, 0.8, 0.7, 0.3])
    r = viewer.set_target(a.fk(q))
    assert r.success and not np.allclose(r.q, a.middle)

    def moved() -> np.ndarray | None:
        image = chromium.screenshot()
        return image if (axis_pixels(image) ^ old).sum() >= 100 else None

    after = browser.poll(moved, WAIT)
    assert after is not None, "the arm's axes did not move on the page"
    new = axis_pixels(after)
    shift = np.abs(np.argwhere(new).mean(axis=0) - np.argwhere(old).mean(axis=0)).max()
    assert shift > 5  # pixels: the axes went elsewhere, not merely flickered
    ys, xs = np.nonzero(old)  # where the arm was: the picture changed there
    box = (slice(ys.min(), ys.max() + 1), slice(xs.min(), xs.max() + 1))
    changed = np.abs(after[box].astype(int) - before[box].astype(int)).max(axis=2) > 60
    assert changed.sum() >= 100


def test_the_panel_is_in_the_page(page):
    viewer, chromium = page

    def panel_text() -> str | None:
        text = chromium.evaluate("document.body.innerText") or ""
        return text if "IK answer" in text else None

    text = browser.poll(panel_text, WAIT)
    assert text, "the panel did not appear"
    labels = [label for label, _ in FIELDS] + ["reason", "all solutions", "joints (FK)"]
    labels += viewer.arm.joint_names
    missing = [label for label in labels if label not in text]
    assert not missing, f"the panel lacks {missing}"
    a = viewer.arm
    r = viewer.set_target(a.fk(a.random_q(5)))
    assert r.success

    def answer_shown() -> list | None:
        script = "Array.from(document.querySelectorAll('input, textarea')).map(e => e.value)"
        values = chromium.evaluate(script) or []
        return values if "converged" in values and r.branch in values else None

    shown = browser.poll(answer_shown, WAIT)
    assert shown, "the panel did not show the answer"


def test_a_region_and_the_paths_are_on_the_page(page):
    viewer, chromium = page
    a = viewer.arm
    q = a.middle + np.array([0.6, 0.3, -0.2, 0.5, 0.4, 0.2])
    viewer.show(q)
    before = browser.poll(lambda: settled(chromium), WAIT)
    assert before is not None
    p = a.fk(q).translation
    r = viewer.set_target([armik.Position(p, bounds=(0.08, 0.08, 0.08))])
    assert r.success and len(viewer.regions) == 1

    def tinted(image: np.ndarray) -> np.ndarray:
        """Pixels the translucent blue box turned bluer than they were."""
        now, was = image.astype(int), before.astype(int)
        bluer = (now[..., 2] - now[..., 0]) - (was[..., 2] - was[..., 0]) > 20
        return bluer & view_region(image)

    def boxed() -> np.ndarray | None:
        image = chromium.screenshot()
        return image if tinted(image).sum() >= 400 else None

    try:
        image = browser.poll(boxed, WAIT)
        assert image is not None, "the region's box did not appear"
        # around the box's centre on the page: the tinted pixels are one blob, not noise
        ys, xs = np.nonzero(tinted(image))
        assert np.ptp(ys) < image.shape[0] / 2 and np.ptp(xs) < image.shape[1] / 2
        line = [a.fk(q + 0.02 * k) for k in range(5)]
        viewer.play_paths({"follow": a.solve_path(line, q),
                           "global": a.solve_path(line, q, plan="global")})  # fmt: skip

        def paths_panel() -> str | None:
            text = chromium.evaluate("document.body.innerText") or ""
            return text if "waypoint" in text and "global" in text else None

        assert browser.poll(paths_panel, WAIT), "the paths' slider did not appear"
    finally:
        if viewer.paths is not None:
            viewer.paths.remove()
        viewer.set_target(a.fk(q))  # a plain pose: no region
        assert viewer.regions == []
