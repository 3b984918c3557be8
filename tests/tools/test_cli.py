"""The command line: output, exit codes, and one-line errors."""

from __future__ import annotations

import json
import re

import pytest

from armik.tools.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_robots_and_info(capsys):
    code, out, _ = run(capsys, "robots")
    assert code == 0 and "panda" in out and "planar_2link" in out
    code, out, _ = run(capsys, "info", "planar_2link")
    assert (
        code == 0
        and re.search(r"planar2r +\(analytic\) applies", out)
        and "auto -> planar2r" in out
    )
    code, out, _ = run(capsys, "info", "panda")
    assert "exactly 2" in out and "auto -> dls" in out


def test_solve_success_json(capsys):
    code, out, _ = run(
        capsys, "solve", "planar_2link", "--xyz", "1.2", "0.5", "0", "--all", "--json"
    )
    assert code == 0
    data = json.loads(out)
    assert {r["branch"] for r in data["results"]} == {"elbow-up", "elbow-down"}


def test_solve_full_pose(capsys):
    code, out, _ = run(
        capsys, "solve", "ur5", "--xyz", "0.4", "0.2", "0.3", "--rpy", "3.1416", "0", "0"
    )
    assert code == 0 and "converged" in out


def test_solve_unreachable_exit_1(capsys):
    code, out, _ = run(capsys, "solve", "ur5", "--xyz", "4", "0", "0")
    assert code == 1 and "unreachable" in out


@pytest.mark.parametrize(
    "argv, words",
    [
        (["solve", "nope", "--xyz", "1", "0", "0"], "neither a bundled robot"),
        (["solve", "ur5", "--xyz", "1", "0"], "expected 3 arguments"),
        (["solve", "ur5", "--xyz", "nan", "0", "0"], "NaN"),
        (["solve", "ur5", "--xyz", "0.4", "0", "0", "--quat", "0", "0", "0", "0"], "zero norm"),
        (["solve", "ur5", "--xyz", "0.4", "0", "0", "--solver", "newton"], "unknown solver"),
        (["solve", "ur5", "--xyz", "0.4", "0", "0", "--solver", "planar2r"], "does not apply"),
        (["solve", "ur5", "--xyz", "0.4", "0", "0", "--q0", "1", "2"], "q0 must have 6"),
        (
            ["solve", "ur5", "--xyz", "0.4", "0", "0", "--q0", "1", "2", "3", "4", "5", "nan"],
            "finite",
        ),
        (["solve", "ur5", "--xyz", "0.4", "0", "0", "--timeout", "0"], "timeout must be > 0"),
        (["solve", "ur5", "--xyz", "0.4", "0", "0", "--timeout", "1e300"], "at most 1e+06 s"),
        (["reach", "ur5", "--resolution", "1e-300"], "too many solves"),
        (["solve", "ur5", "--xyz", "0.4", "0", "0", "--tip", "hand"], "unknown tip frame"),
        (["info", "/no/such/file.urdf"], "does not exist"),
        (["info", "panda", "--lock", "panda_joint7"], "expected NAME=VALUE"),
        (["info", "panda", "--lock", "=0.3"], "expected NAME=VALUE"),
        (["info", "panda", "--lock", "panda_joint7=abc"], "must be a number"),
        (["info", "panda", "--lock", "panda_joint7=nan"], "finite number"),
        (["info", "panda", "--lock", "panda_joint7=9"], "outside its URDF limits"),
        (["info", "panda", "--lock", "panda_joint9=0"], "does not exist"),
        (["info", "panda", "--lock", "panda_joint7=0", "--lock", "panda_joint7=1"], "twice"),
        (["solve", "ur5", "--xyz", "0.4", "0", "0", "--lock", "elbow_joint"], "expected NAME="),
        (["batch", "ur5", "t.npy", "-o", "o.npz", "--lock", "elbow_joint:1"], "expected NAME="),
        (["reach", "ur5", "--lock", "elbow_joint=x"], "must be a number"),
        (["compare", "--seed", "-1"], "--seed: expected a whole number in [0, 4294967295]"),
        (["bench", "--seed", "-1", "-n", "1"], "--seed: expected a whole number in [0,"),
        (["reach", "ur5", "--seed", "4294967296"], "--seed: expected a whole number in [0,"),
        (["reach", "ur5", "--seed", "1.5"], "--seed: expected a whole number in [0,"),
    ],
)
def test_bad_input_exit_2_one_line(capsys, argv, words):
    parser_error = "expected" in words or "must be a number" in words
    with pytest.raises(SystemExit) if parser_error else _nullcontext() as box:
        code, out, err = run(capsys, *argv)
    if box is not None and hasattr(box, "value"):
        code = box.value.code
        err = capsys.readouterr().err
    assert code == 2
    assert words in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_lock_on_the_chain(capsys):
    code, out, _ = run(capsys, "info", "panda", "--lock", "panda_joint7=0.3")
    assert code == 0 and "panda: 6 joints" in out
    assert "locked: panda_joint7 = 0.3 rad (on the chain)" in out
    assert "family: spherical_shoulder" in out and "auto -> spherical_shoulder" in out
    code, out, _ = run(
        capsys,
        "solve",
        "ur5",
        "--lock",
        "wrist_1_joint=-1.2",
        "--lock",
        "shoulder_pan_joint=0.1",
        "--xyz",
        "0.4",
        "0.2",
        "0.3",
        "--json",
    )
    data = json.loads(out)
    assert code == 0 and "wrist_1_joint" not in data["joints"] and len(data["joints"]) == 4


