"""Structure detection: axis lines from the model and the closed-form classes."""

from __future__ import annotations

import re

import numpy as np
import pinocchio as pin
import pytest

import armik
from armik.errors import SolverError
from armik.model import geometry
from armik.solvers import registry
from armik.solvers.closed_form import families, spherical_wrist, three_parallel, two_intersecting

from ..analytic_urdfs import IRB120, IRB120_NEAR_MISS, MEETING_12, UR5, UR5_NEAR_MISS, six_r
from ..conftest import model, write_urdf


def load6(tmp_path, joints, **kw):
    return armik.load(write_urdf(tmp_path, six_r(joints, **kw)), base="world", tip="tool")


@pytest.mark.parametrize(
    "name, cls",
    [
        ("ur5", "three_parallel"),
        ("ur10", "three_parallel"),
        ("z1", "three_parallel"),
        ("abb_irb120", "spherical_wrist"),
        ("kinova", "spherical_wrist"),
        ("planar_2link", "planar"),
    ],
)
def test_bundled_arms_classify(name, cls):
    classes = families.classify(model(name))
    assert not isinstance(classes[cls], str)
    # the families that contain the class (a UR is also a three-parallel arm of any wrist
    # and an arm whose axes 5, 6 meet; a spherical wrist is also a general one)
    wider = {
        "three_parallel": {"three_parallel_general", "two_intersecting"},
        "spherical_wrist": {"spherical_general", "two_intersecting"},
        "planar": set(),
    }[cls]
    assert all(not isinstance(classes[k], str) for k in wider)
    others = [v for k, v in classes.items() if k != cls and k not in wider and k != "general_6r"]
    assert all(isinstance(v, str) and v for v in others)  # each says why not
    # the 2-D search takes every 6R arm, and says why not for the others
    assert isinstance(classes["general_6r"], str) == (name == "planar_2link")


def test_seven_dof_and_prismatic_refused_with_reason():
    c = families.classify(model("panda"))
    assert (
        c["spherical_wrist"]
        == c["three_parallel"]
        == ("the chain has 7 joints, this class needs 6")
    )
    assert "4 joints" in families.classify(model("scara"))["spherical_wrist"]


def test_axis_lines_are_the_jacobian_columns(rng):
    """Each axis line, moved by the joints before it, is the Jacobian's twist column."""
    a = model("ur5")
    ax = geometry.axis_lines(a)
    assert np.allclose(np.linalg.norm(ax.directions, axis=1), 1.0)
    J0 = a.jacobian(np.zeros(6), frame="base")
    tip = ax.tip_position
    for i in range(6):
        w, c = ax.directions[i], ax.points[i]
        assert np.allclose(J0[3:, i], w, atol=1e-12)
        assert np.allclose(J0[:3, i], np.cross(w, tip - c), atol=1e-12)


def test_chain_form_reproduces_pinocchio_fk(tmp_path, rng):
    from armik.solvers.closed_form.sixr import forward

    for a in (
        model("ur5"),
        model("abb_irb120"),
        load6(tmp_path, MEETING_12, mount_rpy="0.2 0 1").kinematics,
    ):
        geo = spherical_wrist.classify(a)
        if isinstance(geo, str):
            geo = three_parallel.classify(a)
        for _ in range(20):
            q = a.random_q(rng)
            R, p = forward(geo.h, geo.p, geo.R_tip0, q)
            T = a.fk(q)
            T_chain = pin.SE3(np.array(R).reshape(3, 3), np.array(p))
            assert np.linalg.norm(pin.log6(T.inverse() * T_chain).vector) < 1e-12


def test_meeting_12_variant(tmp_path):
    geo = spherical_wrist.classify(load6(tmp_path, MEETING_12).kinematics)
    assert geo.variant == "meeting_12" and "axes 1 and 2 meet" in geo.description


def test_near_misses_refused_with_measured_numbers(tmp_path):
    a = load6(tmp_path, IRB120_NEAR_MISS)
    why = spherical_wrist.classify(a.kinematics)
    assert isinstance(why, str) and "miss by 0.0005 m" in why
    # its axes 5 and 6 still meet: the search over q4 solves it exactly
    target = armik.parse_target(a.fk(np.zeros(6)))
    assert registry.choose("auto", a.kinematics, target, every=True).name == "elimination_6r"
    assert two_intersecting.classify(a.kinematics).kind == "two_intersecting"
    b = load6(tmp_path, UR5_NEAR_MISS)
    why = three_parallel.classify(b.kinematics)
    assert isinstance(why, str) and "axes 2 and 3 are 0.001 rad apart" in why
    with pytest.raises(SolverError, match="does not apply.*0.001 rad apart"):
        b.solve(b.fk(np.zeros(6)), solver="three_parallel")


def test_mount_and_tool_do_not_change_the_class(tmp_path):
    kw = dict(mount_xyz="1 2 3", mount_rpy="0.4 -1.2 2.0", tool_xyz="0 0.1 0.2", tool_rpy="1 2 3")
    assert (
        spherical_wrist.classify(load6(tmp_path, IRB120, **kw).kinematics).variant == "parallel_23"
    )
    assert three_parallel.classify(load6(tmp_path, UR5, **kw).kinematics).kind == "three_parallel"


