"""The command line's habits (issue items 2, 5, 14, 16, 19): one line per error, exit 2,
no traceback; closed pipes; negative numbers; the frame tree."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from armik.tools.cli import main
from tests.tools.cli_run import run

from ..conftest import arm, write_urdf
from ..urdf_cases import arm3, chain, joint


def parse_error(capsys, *argv) -> tuple[int, str]:
    with pytest.raises(SystemExit) as box:
        main(list(argv))
    return box.value.code, capsys.readouterr().err


def test_info_frames_prints_the_tree(capsys):
    code, out, _ = run(capsys, "info", "ur5", "--frames")
    assert code == 0
    assert "[revolute] wrist_3_joint -> wrist_3_link" in out
    assert "-> tool0" in out and "-> ee_link" in out
    lines = out.splitlines()
    assert any(line.endswith("-> tool0  (the tip)") for line in lines)
    tool0 = next(i for i, line in enumerate(lines) if "-> tool0" in line)
    wrist3 = next(i for i, line in enumerate(lines) if line.endswith("-> wrist_3_link"))
    indent = len(lines[wrist3]) - len(lines[wrist3].lstrip(" |`-"))
    assert tool0 > wrist3 and len(lines[tool0]) - len(lines[tool0].lstrip(" |`-")) > indent


def test_info_says_how_the_urdf_was_read(capsys, tmp_path):
    text = arm3(
        axis2="0 0 2",
        jtype2="prismatic",
        limit2='<limit lower="0" upper="0" effort="1" velocity="1"/>',
    )
    path = write_urdf(tmp_path, text)
    code, out, err = run(capsys, "info", str(path))
    assert code == 0
    assert "tip: the leaf at the end of the longest chain (3 moving joints)" in out
    assert "note: joint 'j2': axis norm 2 read as the unit axis" in out
    assert "note: joint 'j2' has lower = upper = 0" in out
    warnings = [line for line in err.splitlines() if line.startswith("armik: warning:")]
    assert len(warnings) == 2 and "Traceback" not in err
    assert all("'j2'" in line for line in warnings)


def test_bad_urdf_is_one_line_exit_2(capsys, tmp_path):
    path = write_urdf(tmp_path, arm3().replace('name="j3"', 'name="j1"'))
    code, out, err = run(capsys, "info", str(path))
    assert code == 2 and "two joints named 'j1'" in err
    assert len(err.strip().splitlines()) == 1


def test_closed_pipe_ends_quietly(tmp_path):
    read_end, write_end = os.pipe()
    os.close(read_end)  # the reader is gone before armik writes (armik info panda | true)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    code = (
        "import sys; from armik.tools.cli import main; "
        "sys.exit(main(['info', 'panda', '--frames']))"
    )
    try:
        done = subprocess.run(
            [sys.executable, "-c", code], stdout=write_end, stderr=subprocess.PIPE, env=env
        )
    finally:
        os.close(write_end)
    err = done.stderr.decode()
    assert "Traceback" not in err and "BrokenPipe" not in err, err
    assert done.returncode == 1


def test_negative_numbers_in_exponent_form(capsys):
    code, out, err = run(capsys, "solve", "ur5", "--xyz", "-1e-3", "0.3", "0.4", "--json")
    assert code == 0, err
    code, out, err = run(
        capsys, "solve", "ur5", "--xyz", "0.3", "-2E-1", "0.4", "--rpy", "-3.1e0", "0", "0"
    )
    assert code in (0, 1) and "error" not in err


def test_usage_hint_names_the_command_once(capsys):
    code, err = parse_error(capsys, "--bogus")
    assert code == 2 and "'armik --help'" in err and "armik armik" not in err
    code, err = parse_error(capsys, "solve", "ur5")
    assert code == 2 and "'armik solve --help'" in err
    # a flag the command does not take: that command's help, where the flags are
    for argv, extra in [
        (["info", "ur5", "--tip-offset", "0", "0", "1"], "--tip-offset 0 0 1"),
        (["robots", "extra"], "extra"),
    ]:
        code, err = parse_error(capsys, *argv)
        hint = f"(see 'armik {argv[0]} --help')"
        assert code == 2 and f"unrecognized arguments: {extra} {hint}" in err
        assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("n", ["0", "-3", "x"])
def test_compare_needs_one_target_or_more(capsys, n):
    code, err = parse_error(capsys, "compare", "-n", n)
    assert code == 2 and "whole number >= 1" in err and len(err.strip().splitlines()) == 1


def test_compare_plot_folder_and_speed_refused_in_one_line(capsys, tmp_path):
    """--plot on a file: one line naming the flag, not OSError's words alone; --plot with
    --speed, which draws nothing: refused, not ignored."""
    file = tmp_path / "figures"
    file.write_text("")
    code, _, err = run(capsys, "compare", "-n", "1", "--plot", str(file))
    assert code == 2 and err.startswith(f"armik: error: --plot {str(file)!r} cannot be")
    code, _, err = run(capsys, "compare", "--speed", "--plot", str(tmp_path / "out"))
    assert code == 2 and "give --speed or --plot" in err and not (tmp_path / "out").exists()
    assert len(err.strip().splitlines()) == 1


def test_compare_json_is_strict_json_with_nothing_reachable(capsys):
    """A figure with nothing to measure (no reachable target among a small ``-n``: a median
    of none) is null: ``NaN`` is no JSON, and strict readers refuse the whole output."""

    def refuse(constant):
        raise ValueError(f"{constant} is no JSON")

    code, out, _ = run(capsys, "compare", "-n", "3", "--json")
    assert code == 0
    rows = json.loads(out, parse_constant=refuse)["rows"]
    assert all(r["pos_err_median"] is None for r in rows if r["reachable"] == 0)
    from armik.tools.cli.studies import as_json

    got = json.loads(as_json({"a": [float("nan"), 1.5, float("inf")], "b": (2, -math.inf)}))
    assert got == {"a": [None, 1.5, None], "b": [2, None]}


def test_all_prints_the_call_time_once(capsys):
    code, out, _ = run(capsys, "solve", "planar_2link", "--xyz", "1.2", "0.5", "0", "--all")
    assert code == 0
    assert out.count("ms") == 1 and "for the call (2 solutions)" in out
    # a command's one solve is its solver's first: loading its code counts, or it ran as
    # Python while a helper compiled it; not the warm time armik bench measures
    assert "its solver's first call in this process, not a warm call's time" in out


def test_max_restarts_zero_names_the_real_cause():
    panda = arm("panda")
    T = panda.fk(np.array([2.0, 1.2, -2.0, -0.5, 2.0, 3.0, -2.0]))
    r = panda.solve(T, q0=panda.middle, max_restarts=0, max_iterations=3)
    assert not r.success
    assert "max_restarts=0" in r.reason and "time budget" not in r.reason


def test_default_tip_choice_is_shown(capsys, tmp_path):
    text = chain(
        joint("j1", "base", "l1"),
        joint("j2", "l1", "l2", xyz="0.3 0 0"),
        joint("flange", "l2", "tool0", jtype="fixed", xyz="0.1 0 0"),
        joint("cam", "l1", "camera", jtype="fixed"),
    )
    code, out, _ = run(capsys, "info", str(write_urdf(tmp_path, text)))
    assert code == 0 and "to 'tool0'" in out and "REP 199" in out


def test_unwritable_output_is_one_line(capsys, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    code, out, err = run(capsys, "compare", "-n", "2", "--plot", str(blocker / "sub"))
    assert code == 2 and "armik: error:" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def _two_leaves(tmp_path):
    from ..conftest import two_link_urdf

    text = (
        two_link_urdf()
        .replace('<link name="tip"/>', '<link name="tip"/><link name="cam"/>')
        .replace(
            "</robot>",
            '<joint name="c" type="continuous"><parent link="l1"/><child link="cam"/></joint>'
            "</robot>",
        )
    )
    return str(write_urdf(tmp_path, text))


def test_info_frames_without_a_tip_lists_the_frames_to_choose_from(capsys, tmp_path):
    path = _two_leaves(tmp_path)
    code, out, err = run(capsys, "info", path, "--frames")
    assert code == 0 and not err
    assert "no tip chosen" in out and "pass --tip one of 'cam', 'tip'" in out
    assert "-> cam  (leaf: a tip to choose, --tip)" in out
    assert "-> tip  (leaf: a tip to choose, --tip)" in out
    code, out, err = run(capsys, "info", path)  # without --frames it is an error
    assert code == 2 and "pass --tip one of" in err and "tip=" not in err
    code, out, _ = run(capsys, "info", path, "--tip", "cam", "--frames")
    assert code == 0 and "-> cam  (the tip)" in out and "-> tip  (leaf)" in out


def test_bench_takes_the_tip_its_error_asks_for(capsys, tmp_path):
    path = _two_leaves(tmp_path)
    code, _, err = run(capsys, "bench", "--arms", path, "--solvers", "dls", "-n", "2")
    assert code == 2 and "pass --tip one of" in err
    code, out, _ = run(
        capsys, "bench", "--arms", path, "--tip", "tip", "--solvers", "dls", "-n", "2", "--json"
    )
    assert code == 0 and '"solver": "dls"' in out
