"""Bad input to the facade gets armik's own error naming the value and the fix, never a
raw numpy, Pinocchio or OS exception and never a silent answer."""

from __future__ import annotations

import numpy as np
import pytest

import armik
from armik.collision import write_srdf
from armik.tools.cli import main


@pytest.fixture(scope="module")
def ur5():
    return armik.load("ur5")


@pytest.mark.parametrize("q", [[], [0.0], [0.0] * 9], ids=["empty", "one", "nine"])
def test_within_limits_refuses_another_arms_length(ur5, q):
    with pytest.raises(armik.OptionError, match=rf"q must have 6 values .*shape \({len(q)},\)"):
        ur5.within_limits(q)


def test_within_limits_refuses_no_numbers_and_several_rows(ur5):
    with pytest.raises(armik.OptionError, match="q must be 6 numbers.*'abc'"):
        ur5.within_limits("abc")
    with pytest.raises(armik.OptionError, match=r"shape \(3, 6\); for 3 configurations"):
        ur5.within_limits(np.zeros((3, 6)))
    with pytest.raises(armik.OptionError, match="tol must be a number, got 'x'"):
        ur5.within_limits(ur5.middle, tol="x")
    assert ur5.within_limits(ur5.middle)
    assert not ur5.within_limits([np.nan] * 6)  # a NaN is outside, as before
    assert not ur5.within_limits(ur5.upper + 0.1)


@pytest.mark.parametrize("rng", ["x", -1, 1.5])
def test_random_q_refuses_a_seed_numpy_cannot_take(ur5, rng):
    with pytest.raises(armik.OptionError, match=f"rng must be .*got {rng!r}") as info:
        ur5.random_q(rng)
    assert info.value.option == "rng"
    np.testing.assert_array_equal(ur5.random_q(3), ur5.random_q(np.random.default_rng(3)))


def test_posture_refuses_no_numbers():
    with pytest.raises(armik.OptionError, match="Posture q_ref .*got 'x'"):
        armik.Posture("x")
    with pytest.raises(armik.OptionError, match="Posture q_ref .*got \\[\\]"):
        armik.Posture([])
    with pytest.raises(armik.OptionError, match="Posture weights must be 6 numbers .*'ab'"):
        armik.Posture([0.0] * 6, weights="ab")


def test_a_backend_returning_no_results_is_named(ur5):
    T = ur5.fk(ur5.random_q(0))

    def nothing(jobs, workers):
        return None

    for backend, got in ((nothing, "None"), (lambda jobs, workers: 3, "3")):
        with pytest.raises(armik.ArmikError, match=f"returned {got}: a backend returns"):
            ur5.solve_batch([T, T], backend=backend)


def test_export_into_a_file_names_the_path(ur5, tmp_path):
    file = tmp_path / "existing"
    file.write_text("x")
    with pytest.raises(armik.OptionError, match=f"out='{file}' cannot hold") as info:
        armik.export(ur5, "u", out=file)
    assert info.value.option == "out"
    files = armik.export(ur5, "u", out=tmp_path / "new")  # a new folder is made
    assert sorted(p.name for p in (tmp_path / "new").iterdir()) == sorted(files)


def test_saving_a_batch_where_it_cannot_be_written_names_the_path(ur5, tmp_path):
    res = ur5.solve_batch([ur5.fk(ur5.middle)])
    nowhere = tmp_path / "no" / "x.npz"
    with pytest.raises(armik.InputError, match=f"cannot write '{nowhere}'.*existing folder"):
        res.save(nowhere)
    with pytest.raises(armik.InputError, match=f"cannot write '{tmp_path}'"):
        res.save(tmp_path)  # a folder


def test_srdf_refuses_a_urdf_and_other_xml(ur5, tmp_path):
    with pytest.raises(armik.CollisionError, match="is a URDF, not an SRDF.*<joint>, <link>"):
        armik.load("ur5", srdf=ur5.source)
    other = tmp_path / "other.xml"
    other.write_text("<config><x/></config>")
    with pytest.raises(armik.CollisionError, match=f"'{other}' is not an SRDF.*<config>"):
        armik.load("ur5", srdf=other)
    stray = tmp_path / "stray.srdf"
    stray.write_text('<robot name="ur5"><bar/></robot>')
    with pytest.raises(armik.CollisionError, match=f"'{stray}' is not an SRDF.*<bar>"):
        armik.load("ur5", srdf=stray)
    empty = tmp_path / "empty.srdf"
    write_srdf([], empty)  # no pair to disable: still an SRDF
    assert armik.load("ur5", srdf=empty).kinematics.disabled_pairs == frozenset()


