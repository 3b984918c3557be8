"""Branch labels say what they mean: every word a closed form labels an answer with is
explained where docs/solvers.md explains the branches, and the words `swept` and `hold=` give
a 7R arm mean there what the page says, measured on Pinocchio's placements."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from armik.solvers.closed_form import planar2r, sixr, swept_7r

from ...conftest import arm

SOLVERS_PAGE = Path(__file__).resolve().parents[3] / "docs" / "solvers.md"


@pytest.mark.skipif(not SOLVERS_PAGE.exists(), reason="docs/ is not part of this tree (an sdist)")
def test_every_branch_word_is_explained_on_the_solvers_page():
    """The Panda's swept answers said wrist-front, shoulder-flip, ... which the page did not
    name: it listed the 6R words only."""
    labels = [*sixr.LABELS, *swept_7r._HELD_LABELS, *filter(None, planar2r._BRANCHES.values())]
    words = {word for label in labels for word in label.split("/")}
    text = SOLVERS_PAGE.read_text()
    branches = text[text.index("### Branches") : text.index("### Singular and unreachable")]
    missing = sorted(w for w in words if f"`{w}`" not in branches)
    assert not missing, f"branch words docs/solvers.md does not explain: {missing}"


@pytest.mark.parametrize(("name", "front_sign"), [("panda", 1.0), ("kuka_iiwa14", -1.0)])
def test_the_words_of_a_held_joint_7_mean_what_the_page_says(name, front_sign):
    """docs/solvers.md, Branches: S the shoulder centre, E on axis 4, W where axes 5 and 6
    meet; wrist-front by the side of the plane of axes 5 and 6 that S is on, elbow-up by
    the turn from S-E to E-W about axis 4, shoulder-no-flip q2 > 0."""
    a = arm(name)
    model, data = a.kinematics.model, a.kinematics.data
    ids = [model.getJointId(j) for j in a.joint_names]
    rng = np.random.default_rng(7)
    seen = set()
    for _ in range(8):
        q = a.random_q(rng)
        for r in a.solve_all(a.fk(q), hold={a.joint_names[6]: float(q[6])}):
            assert r.solver == "swept"
            if not r.success:  # the closest configuration: on a boundary (S in the plane)
                continue
            pin.computeJointJacobians(model, data, a.kinematics.to_pin(r.q))
            axis = {k + 1: data.J[3:, model.idx_vs[i]] for k, i in enumerate(ids)}
            S, E, W = (data.oMi[ids[k]].translation for k in (1, 3, 5))
            wrist, elbow, shoulder = r.branch.split("#")[0].split("/")
            side = np.cross(axis[5], axis[6]) @ (S - W) * front_sign
            assert (wrist == "wrist-front") == (side > 0), (r.branch, side)
            bend = np.cross(E - S, W - E) @ axis[4]
            assert (elbow == "elbow-up") == (bend > 0), (r.branch, bend)
            assert (shoulder == "shoulder-no-flip") == (r.q[1] > 0), (r.branch, r.q[1])
            if name == "panda":  # the elbow offsets put E on the line S-W at q4 = -0.467
                assert (elbow == "elbow-down") == (r.q[3] < -0.467), (r.branch, r.q[3])
            seen.add(r.branch.split("#")[0])
    assert len(seen) >= 4  # the checks met both words of each test