def test_export_takes_lock_as_load_does(capsys, tmp_path):
    # armik export had no --lock: the Panda with joint 7 locked, a 6R arm armik.export
    # writes, could not be exported from the command line
    import armik

    code, out, err = run(
        capsys,
        "export",
        "panda",
        "--lock",
        "panda_joint7=0.3",
        "--name",
        "p6",
        "--out",
        str(tmp_path),
    )
    assert code == 0, err
    arm = armik.load("panda", locked={"panda_joint7": 0.3})
    files = armik.export(arm, "p6", tmp_path / "from_python")
    assert "#define P6_IK_DOF 6" in files["p6_ik.h"]
    for name, text in files.items():
        assert (tmp_path / name).read_text() == text


class _nullcontext:
    def __enter__(self):
        return None

    def __exit__(self, *exc):
        return False


def test_demo_and_bench_small(capsys):
    code, out, _ = run(capsys, "demo")
    assert code == 0 and "elbow-up" in out and "panda" in out
    # the 2-link solve_all's time is the call's, printed once, not once per solution
    two_link = out.split("panda:")[0]
    assert two_link.count("ms for the call (2 solutions); its solver's first call") == 1
    assert "ms," not in two_link
    code, out, _ = run(capsys, "bench", "--arms", "ur5", "--solvers", "dls", "-n", "20", "--json")
    rows = json.loads(out)
    assert code == 0 and rows[0]["arm"] == "ur5" and rows[0]["n"] == 20
    assert rows[0]["limit_violations"] == 0
    assert rows[0]["failures"] == round(20 * (1 - rows[0]["success_rate"] / 100))


def test_bench_repeats_and_bad_values(capsys):
    code, out, _ = run(
        capsys, "bench", "--arms", "ur5", "--solvers", "qp", "-n", "5", "--repeats", "2", "--json"
    )
    assert code == 0 and json.loads(out)[0]["n"] == 10
    code, out, _ = run(capsys, "bench", "--arms", "ur5", "--solvers", "dls,qp", "-n", "3", "--json")
    assert code == 0 and [r["solver"] for r in json.loads(out)] == ["dls", "qp"]
    for flag, value, words in (
        ("-n", "0", "targets per arm must be at least 1"),
        ("--repeats", "0", "passes must be at least 1"),
        ("--budget", "-1", "budget per solve must be > 0"),
        ("--tol", "0", "tolerance must be > 0"),
    ):
        code, _, err = run(capsys, "bench", "--arms", "ur5", "--solvers", "dls", flag, value)
        assert code == 2 and words in err and "Traceback" not in err


def test_solve_flags_are_the_python_options(capsys):
    import numpy as np
    import pinocchio as pin

    import armik

    args = ["--xyz", "0.4", "0.2", "0.3", "--rpy", "3.1", "0.1", "0", "--solver", "dls"]
    flags = ["--weights", "1", "1", "1", "1", "1", "0", "--tip-offset", "0", "0", "0.1"]
    code, out, _ = run(capsys, "solve", "ur5", *args, *flags, "--seed", "3", "--json")
    assert code == 0
    got = json.loads(out)["results"][0]
    a = armik.load("ur5", tip_offset=(0, 0, 0.1))
    T = pin.SE3(pin.rpy.rpyToMatrix(3.1, 0.1, 0.0), np.array([0.4, 0.2, 0.3]))
    r = a.solve(T, solver="dls", weights=(1, 1, 1, 1, 1, 0), seed=3)
    assert got["success"] and got["q"] == r.q.tolist()
    code, out, _ = run(capsys, "solve", "ur5", *args, "--position-only", "--json")
    assert code == 0 and json.loads(out)["results"][0]["orientation_error"] is None


