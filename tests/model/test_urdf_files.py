"""Reading URDF files as files (issue items 10, 13-15): deep trees refused before the
parser could crash, paths that are not files refused without blocking, the parser's reasons
named by element and value, xacro expanded or its absence said."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import armik
from armik.errors import URDFError
from armik.model import urdf as urdf_mod

from ..conftest import load_text, write_urdf
from ..urdf_cases import arm3, chain, joint

# -- 10. deep trees are refused before Pinocchio's parser could crash ---------------------


def deep_chain(n: int, moving_every: int = 1) -> str:
    """A chain n links deep, one joint in ``moving_every`` revolute, the others fixed."""
    return chain(
        *(
            joint(
                f"j{i}", f"l{i}", f"l{i + 1}", "revolute" if i % moving_every == 0 else "fixed",
                xyz="0 0 0.01",
            )
            for i in range(n)
        )
    )  # fmt: skip


def test_tree_deeper_than_the_limit_is_refused(tmp_path):
    with pytest.raises(URDFError, match=f"more than {urdf_mod.MAX_DEPTH} links deep"):
        urdf_mod.read_urdf_string(deep_chain(urdf_mod.MAX_DEPTH + 5))


def test_a_huge_file_of_fixed_links_after_the_tip_is_refused_by_the_depth_limit(tmp_path):
    # 45 000 fixed links hanging after a 2-link arm's tip (about 5 MB): refused by the depth
    # limit, naming where the tree gets too deep. Reading it took 28 s while the links'
    # names were checked against a list (quadratic); a set makes it linear, 1.8 s here.
    arm = chain(
        joint("j1", "base", "l1", xyz="0 0 0.1"),
        joint("j2", "l1", "tip", xyz="0.5 0 0"),
    )
    n = 45_000
    hanging = "".join(
        f'<link name="f{i}"/><joint name="fj{i}" type="fixed"><parent link="'
        f'{"tip" if i == 0 else f"f{i - 1}"}"/><child link="f{i}"/></joint>'
        for i in range(n)
    )
    text = arm.replace("</robot>", hanging + "</robot>")
    assert len(text) > 4_000_000
    with pytest.raises(URDFError, match=f"more than {urdf_mod.MAX_DEPTH} links deep.*'f9"):
        armik.load(write_urdf(tmp_path, text), tip="tip")


def test_deep_tree_parses_on_a_small_thread_stack(tmp_path):
    # 600 links crashed Pinocchio's parser on a 512 kB thread stack (measured at 300);
    # armik parses on a thread of its own with a large stack. In a subprocess: a crash
    # must not take the test run down.
    path = write_urdf(tmp_path, deep_chain(600, moving_every=3))  # 200 moving joints
    code = textwrap.dedent(
        f"""
        import threading
        from armik.model.urdf import read_urdf
        out = []
        threading.stack_size(512 * 1024)
        t = threading.Thread(target=lambda: out.append(read_urdf({str(path)!r})[0].njoints))
        t.start(); t.join()
        print(out[0])
        """
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr[-500:]
    assert done.stdout.strip() == "201"


def test_more_moving_joints_than_pinocchio_data_can_hold_are_refused_by_count(tmp_path):
    """A URDF of 300 moving joints, chain or tree: a ``URDFError`` naming the count and
    the fix, where Pinocchio's data (about 1.8 GB a copy) ended the process; a tree of as
    many links with the joints past the limit fixed still loads."""
    n = urdf_mod.MAX_MOVING + 44
    with pytest.raises(URDFError, match=f"has {n} moving joints.*up to 256.*fixed"):
        urdf_mod.read_urdf_string(deep_chain(n))
    star = chain(*(joint(f"j{i}", "l0", f"b{i}") for i in range(n)))
    with pytest.raises(URDFError, match=f"has {n} moving joints"):
        urdf_mod.read_urdf_string(star)
    model = urdf_mod.read_urdf_string(deep_chain(n, moving_every=2))[0]
    assert model.nv == (n + 1) // 2


# -- 13. files that are not files -------------------------------------------------------


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
def test_device_is_refused():
    with pytest.raises(URDFError, match="not a regular file"):
        armik.load("/dev/zero")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
def test_named_pipe_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "robot.urdf"
    os.mkfifo(fifo)
    with pytest.raises(URDFError, match="not a regular file"):
        armik.load(fifo)


def test_file_size_cap(tmp_path, monkeypatch):
    path = write_urdf(tmp_path, arm3())
    monkeypatch.setattr(urdf_mod, "MAX_FILE_BYTES", 100)
    with pytest.raises(URDFError, match="above the"):
        armik.load(path)


# -- 14. the parser's reasons, named ------------------------------------------------------


@pytest.mark.parametrize(
    "edit, words",
    [
        (lambda t: t.replace('name="j3"', 'name="j1"'), ["two joints named 'j1'", "unique"]),
        (
            lambda t: t.replace('<link name="l3"/>', '<link name="l3"/><link name="l3"/>'),
            ["two links named 'l3'"],
        ),
        (
            lambda t: t.replace(
                '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint><joint name="j3"',
                '</joint><joint name="j3"',
            ),
            ["joint 'j2'", "no <limit>", "continuous"],
        ),
        (lambda t: t.replace('xyz="0.25 0 0"', 'xyz="0.25 0 nan"'), ["joint 'j3'", "'nan'"]),
        (lambda t: t.replace('xyz="0.25 0 0"', 'xyz="0.25 0 1x"'), ["joint 'j3'", "'1x'"]),
        (lambda t: t.replace('xyz="0.25 0 0"', 'xyz="0.25 0"'), ["joint 'j3'", "3 numbers"]),
        (
            lambda t: t.replace('upper="2" effort="1"', 'upper="2"', 1),
            ["joint 'j1'", "no effort"],
        ),
        (lambda t: t.replace('xyz="0.2 0 0"', 'xyz="1e308 0 0"'), ["'tool_joint'", "1e308"]),
        (lambda t: t.replace('type="revolute"', 'type="hinge"', 1), ["'j1'", "'hinge'"]),
        (lambda t: t.replace('<child link="l2"/>', '<child link="l9"/>'), ["'l9'", "not a <link>"]),
        (
            lambda t: t.replace('<child link="l3"/>', '<child link="l2"/>'),
            ["'l2'", "child of two joints"],
        ),
    ],
)
def test_parser_errors_name_the_element_and_value(tmp_path, edit, words):
    text = edit(arm3())
    assert text != arm3()
    with pytest.raises(URDFError) as info:
        load_text(tmp_path, text)
    message = str(info.value)
    for word in words:
        assert word in message, message
    assert "not a valid URDF model" not in message and "\n" not in message


def test_default_namespace_is_read_like_urdfdom_reads_it(tmp_path):
    text = arm3().replace('<robot name="chain">', '<robot name="chain" xmlns="http://x.org/urdf">')
    assert load_text(tmp_path, text).dof == 3


def test_urdfdom_reason_is_captured_when_armik_does_not_know_it(tmp_path, capfd):
    text = arm3().replace('<robot name="chain">', "<robot>")  # urdfdom needs a robot name
    with pytest.raises(URDFError, match="Pinocchio could not build") as info:
        load_text(tmp_path, text)
    message = str(info.value)
    assert "No name given for the robot" in message and "\n" not in message
    assert "No name" not in capfd.readouterr().err  # taken from stderr, not left there


# -- 15. xacro ------------------------------------------------------------------------


XACRO = """<?xml version="1.0"?>
<robot name="xarm2" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:property name="len" value="0.4"/>
  <xacro:macro name="rev" params="name parent child x">
    <joint name="${name}" type="revolute"><parent link="${parent}"/><child link="${child}"/>
      <origin xyz="${x} 0 0"/><axis xyz="0 0 1"/>
      <limit lower="${-pi/2}" upper="${pi/2}" effort="1" velocity="1"/></joint>
  </xacro:macro>
  <link name="base"/><link name="a"/><link name="b"/>
  <xacro:rev name="j1" parent="base" child="a" x="0"/>
  <xacro:rev name="j2" parent="a" child="b" x="${len}"/>
