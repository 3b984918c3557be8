"""A ``BatchResult`` saved and loaded keeps every field its rows' words read (its rows'
solvers, its successes' kept words apart from the failures' reasons, its weights, each
tip's errors), and a file that is no saved batch is an ``InputError`` naming the file and
what it is (``armik.batch_file``, ``armik.npz``)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import armik

from .conftest import arm


def _batch(**kw):
    a = arm("kuka_iiwa14")
    T = [a.fk(a.random_q(k)) for k in range(5)]
    T[2].translation += np.array([3.0, 0.0, 0.0])  # out of reach: a failure's reason
    return a.solve_batch(T, **kw)


def test_a_saved_batch_loads_with_every_field(tmp_path):
    b = _batch()  # srs: its successes' words kept
    assert b.said and b.reasons  # a success's words kept, a failure's reason
    # rows that name several solvers (a row-by-row batch's), and one tip's errors
    b = replace(b, solvers={0: "dls", 1: "qp"}, errors={"tool": np.arange(10.0).reshape(5, 2)})
    c = armik.BatchResult.load(b.save(tmp_path / "b.npz"))
    assert c.solvers == b.solvers
    assert [r.solver for r in c] == [r.solver for r in b] != [b.solver] * len(b)
    assert c.said == b.said and c.reasons == b.reasons
    assert list(c.errors) == ["tool"] and np.array_equal(c.errors["tool"], b.errors["tool"])
    assert [c.reason(i) for i in range(len(c))] == [b.reason(i) for i in range(len(b))]


def test_a_saved_batch_keeps_its_weights(tmp_path):
    b = _batch(weights=(1, 1, 1, 1, 1, 0.5))
    assert b.weighted
    assert armik.BatchResult.load(b.save(tmp_path / "w.npz")).weighted is True


def test_a_batch_saved_before_its_solvers_were_kept_loads_without_them(tmp_path):
    b = _batch()
    path = b.save(tmp_path / "b.npz")
    with np.load(path) as z:  # as armik wrote it before: no said, solvers, errors
        old = {k: z[k] for k in z.files if not k.startswith(("said_", "solver_", "errors_"))}
    np.savez(tmp_path / "old.npz", **old)
    c = armik.BatchResult.load(tmp_path / "old.npz")
    assert c.solvers == {} and c.errors == {} and c.said == {}
    assert [c.reason(i) for i in range(len(c))] == [b.reason(i) for i in range(len(b))]


@pytest.mark.parametrize(
    ("content", "kind"),
    [
        (b"q0 = [0, 0, 0]\n", "a text file"),
        (b"", "an empty file"),
        (b"\x93NUMPY\x01\x00", "one array (.npy)"),
        (bytes(range(256)), "a binary file of another format"),
    ],
)
def test_a_file_that_is_no_saved_batch_says_what_it_is(tmp_path, content, kind):
    path = tmp_path / "rows.npz"
    path.write_bytes(content)
    with pytest.raises(armik.InputError) as info:
        armik.BatchResult.load(path)
    said = str(info.value)
    assert str(path) in said and f"({kind}, not an .npz archive)" in said, said
    assert "pickle" not in said


@pytest.mark.parametrize("path", [5, None, 3.5])
def test_a_path_that_is_no_path_is_refused_by_value(path):
    b = _batch()
    for call, verb in (
        (lambda: b.save(path), "save to"),
        (lambda: armik.BatchResult.load(path), "load from"),
    ):
        with pytest.raises(armik.InputError) as info:
            call()
        assert f"cannot {verb} {path!r}: give a file's path" in str(info.value)


def test_a_truncated_saved_batch_is_named_not_a_zip_error(tmp_path):
    """Half of a saved batch (an archive's signature, no directory): an ``InputError``
    naming the file, not ``zipfile.BadZipFile``."""
    whole = _batch().save(tmp_path / "whole.npz")
    cut = tmp_path / "cut.npz"
    cut.write_bytes(whole.read_bytes()[: len(whole.read_bytes()) // 2])
    with pytest.raises(armik.InputError, match="cut.npz"):
        armik.BatchResult.load(cut)