def test_solve_takes_tol_as_batch_and_path_do(capsys):
    # --tol was batch's and path's only: armik solve refused it as an unrecognized argument
    import numpy as np
    import pinocchio as pin

    import armik

    args = ["--xyz", "0.4", "0.2", "0.3", "--rpy", "3.1", "0.1", "0", "--solver", "dls"]
    code, out, err = run(capsys, "solve", "ur5", *args, "--tol", "1e-3", "--json")
    assert code == 0, err
    got = json.loads(out)["results"][0]
    T = pin.SE3(pin.rpy.rpyToMatrix(3.1, 0.1, 0.0), np.array([0.4, 0.2, 0.3]))
    r = armik.load("ur5").solve(T, solver="dls", tol_position=1e-3, tol_orientation=1e-3)
    assert got["success"] and got["q"] == r.q.tolist() and got["reason"] == r.reason
    assert "(tol 0.001)" in got["reason"]


def test_version(capsys):
    # armik --version was an unrecognized argument
    import armik

    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out == f"armik {armik.__version__}\n"


def test_parsing_imports_none_of_the_library():
    """``armik --help`` and a command's parsing import no solver, no numba and no Pinocchio:
    a command's own module is imported when it runs."""
    import subprocess
    import sys

    code = (
        "import sys\n"
        "from armik.tools.cli import main\n"
        "try:\n"
        "    main(['--help'])\n"
        "except SystemExit:\n"
        "    pass\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('numba', 'pinocchio', 'numpy') or m in ('armik.arm', 'armik.solvers')))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip().splitlines()[-1] == "[]"


def test_compile_parts_named_in_the_parser():
    from armik.precompile import PARTS
    from armik.tools.cli.commands import PART_NAMES

    assert PART_NAMES == tuple(PARTS)


def test_prefer_choices_are_the_named_scores():
    # the parser imports none of the library: its --prefer choices are written out, and a
    # score named in problem/scores.py without them would be refused by the CLI
    from armik.problem.scores import _NAMED
    from armik.tools.cli.main import _parser

    commands = next(a for a in _parser()._actions if a.choices and "solve" in a.choices).choices
    choices = {
        tuple(a.choices)
        for command in ("solve", "batch", "path")
        for a in commands[command]._actions
        if a.dest == "prefer"
    }
    assert choices == {tuple(_NAMED)}


def test_rpy_in_degrees_is_warned_of_and_taken_as_radians(capsys):
    """--rpy 180 0 0 (degrees by mistake) is 180 rad as the help says, with one line on
    stderr; angles within 2 pi say nothing."""
    code, out, err = run(
        capsys, "solve", "ur5", "--xyz", "0.4", "0.2", "0.3", "--rpy", "180", "0", "0", "--json"
    )
    assert code in (0, 1)
    assert [line for line in err.splitlines() if "warning" in line] == [
        "armik: warning: --rpy 180 0 0 looks like degrees; --rpy takes radians"
    ]
    assert json.loads(out)["results"]
    code, _, err = run(
        capsys, "solve", "ur5", "--xyz", "0.4", "0.2", "0.3", "--rpy", "3.1416", "0", "0"
    )
    assert code == 0 and "degrees" not in err


def test_rpy_not_finite_is_refused_by_its_flag_not_taken_for_degrees(capsys):
    code, _, err = run(
        capsys, "solve", "ur5", "--xyz", "0.4", "0.2", "0.3", "--rpy", "inf", "0", "0"
    )
    assert code == 2
    assert (
        err == "armik: error: --rpy inf 0 0 is not 3 finite angles: give roll, pitch, yaw (rad)\n"
    )


def test_xy_is_a_planar_arms_2_vector(capsys):
    """--xy A B on a planar arm is Python's 2-vector (the base's axes across its plane); on
    another arm, with --rpy, or without any position, a one-line error naming the fix."""
    import numpy as np

    import armik

    code, out, _ = run(capsys, "solve", "planar_2link", "--xy", "1.2", "0.5", "--json")
    assert code == 0
    q = json.loads(out)["results"][0]["q"]
    reached = armik.load("planar_2link").fk(q).translation
    assert np.allclose(reached[:2], [1.2, 0.5], atol=1e-9)
    code, _, err = run(capsys, "solve", "ur5", "--xy", "0.3", "0.2")
    assert code == 2 and "--xy needs a planar arm, and arm 'ur5' is not planar" in err
    assert "give --xyz X Y Z" in err and len(err.strip().splitlines()) == 1
    code, _, err = run(
        capsys, "solve", "planar_2link", "--xy", "1.2", "0.5", "--rpy", "0", "0", "0"
    )
    assert code == 2 and "--xy (a point on a planar arm's plane) does not go with --rpy" in err
    with pytest.raises(SystemExit):
        main(["solve", "planar_2link"])
    assert "one of the arguments --xyz --xy is required" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["solve", "planar_2link", "--xyz", "1.2", "0.5"])
    assert "expected 3 arguments (a planar arm's" in capsys.readouterr().err