</robot>
"""


def test_xacro_is_expanded_when_the_package_is_installed(tmp_path):
    a = load_text(tmp_path, XACRO, "arm.urdf.xacro")
    assert a.dof == 2 and a.name == "xarm2"
    np.testing.assert_allclose(a.upper, [np.pi / 2] * 2, atol=1e-12)
    np.testing.assert_allclose(a.fk([0, 0]).translation, [0.4, 0, 0], atol=1e-12)


def test_xacro_that_cannot_be_expanded_says_so(tmp_path):
    text = XACRO.replace('value="0.4"', 'value="${undefined_length}"')
    with pytest.raises(URDFError, match="could not expand it.*undefined_length.*xacro "):
        load_text(tmp_path, text, "arm.xacro")


def test_expressions_in_a_plain_urdf_are_expanded_only_when_needed(tmp_path):
    text = arm3().replace('xyz="0.25 0 0"', 'xyz="${0.5 / 2} 0 0"')
    a = load_text(tmp_path, text)  # fails as URDF ('${0.5' is no number): expanded
    np.testing.assert_allclose(a.fk([0, 0, 0]).translation, [0.45, 0, 0.4], atol=1e-12)
    # A stray ${...} where nobody reads it (a comment, as in example-robot-data's xArm 7)
    # leaves the file as it is.
    plain = arm3().replace("<link", "<!-- ${prefix}link --><link", 1)
    assert load_text(tmp_path, plain, "plain.urdf").dof == 3


def test_xacro_without_the_package_says_how_to_expand_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "xacro", None)  # import xacro -> ImportError
    with pytest.raises(URDFError, match="xacro file.*xacro .*> robot.urdf"):
        load_text(tmp_path, XACRO, "arm.urdf")  # detected from the text, not the suffix
    text = arm3().replace('xyz="0.25 0 0"', 'xyz="${0.5 / 2} 0 0"')
    with pytest.raises(URDFError, match="joint 'j3'.*if it is a xacro file"):
        load_text(tmp_path, text, "expr.urdf")
