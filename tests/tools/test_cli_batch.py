"""armik batch and armik reach on good and bad files."""

from __future__ import annotations

import numpy as np
import pytest

from armik import BatchResult
from armik.solve.reach import ReachMap
from armik.tools.cli import main

from ..conftest import arm


@pytest.fixture(scope="module")
def poses() -> np.ndarray:
    a = arm("ur5")
    rng = np.random.default_rng(11)
    return np.array([a.fk(a.random_q(rng)).homogeneous for _ in range(12)])


def _rows7(T: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    return np.hstack([T[:, :3, 3], Rotation.from_matrix(T[:, :3, :3]).as_quat()])


def test_batch_files_of_every_kind_agree(tmp_path, poses, capsys):
    files = {
        "t.npy": lambda p: np.save(p, poses),
        "t.npz": lambda p: np.savez(p, targets=_rows7(poses)),
        "t.csv": lambda p: np.savetxt(
            p, _rows7(poses), delimiter=",", header="x,y,z,qx,qy,qz,qw", comments=""
        ),
        "flat.csv": lambda p: np.savetxt(p, poses.reshape(-1, 16), delimiter=","),
    }
    results = []
    for name, write in files.items():
        write(tmp_path / name)
        out = tmp_path / f"{name}.out.npz"
        assert main(["batch", "ur5", str(tmp_path / name), "-o", str(out), "--workers", "1"]) == 0
        text = capsys.readouterr().out
        assert "12/12 solved" in text and f"wrote {out}" in text
        results.append(BatchResult.load(out))
    for r in results[1:]:
        np.testing.assert_allclose(r.q, results[0].q, atol=1e-6)
        assert r.success.all()


def test_a_file_of_one_target_is_a_batch_of_one(tmp_path, poses, capsys):
    """One 4x4 pose, or one row x y z qx qy qz qw, saved alone: one target, where the
    command said to use Arm.solve, which it has not."""
    for name, array in (("T.npy", poses[0]), ("row.npy", _rows7(poses[:1])[0])):
        np.save(tmp_path / name, array)
        out = tmp_path / f"{name}.npz"
        code = main(["batch", "ur5", str(tmp_path / name), "-o", str(out), "--workers", "1"])
        assert code == 0, capsys.readouterr().err
        assert "1/1 solved" in capsys.readouterr().out
        reached = arm("ur5").fk(BatchResult.load(out).q[0]).homogeneous
        np.testing.assert_allclose(reached, poses[0], atol=1e-6)


def test_batch_options_and_seeds_from_the_file(tmp_path, poses, capsys):
    q0 = np.tile(arm("ur5").middle, (len(poses), 1))
    np.savez(tmp_path / "t.npz", targets=poses[:, :3, 3], q0=q0)  # positions, with seeds
    out = tmp_path / "o.npz"
    argv = ["batch", "ur5", str(tmp_path / "t.npz"), "-o", str(out), "--timeout", "0.02"]
    assert main(argv + ["--tol", "1e-5", "--seed", "3", "--solver", "qp", "--workers", "2"]) == 0
    r = BatchResult.load(out)
    assert r.solver == "qp" and r.success.all() and np.isnan(r.orientation_error).all()
    assert r.tol_position == 1e-5


BAD_FILES = [
    ("missing.npy", None, "does not exist"),
    ("t.txt", b"1 2 3\n", "give a .npy, .npz or .csv"),
    ("t.npy", b"garbage", "t.npy' is not a valid .npy file"),
    ("t.npz", b"garbage", "t.npz' is not a valid .npz file"),
    ("t.csv", b"1,2,3\n4,5\n", "different numbers of columns"),
    ("t.csv", b"x,y,z\n1,2,abc\n", "line 2 is not numbers: '1,2,abc'"),
    # a typo in the first row: refused by its line, not taken for a header and dropped
    ("t.csv", b"0.4,0.2,O.3\n0.3,0.1,0.4\n", "line 1 is not numbers: '0.4,0.2,O.3'"),
    ("t.csv", b"0.4 0.2 0.3\n0.3 0.1 0.4\n", "line 1 is not numbers: .* with commas"),
    ("t.csv", b"0.4,0.2,0.3,\n", "line 1 is not numbers: .* a field is empty"),
    ("t.csv", b"0.1,0.2,nan\n", "target 0: position contains NaN"),
    # a file's 2-vector on a spatial arm: the library's words, no flag the command lacks
    ("t.csv", b"1.2,0.5\n", r"target 0: a 2-vector target needs a planar arm.* \(x, y, z\)"),
    ("t.csv", b"1,2,3,4\n", r"shape \(1, 4\)"),
    ("t.csv", b"0.4 0.2 0.3\n", "line 1 is not numbers: '0.4 0.2 0.3'; separate the"),
    ("t.csv", b"x,y,z\n", "its one line, 'x,y,z', is no row of numbers"),
    ("t.csv", b"# a comment\n", "the file holds no rows of numbers; write one target a line"),
]


@pytest.mark.parametrize("name, content, words", BAD_FILES, ids=[b[2] for b in BAD_FILES])
def test_bad_files_one_line_exit_2(tmp_path, capsys, name, content, words):
    if content is not None:
        (tmp_path / name).write_bytes(content)
    code = main(["batch", "ur5", str(tmp_path / name), "-o", str(tmp_path / "o.npz")])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and err.startswith("armik: error:"), err
    assert words in err or __import__("re").search(words, err), err
    assert "allow_pickle" not in err


def test_csv_blank_lines_comments_and_byte_order_mark(tmp_path, poses, capsys):
    """Lines of spaces, comments and Excel's byte-order mark are no targets; every other
    line is one, in the order of the file."""
    rows = [",".join(f"{v:.17g}" for v in p[:3, 3]) for p in poses[:3]]
    text = f"\ufeff# x,y,z\n{rows[0]}\n   \n{rows[1]}\n\t\n  # a note\n{rows[2]}\n"
    (tmp_path / "t.csv").write_text(text, encoding="utf-8")
    out = tmp_path / "o.npz"
    assert main(["batch", "ur5", str(tmp_path / "t.csv"), "-o", str(out), "--workers", "1"]) == 0
    assert "3/3 solved" in capsys.readouterr().out
    r = BatchResult.load(out)
    a = arm("ur5")
    reached = [a.fk(q).translation for q in r.q]
    np.testing.assert_allclose(reached, poses[:3, :3, 3], atol=1e-6)


def test_bad_npz_and_output(tmp_path, poses, capsys):
    np.savez(tmp_path / "two.npz", a=poses, b=poses)
    assert main(["batch", "ur5", str(tmp_path / "two.npz"), "-o", str(tmp_path / "o.npz")]) == 2
    assert "name the targets array 'targets'" in capsys.readouterr().err
    obj = np.empty(2, dtype=object)
    np.save(tmp_path / "obj.npy", obj, allow_pickle=True)
    assert main(["batch", "ur5", str(tmp_path / "obj.npy"), "-o", str(tmp_path / "o.npz")]) == 2
    err = capsys.readouterr().err
    assert "obj.npy' holds an array of Python objects" in err and "allow_pickle" not in err
    np.savez(tmp_path / "obj.npz", targets=obj, allow_pickle=True)
    assert main(["batch", "ur5", str(tmp_path / "obj.npz"), "-o", str(tmp_path / "o.npz")]) == 2
    assert "obj.npz' holds an array of Python objects" in capsys.readouterr().err
    np.save(tmp_path / "t.npy", poses)
    assert main(["batch", "ur5", str(tmp_path / "t.npy"), "-o", str(tmp_path / "o.txt")]) == 2
    assert "*.npz" in capsys.readouterr().err
    nowhere = tmp_path / "no" / "o.npz"
    assert main(["batch", "ur5", str(tmp_path / "t.npy"), "-o", str(nowhere)]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_reach_command_saves_and_plots(tmp_path, capsys):
    out, png = tmp_path / "reach.npz", tmp_path / "reach.png"
    argv = ["reach", "planar_2link", "--resolution", "0.4", "--orientations", "2"]
    assert main(argv + ["-o", str(out), "--plot", str(png), "--workers", "1"]) == 0
    text = capsys.readouterr().out
    assert "voxels" in text and f"wrote {png}" in text
    assert "positions only" in text  # 2 joints: a map of positions, one solve a voxel
    m = ReachMap.load(out)
    assert m.position_only and m.orientations == 1 and m.fraction.ndim == 3
    assert np.nanmax(m.fraction) == 1
    assert png.stat().st_size > 10_000
    assert main(["reach", "ur5", "--resolution", "-1"]) == 2
    assert "resolution must be" in capsys.readouterr().err
    # a plot folder that is not there: refused before the run, nothing written
    missing = tmp_path / "none" / "x.png"
    other = tmp_path / "other.npz"
    assert main(argv + ["-o", str(other), "--plot", str(missing)]) == 2
    assert "plot folder" in capsys.readouterr().err and not other.exists()


def test_reach_plot_kinds_said_before_the_run_and_the_file_written_named(tmp_path, capsys):
    """--plot x.xyz, a kind matplotlib does not write: refused before the run, where a
    ValueError traceback came after it; --plot without a suffix names the .png written."""
    argv = ["reach", "planar_2link", "--resolution", "0.5", "--orientations", "1"]
    out = tmp_path / "r.npz"
    assert main(argv + ["-o", str(out), "--plot", str(tmp_path / "r.xyz")]) == 2
    err = capsys.readouterr().err
    assert "matplotlib writes no .xyz file: name it .png" in err and not out.exists()
    assert main(argv + ["-o", str(out), "--plot", str(tmp_path / "map")]) == 0
    png = tmp_path / "map.png"
    assert f"wrote {png}\n" in capsys.readouterr().out and png.stat().st_size > 10_000


def test_batch_takes_the_solve_flags(tmp_path, capsys):
    a = arm("ur5")
    T = np.array([a.fk(q).homogeneous for q in a.random_q(4, n=5)])
    np.save(tmp_path / "t.npy", T)
    out = tmp_path / "r.npz"
    code = main(
        ["batch", "ur5", str(tmp_path / "t.npy"), "-o", str(out), "--workers", "1",
         "--position-only", "--weights", "1", "1", "1", "0", "0", "0", "--seed", "2"]
    )  # fmt: skip
    assert code == 0
    r = BatchResult.load(out)
    assert r.success.all() and np.isnan(r.orientation_error).all()
