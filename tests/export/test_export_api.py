"""``armik.export`` and ``armik export``: the files, the refusals and their reasons."""

from __future__ import annotations

import errno
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import armik
from armik.export import FAMILIES
from armik.solvers import registry
from armik.tools.cli import main
from tests.export.build import CFLAGS, HERE, compilers, run
from tests.solvers.closed_form.random_arms import load_arm, random_urdf


def test_files_returned_and_written(tmp_path):
    arm = armik.load("ur5")
    files = armik.export(arm, "ur5", tmp_path / "out", ikfast=True)
    assert sorted(files) == ["ur5_ik.c", "ur5_ik.h", "ur5_ikfast.cpp"]
    for name, text in files.items():
        assert (tmp_path / "out" / name).read_text() == text
    header = files["ur5_ik.h"]
    assert "#define UR5_IK_DOF 6" in header and "#define UR5_IK_MAX_SOLUTIONS 8" in header
    assert "int ur5_ik(const double T[16], double q[][UR5_IK_DOF]);" in header
    # the version line MoveIt's create_ikfast_moveit_plugin.py reads, as it reads it
    found = re.search(r"^/// ikfast version (.*) generated", files["ur5_ikfast.cpp"], re.M)
    assert found and int(found.group(1), 0) & ~0x10000000 == 61
    assert sorted(armik.export(arm.kinematics, "x")) == ["x_ik.c", "x_ik.h"]  # nothing written
    assert not (tmp_path / "x_ik.c").exists()


def test_limits_and_geometry_folded_in():
    """The C holds the arm's own numbers: another limit changes the file, nothing else does."""
    arm = armik.load("abb_irb120")
    narrow = arm.with_limits({arm.joint_names[0]: (-1.0, 1.0)})
    a, b = armik.export(arm, "irb")["irb_ik.c"], armik.export(narrow, "irb")["irb_ik.c"]
    assert a != b and a == armik.export(arm, "irb")["irb_ik.c"]


@pytest.mark.parametrize("name", ["9lives", "a-b", "", "x y"])
def test_name_must_be_a_c_identifier(name):
    with pytest.raises(armik.OptionError, match="C identifier"):
        armik.export(armik.load("ur5"), name)


@pytest.mark.parametrize("kind", ["two_parallel", "two_intersecting", "general"])
def test_arms_without_an_exported_closed_form_are_refused(kind):
    """Each exported family's reason, as armik info gives it; a search solve_all would
    run named as one (armik info: "every solution, a search") with its summary."""
    arm = load_arm(kind, np.random.default_rng(9))
    with pytest.raises(armik.SolverError) as info:
        armik.export(arm, "x")
    text = str(info.value)
    for name in FAMILIES:
        assert f"{name}: {registry.why_not(name, arm.kinematics)}" in text
    chosen = registry.choose("auto", arm.kinematics, every=True)
    assert not chosen.complete  # each of these arms' solve_all is a search
    assert f"solve_all chooses {chosen.name!r}, every solution by a search" in text
    assert chosen.summary in text