def test_cli_batch_says_which_arrays_it_reads(ur5, tmp_path, capsys):
    poses = np.array([ur5.fk(ur5.random_q(i)).homogeneous for i in range(2)])
    out = str(tmp_path / "o.npz")
    np.savez(tmp_path / "foo.npz", foo=poses)
    assert main(["batch", "ur5", str(tmp_path / "foo.npz"), "-o", out]) == 2
    err = capsys.readouterr().err
    assert "['foo']" in err and "'targets'" in err and "'q0'" in err, err
    np.savez(tmp_path / "seeds.npz", targets=poses, seeds=np.zeros((2, 6)))
    assert main(["batch", "ur5", str(tmp_path / "seeds.npz"), "-o", out]) == 2
    assert "does not read: ['seeds']" in capsys.readouterr().err
    np.savez(tmp_path / "plain.npz", poses)  # numpy's own name, arr_0, for one array
    assert main(["batch", "ur5", str(tmp_path / "plain.npz"), "-o", out]) == 0


def test_an_int_beyond_a_floats_range_is_an_armik_error_everywhere():
    """A Python int too large for a float (10**400) in a configuration, a seed, a batch's
    seeds, a target or a tolerance is an armik error naming it, where Python's
    ``OverflowError`` escaped."""
    a = armik.load("scara")
    big = 10**400
    T = a.fk(np.zeros(4))
    calls = [
        lambda: a.fk([big, 0, 0, 0]),
        lambda: a.fk_batch([[big, 0, 0, 0]]),
        lambda: a.within_limits([big, 0, 0, 0]),
        lambda: a.solve(T, q0=[big, 0, 0, 0]),
        lambda: a.solve_batch([T, T], q0=[big, 0, 0, 0]),
        lambda: a.solve_path([T, T], [big, 0, 0, 0]),
        lambda: a.solve([big, 0, 0]),
        lambda: a.solve_batch([[big, 0, 0]] * 2),
        lambda: a.solve(T, tol_position=big),
    ]
    for call in calls:
        with pytest.raises(armik.ArmikError):
            call()


@pytest.mark.parametrize(
    "options",
    [{"position_only": np.array([1.0, 0.0])}, {"bounds": (0.1, 0.1, -1.0)}],
    ids=["position_only array", "bounds of 3"],
)
def test_an_option_beside_a_task_list_is_named_before_the_tasks_read_it(ur5, options):
    """An option given beside a task list the compiled path lowers was read against the
    tasks before it was checked: numpy's "truth value of an array is ambiguous"."""
    T = ur5.fk(ur5.middle)
    tasks = [armik.Pose(T)]
    name = next(iter(options))
    with pytest.raises(armik.OptionError, match=name):
        ur5.solve(tasks, **options)
    with pytest.raises(armik.OptionError, match=name):
        ur5.solve_batch([tasks, tasks], **options)
    with pytest.raises(armik.OptionError, match=name):
        ur5.solve_path([tasks, tasks], ur5.middle, **options)


@pytest.mark.parametrize("key", ["tol_position", "tol_orientation"])
@pytest.mark.parametrize("route", ["solve", "solve_all", "solve_batch", "solve_path"])
def test_a_tolerance_below_what_double_precision_verifies_is_refused(ur5, key, route):
    # at 2e-16 an independent FK put 17 of solve_all's successes past the tolerance by
    # rounding alone; 1e-12 is the floor the exported solver keeps too
    q = ur5.middle + 0.1
    T = ur5.fk(q)
    call = {
        "solve": lambda **o: ur5.solve(T, **o),
        "solve_all": lambda **o: ur5.solve_all(T, **o)[0],
        "solve_batch": lambda **o: ur5.solve_batch([T, T], **o),
        "solve_path": lambda **o: ur5.solve_path([T, T], q, **o),
    }[route]
    with pytest.raises(armik.OptionError, match=rf"{key}=2e-16 is below .* at least 1e-12"):
        call(**{key: 2e-16})
    assert np.all(np.atleast_1d(call(**{key: 1e-12}).success))


def test_a_finite_bound_beyond_any_reach_is_refused_with_inf_as_the_way(ur5):
    # (1e300,) * 3 overflowed numpy's dot in the numeric solver's error norm
    T = ur5.fk(ur5.middle + 0.1)
    with pytest.raises(armik.OptionError, match=r"at most 1e6 .*math.inf frees"):
        ur5.solve(T, bounds=(1e300,) * 3 + (0.0,) * 3)
    assert ur5.solve(T, bounds=(float("inf"),) * 3 + (0.0,) * 3).success


def test_a_batch_of_task_lists_names_the_row_that_is_not_one(ur5):
    p = ur5.fk(ur5.middle).translation
    rows = [[armik.Position(p)]] * 2 + [[armik.Position(p), 5]]
    with pytest.raises(armik.TargetError, match="target 2: a list of tasks holds only tasks"):
        ur5.solve_batch(rows)


def test_a_name_in_another_case_is_suggested():
    with pytest.raises(armik.ArmikError, match="did you mean 'ur5'"):
        armik.load("UR5")