def test_compile_prints_its_times_in_one_column(capsys, monkeypatch):
    from armik.tools.cli import compile as cli_compile

    def took(names, jobs, load):
        return {name: 0.5 for name in names}

    monkeypatch.setattr(cli_compile, "compile", took)
    code, out, _ = run(capsys, "compile", "dls", "three_parallel_general", "fk_batch")
    rows = out.splitlines()[:-1]
    assert code == 0 and len(rows) == 3
    assert len({row.index("0.50 s") for row in rows}) == 1, out
    assert out.splitlines()[-1].startswith("compiled 3 parts in ")
    code, out, _ = run(capsys, "compile", "planar2r")  # one part, not "1 parts"
    assert code == 0 and out.splitlines()[-1].startswith("compiled 1 part in "), out


def test_ctrl_c_is_one_line_and_exit_130(capsys, monkeypatch):
    # Ctrl-C in a long command (a reach map, a batch) printed Python's traceback of the
    # KeyboardInterrupt from wherever the solve was
    from armik.tools.cli import many

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(many, "cmd_batch", interrupted)
    try:
        code, out, err = run(capsys, "batch", "ur5", "targets.npy", "-o", "out.npz")
    except KeyboardInterrupt:
        pytest.fail("Ctrl-C left main as a KeyboardInterrupt: a traceback")
    assert code == 130 and out == "" and err == "armik: interrupted\n"


@pytest.mark.parametrize("command", ["batch", "path"])
def test_help_names_no_flag_the_command_lacks(capsys, command):
    # batch's and path's --bounds help told how --bounds reads with --axis, a flag of solve's
    with pytest.raises(SystemExit) as exc:
        main([command, "--help"])
    out = capsys.readouterr().out
    assert exc.value.code == 0 and "--bounds BX BY BZ" in out and "--axis" not in out
    with pytest.raises(SystemExit):
        main(["solve", "--help"])
    assert "with --axis, the position's box" in " ".join(capsys.readouterr().out.split())


@pytest.mark.parametrize(
    "flags", [["--arms", "ur5", "--solvers", ","], ["--arms", ""]], ids=["solvers", "arms"]
)
def test_bench_refuses_an_empty_list_of_names(capsys, flags):
    # no solver name ended in a ZeroDivisionError traceback, no arm name in an empty table
    code, out, err = run(capsys, "bench", "-n", "2", *flags)
    assert code == 2 and out == "" and err.startswith("armik: error: give at least one")


@pytest.mark.parametrize("command", ["solve", "batch", "path"])
@pytest.mark.parametrize("tol", ["-1", "0", "nan"])
def test_a_bad_tol_names_the_flag(capsys, tmp_path, command, tol):
    # the keyword's words ("tol_position must be > 0") named neither the flag nor the
    # orientation's tolerance it sets too
    points = tmp_path / "points.npy"
    import numpy as np

    np.save(points, np.array([[0.4, 0.1, 0.3], [0.4, 0.12, 0.3]]))
    where = {
        "solve": ["--xyz", "0.4", "0.1", "0.3"],
        "batch": [str(points), "-o", str(tmp_path / "out.npz")],
        "path": [str(points), "-o", str(tmp_path / "out.npz")],
    }[command]
    code, out, err = run(capsys, command, "ur5", *where, f"--tol={tol}")
    assert code == 2
    assert err.strip().splitlines() == [
        f"armik: error: --tol must be a positive number of m and rad, got {float(tol):g}"
    ]


def test_the_command_runs_as_a_module():
    # where the armik script is not on the PATH: python -m armik.tools.cli, as README says
    # (armik's core never imports its tools: no armik/__main__.py)
    import subprocess
    import sys

    import armik

    run = [sys.executable, "-m", "armik.tools.cli"]
    done = subprocess.run([*run, "--version"], capture_output=True, text=True)
    assert (done.returncode, done.stdout) == (0, f"armik {armik.__version__}\n")
    done = subprocess.run([*run, "no_such_command"], capture_output=True, text=True)
    assert done.returncode == 2 and "invalid choice: 'no_such_command'" in done.stderr