def test_cli(tmp_path, capsys):
    out = tmp_path / "ik"
    assert main(["export", "planar_2link", "--name", "two", "--out", str(out)]) == 0
    assert capsys.readouterr().out.split() == [str(out / "two_ik.h"), str(out / "two_ik.c")]
    assert "TWO_IK_MAX_SOLUTIONS 2" in (out / "two_ik.h").read_text()
    assert main(["export", "xarm7", "--name", "p", "--out", str(tmp_path / "p")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no closed form to export" in err
    assert not (tmp_path / "p").exists()
    assert main(["export", "ur5", "--name", "1x", "--out", str(out)]) == 2
    assert "C identifier" in capsys.readouterr().err
    tight = ["--tol-position", "1e-9", "--tol-orientation", "2e-9"]
    assert main(["export", "ur5", "--name", "t", "--out", str(out), *tight]) == 0
    assert "to 1e-09 m and 2e-09 rad" in (out / "t_ik.h").read_text()
    assert main(["export", "ur5", "--name", "t", "--out", str(out), "--tol-position", "-1"]) == 2
    assert "armik: error: --tol-position must be > 0" in capsys.readouterr().err


@pytest.mark.parametrize(
    "flags, words",
    [
        (["--name", "1x"], "--name must be a C identifier"),
        (["--name", "_x"], "--name '_x' is reserved"),
        (["--tol-orientation", "nan"], "--tol-orientation must be finite"),
        (["--tol-position", "1e-13"], "--tol-position 1e-13 is below"),
    ],
)
def test_cli_errors_name_the_flag(flags, words, tmp_path, capsys):
    """A refusal of an argument of ``armik.export`` names the flag that gave it, not the
    Python keyword (``tol_position``, ``name=``), which the command line has not."""
    argv = ["export", "ur5", "--name", "t", "--out", str(tmp_path / "o"), *flags]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"armik: error: {words}" in err and "tol_" not in err


def test_cli_error_of_out_names_the_flag(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    assert main(["export", "ur5", "--name", "t", "--out", str(tmp_path / "file")]) == 2
    assert f"armik: error: --out {str(tmp_path / 'file')!r} cannot" in capsys.readouterr().err


def test_cli_prints_the_paths_written(tmp_path, capsys, monkeypatch):
    """--out "" writes into the current folder and --out sub/ into sub: the paths printed
    are those of the files, not "/two_ik.h" or "sub//two_ik.h"."""
    monkeypatch.chdir(tmp_path)
    for out in ("", "sub/"):
        assert main(["export", "planar_2link", "--name", "two", "--out", out]) == 0
        printed = capsys.readouterr().out.split()
        assert printed == [str(Path(out) / "two_ik.h"), str(Path(out) / "two_ik.c")]
        assert all((tmp_path / p).is_file() and "//" not in p for p in printed)


def test_two_solvers_link_into_one_library(tmp_path):
    """Everything but N_ik and N_fk is static: two arms' solvers share a program."""
    cc, _ = compilers()
    sources = []
    for name in ("ur5", "abb_irb120"):
        armik.export(armik.load(name), name, tmp_path)
        sources.append(str(tmp_path / f"{name}_ik.c"))
    run(cc, *CFLAGS, "-shared", "-fPIC", *sources, "-o", str(tmp_path / "both.so"), "-lm")
    symbols = subprocess.run(
        ["nm", "-D", "--defined-only", str(tmp_path / "both.so")], capture_output=True, text=True
    ).stdout.split()
    exported = {s for s in symbols if s.endswith(("_ik", "_fk"))}
    assert exported == {"ur5_ik", "ur5_fk", "abb_irb120_ik", "abb_irb120_fk"}


def test_names_beyond_ascii_are_written_as_escapes(tmp_path):
    """The URDF's names go into the files' comments in ASCII, so the files are the same
    bytes under any locale (an ASCII one raised UnicodeEncodeError midway and left the
    temporaries) and compile with every warning an error."""
    cc, _ = compilers()
    text = random_urdf("three_parallel", np.random.default_rng(0))
    text = text.replace('<robot name="random_6r">', '<robot name="bras_soudé_焊接">')
    arm = armik.load_string(text.replace('"tool"', '"outil_é"'), base="world", tip="outil_é")
    files = armik.export(arm, "bras", tmp_path, ikfast=True)
    for name, source in files.items():
        assert source.isascii(), name
        assert (tmp_path / name).read_bytes() == source.encode("ascii")
    assert "bras_soud\\xe9_\\u710a\\u63a5" in files["bras_ik.c"]
    assert sorted(os.listdir(tmp_path)) == sorted(files)  # no temporary left
    run(cc, *CFLAGS, "-c", str(tmp_path / "bras_ik.c"), "-o", str(tmp_path / "bras.o"))


def _bundled_exports() -> list[str]:
    """The bundled arms with a closed form to export (a 7R arm: joint 7 held)."""
    names = []
    for name in armik.robots():
        try:
            armik.export(armik.load(name), "x")
        except armik.SolverError:
            continue
        names.append(name)
    return names


@pytest.mark.parametrize("compiler", ["cc", "clang"])
def test_every_bundled_export_compiles_without_a_warning(compiler, tmp_path):
    """Each bundled arm's files, with every warning an error, as C99 and as C++ (the IKFast
    file against the tests' ikfast.h): no unused helper, whichever a family calls. gcc
    (``cc``) always; clang when it is installed."""
    if compiler == "cc":
        c, cxx = compilers()
    else:
        c, cxx = shutil.which("clang") or "", shutil.which("clang++") or ""
        if not c or not cxx:
            pytest.skip("clang or clang++ is not installed")
    warnings = ["-Wall", "-Wextra", "-Werror"]
    names = _bundled_exports()
    assert {"ur5", "abb_irb120", "planar_2link", "panda", "kuka_iiwa14"} <= set(names)
    for name in names:
        armik.export(armik.load(name), name, tmp_path, ikfast=True)
        source, obj = str(tmp_path / f"{name}_ik.c"), str(tmp_path / "x.o")
        run(c, "-std=c99", *warnings, "-c", source, "-o", obj)
        run(cxx, "-x", "c++", *warnings, "-c", source, "-o", obj)
        wrapper = str(tmp_path / f"{name}_ikfast.cpp")
        run(cxx, "-std=c++14", *warnings, f"-I{HERE}", f"-I{tmp_path}", "-c", wrapper, "-o", obj)


def test_files_are_replaced_all_or_none(tmp_path, monkeypatch):
    """An export over an earlier one replaces its files; when one of them cannot be
    written, none is: the folder keeps the earlier pair, which solve the same arm."""
    arm, other = armik.load("ur5"), armik.load("abb_irb120")
    before = armik.export(arm, "x", tmp_path, ikfast=True)
    after = armik.export(other, "x", tmp_path, ikfast=True)  # replaced, as a generator does
    assert all((tmp_path / f).read_text() == text for f, text in after.items())
    armik.export(arm, "x", tmp_path, ikfast=True)
    (tmp_path / "x_ikfast.cpp").unlink()
    (tmp_path / "x_ikfast.cpp").mkdir()  # the third file cannot be written
    with pytest.raises(armik.OptionError, match="x_ikfast.cpp"):
        armik.export(other, "x", tmp_path, ikfast=True)
    for f in ("x_ik.h", "x_ik.c"):
        assert (tmp_path / f).read_text() == before[f]
    (tmp_path / "x_ikfast.cpp").rmdir()
    opened = os.open

    def full(path, *args):  # the disk full at the second file
        if "x_ik.c" in str(path):
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        return opened(path, *args)

    monkeypatch.setattr(os, "open", full)
    with pytest.raises(armik.OptionError, match="No space left"):
        armik.export(other, "x", tmp_path)
    assert sorted(os.listdir(tmp_path)) == ["x_ik.c", "x_ik.h"]  # no temporary left
    for f in ("x_ik.h", "x_ik.c"):
        assert (tmp_path / f).read_text() == before[f]


def test_a_failed_export_leaves_no_folder_it_made(tmp_path):
    out = tmp_path / "new" / "ik"
    with pytest.raises(armik.OptionError, match="cannot hold"):
        armik.export(armik.load("ur5"), "a" * 300, out)  # a file name too long
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "options, words",
    [
        ({"out": 5}, "out must be a folder's path"),
        ({"out": "ur5\0ik"}, "null character"),
        ({"out": Path("ur5\0ik")}, "null character"),
        ({"ikfast": "yes"}, "ikfast must be True or False, got 'yes'"),
        ({"tol_orientation": 1e-300}, "tol_orientation=1e-300 is below .* at least 1e-12 rad"),
        ({"tol_position": 5e-13}, "tol_position=5e-13 is below .* at least 1e-12 m"),
    ],
)
def test_options_of_the_wrong_kind_are_named(options, words):
    with pytest.raises(armik.OptionError, match=words):
        armik.export(armik.load("ur5"), "x", **options)


@pytest.mark.parametrize("name", ["_X", "__x", "_x", "a__b"])
def test_names_c_reserves_are_refused(name, tmp_path, capsys):
    with pytest.raises(armik.OptionError, match="reserved in C or C\\+\\+"):
        armik.export(armik.load("ur5"), name)
    assert main(["export", "ur5", "--name", name, "--out", str(tmp_path / "o")]) == 2
    assert "reserved" in capsys.readouterr().err and not (tmp_path / "o").exists()


def test_the_files_own_macros_stand_whatever_the_build_defines(tmp_path):
    """A build that defines ``DOF``, ``HELD``, ``MAX_ROWS`` or another of the solver file's
    own macro names (``-DHELD=3``, common words in a robot's project) compiles it without a
    warning: the file undefines each before its own (it failed, "HELD" redefined)."""
    c, _ = compilers()
    given = ["DOF=2", "HELD=3", "MAX_ROWS=1", "FREE_SWEEP=0", "EQUAL_LINKS=9"]
    given += ["SP_GRID=1", "SP_STARTS=1"]
    for name in ("planar_2link", "ur5", "panda", "kinova"):
        armik.export(armik.load(name), name, tmp_path)
        source, obj = str(tmp_path / f"{name}_ik.c"), str(tmp_path / "x.o")
        run(
            c,
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Werror",
            *[f"-D{d}" for d in given],
            "-c",
            source,
            "-o",
            obj,
        )