def test_info_prints_the_classes(capsys):
    from armik.tools.cli import main

    assert main(["info", "abb_irb120"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"spherical_wrist +yes: spherical wrist at \[0.302, 0.0, 0.63\] m", out)
    assert re.search(r"three_parallel +no: axes 2, 3, 4 are not parallel", out)
    assert "auto -> spherical" in out
    main(["info", "ur5"])
    out = capsys.readouterr().out
    assert re.search(r"spherical_wrist +no: the last three axes do not meet in one point", out)
    assert "auto -> three_parallel" in out
    # one column for the verdicts, however long the class names
    structure = out.split("structure:\n")[1].split("family:")[0].splitlines()
    assert len(structure) == len(families.classify(model("ur5")))
    assert len({line.index(" yes: " if " yes: " in line else " no: ") for line in structure}) == 1


def test_compare_speed_table(capsys):
    from armik.tools.cli import main

    assert main(["compare", "--speed", "-n", "5"]) == 0
    out = capsys.readouterr().out
    assert "| ur5 | three_parallel | 5/5 |" in out and "| abb_irb120 | spherical | 5/5 |" in out


def _planar_urdf(origin: str, axis: str, along: str) -> str:
    """A 2-link planar arm: its first joint at ``origin``, both axes along ``axis``, the
    links along ``along`` (0.4 m, then a 0.3 m tool)."""
    link1 = " ".join(str(0.4 * float(c)) for c in along.split())
    tool = " ".join(str(0.3 * float(c)) for c in along.split())
    limit = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'
    return f"""<robot name="p"><link name="b"/><link name="l1"/><link name="l2"/><link name="t"/>
<joint name="a" type="revolute"><parent link="b"/><child link="l1"/><origin xyz="{origin}"/>
<axis xyz="{axis}"/>{limit}</joint>
<joint name="c" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="{link1}"/>
<axis xyz="{axis}"/>{limit}</joint>
<joint name="f" type="fixed"><parent link="l2"/><child link="t"/><origin xyz="{tool}"/></joint>
</robot>"""


@pytest.mark.parametrize(
    "origin, axis, along, kept",
    [
        ("0.2 0.1 0.3", "0 0 1", "1 0 0", (0, 1)),  # the x-y plane, mounted off the origin
        ("0.2 0.1 0.3", "0 0 -1", "1 0 0", (0, 1)),  # its axes the other way
        ("0 0 0.5", "0 1 0", "0 0 1", (0, 2)),  # the x-z plane
        ("0.1 0 0", "-1 0 0", "0 1 0", (1, 2)),  # the y-z plane
    ],
)
def test_a_planar_arms_2_vector_is_in_the_base_frame(origin, axis, along, kept):
    """(x, y) on a planar arm are the base frame's two axes across its plane, from the base's
    origin: the point asked is the point reached, wherever the first joint is mounted."""
    arm = armik.load(_planar_urdf(origin, axis, along), tip="t")
    p = arm.fk([0.4, 0.7]).translation
    r = arm.solve(p[list(kept)])
    assert r.success
    reached = arm.fk(r.q).translation
    assert np.allclose(reached, p, atol=1e-9)
    assert r.position_error == pytest.approx(np.linalg.norm(reached - p), abs=1e-12)


def test_a_tilted_planar_arms_2_vector_gives_the_base_x_and_y():
    """Axes along (0, -0.39, 0.92): the plane is along no two base axes. (x, y) are the base
    x and y of the plane's point, the third read off the plane: the tip reaches them."""
    axis = "0 -0.389418342 0.921060994"  # (0, -sin 0.4, cos 0.4)
    arm = armik.load(_planar_urdf("0.1 0.2 0.3", axis, "1 0 0"), tip="t")
    p = arm.fk([0.4, 0.7]).translation
    r = arm.solve(p[:2])
    assert r.success
    reached = arm.fk(r.q).translation
    assert np.allclose(reached, p, atol=1e-9)
    assert r.position_error == pytest.approx(np.linalg.norm(reached - p), abs=1e-12)
    b = arm.solve_batch(np.array([p[:2], p[:2]]))
    assert b.success.all() and np.allclose(arm.fk(b.q[0]).translation, p, atol=1e-9)


@pytest.mark.parametrize(
    "axes, along, words",
    [
        (("0 1 0", "0 1 0"), "1 0 0", "all axes along [0.0, 1.0, 0.0]"),  # plane normal -y
        (("0 0 -1", "0 0 -1"), "1 0 0", "all axes along [0.0, 0.0, -1.0]"),
        (("-1 0 0", "-1 0 0"), "0 1 0", "all axes along [-1.0, 0.0, 0.0]"),
        (
            ("0 1 0", "0 -1 0"),
            "1 0 0",
            "axes along [0.0, 1.0, 0.0] (c about the opposite direction)",
        ),
    ],
)
def test_a_planar_arms_axes_as_the_urdf_turns_them(tmp_path, capsys, axes, along, words):
    """armik info and the exported header say the joints' axis as the URDF gives it, not
    the normal the plane's coordinates chose (-y for an arm about +y, in the x-z plane)."""
    from armik.tools.cli import main

    text = _planar_urdf("0 0 0.1", axes[0], along)
    first = text.index("<axis")
    second = text.index("<axis", first + 1)
    text = text[:second] + text[second:].replace(axes[0], axes[1], 1)
    arm = armik.load(text, tip="t")
    plane = arm.kinematics.plane
    assert plane is not None and plane.axes_words(list(arm.joint_names)) == words
    path = tmp_path / "p.urdf"
    path.write_text(text)
    assert main(["info", str(path), "--tip", "t"]) == 0
    assert f"planar: {words}\n" in capsys.readouterr().out
    header = armik.export(arm, "p")["p_ik.h"]
    assert words.removeprefix("all ") in " ".join(header.replace("*", "").split())
