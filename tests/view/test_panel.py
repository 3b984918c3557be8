"""The panel says what is drawn and solved: a continuous joint's angle beyond pi is wrapped
onto its [-pi, pi] slider (the same pose), not clipped to another angle; a preference the
viewer was opened with is named in the dropdown and can be chosen again."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import armik
from armik.view.panel import GIVEN

from ..conftest import arm

pytest.importorskip("viser")


def test_a_continuous_joint_beyond_pi_is_wrapped_on_its_slider():
    a = arm("scara")
    (k,) = [i for i in range(a.dof) if not np.isfinite(a.kinematics.lower[i])]
    with armik.view(a, port=0, open_browser=False) as viewer:
        q = a.middle.copy()
        q[k] = 4.0  # rad: past pi, as a solve unwrapped near a seed by pi returns it
        viewer.show(q)
        slid = viewer.panel.slider_q()
        assert -math.pi <= slid[k] <= math.pi
        assert math.cos(slid[k]) == pytest.approx(math.cos(4.0), abs=1e-12)
        assert math.sin(slid[k]) == pytest.approx(math.sin(4.0), abs=1e-12)
        drawn = a.fk(q)
        viewer._slid(slid)  # another slider touched: every slider's value is set
        moved = a.fk(viewer.q)
        assert np.allclose(moved.homogeneous, drawn.homogeneous, rtol=0.0, atol=1e-12)


def _choose(handle, value) -> None:
    """What a browser's choice does: the handle's callbacks with an event from a client."""
    event = SimpleNamespace(client=object(), target=SimpleNamespace(value=value))
    for callback in handle._impl.update_cb:
        callback(event)


def test_a_preference_of_the_viewers_own_is_shown_and_chosen_again():
    """A viewer opened with prefer=armik.Posture(...) says so in the dropdown, not "none";
    choosing it again after another solves with that posture once more."""
    a = arm("abb_irb120")
    posture = armik.Posture(a.middle)
    with armik.view(a, port=0, open_browser=False, prefer=posture) as viewer:
        assert viewer.panel.prefer.value == GIVEN and GIVEN in viewer.panel.prefer.options
        T = a.fk(a.random_q(3))
        r = viewer.set_target(T)
        assert viewer.panel._fields["score"].value == f"{r.extra['score']:.3g}"
        _choose(viewer.panel.prefer, "none")
        assert "prefer" not in viewer.options
        seed = viewer.q
        _choose(viewer.panel.prefer, GIVEN)
        assert viewer.options["prefer"] is posture
        want = a.solve(T, q0=seed, prefer=posture)  # re-solved from the arm shown
        assert np.array_equal(viewer.result.q, want.q)
        assert viewer.result.extra["score"] == want.extra["score"]
    with armik.view(a, port=0, open_browser=False, prefer="nearest") as viewer:
        assert viewer.panel.prefer.value == "nearest"
        assert GIVEN not in viewer.panel.prefer.options


def test_the_target_row_says_what_was_solved():
    """A drag says "dragged target"; choosing a solver or a preference solves the target
    again and says so, not that it was dragged."""
    a = arm("abb_irb120")
    with armik.view(a, port=0, open_browser=False) as viewer:
        viewer.set_target(a.fk(a.random_q(4)))
        assert viewer.panel.message.value == "target"
        _choose(viewer.panel.solver, "dls")
        assert viewer.result.solver == "dls"
        assert viewer.panel.message.value == "target, with solver 'dls'"
        _choose(viewer.panel.prefer, "nearest")
        assert viewer.panel.message.value == "target, with the preference chosen"
