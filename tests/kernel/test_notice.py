"""The compile notice (``kernel.notice``): one line for a burst, held open while the
helper is awaited, and a duration measured on this machine once there is one."""

from __future__ import annotations

import io
import json
from types import SimpleNamespace

import pytest

from armik.kernel import notice


def _event(module: str):
    func = SimpleNamespace(__module__=module, __qualname__="first")
    return SimpleNamespace(data={"dispatcher": SimpleNamespace(py_func=func)})


def _compile(n: notice._Notice, module: str = "armik.kernel.step") -> None:
    n.on_start(_event(module))
    n.on_end(_event(module))


@pytest.fixture
def quick(monkeypatch, tmp_path):
    monkeypatch.setenv(notice.ENVIRONMENT, "1")
    monkeypatch.setenv(notice.TIMES_ENVIRONMENT, str(tmp_path / notice.TIMES))
    monkeypatch.setattr(notice, "BURST_GAP", 0.01)


def _key(what: str, module: str = "armik.kernel.step") -> str:
    return notice.record_key(what, f"{module}.first")


def _closed(n: notice._Notice) -> None:
    """Wait for the line's closing timer, then close what is left at once."""
    if n.closing is not None:
        n.closing.join()
    n._close()


def test_a_hold_keeps_one_line_across_a_wait(quick):
    stream = io.StringIO()
    n = notice._Notice(stream)
    with n.held():
        _compile(n)  # this process's share
        assert n.closing is None  # a wait for the helper here does not close the line
    _compile(n)  # the entry, after the wait
    _closed(n)
    assert stream.getvalue().count("armik: compiling the numeric solvers") == 1


def test_without_a_hold_a_pause_gives_a_second_line(quick):
    stream = io.StringIO()
    n = notice._Notice(stream)
    _compile(n)
    _closed(n)  # a pause longer than BURST_GAP
    _compile(n)
    _closed(n)
    assert stream.getvalue().count("armik: compiling the numeric solvers") == 2


def test_the_duration_said_is_measured_here_once_there_is_one(quick, tmp_path):
    stream = io.StringIO()
    n = notice._Notice(stream)
    _compile(n)
    assert "(once; about 25 s on a quiet 2-core machine)" in stream.getvalue()
    _closed(n)
    took = json.loads((tmp_path / notice.TIMES).read_text())[_key("the numeric solvers")]
    assert 0.0 <= took < 60.0
    _compile(n)  # a later notice of the part (another cache, an upgrade)
    assert f"(once; it took {took:.0f} s here last time)" in stream.getvalue()
    _closed(n)


def test_an_unwritable_place_leaves_the_notice_as_it_was(quick, monkeypatch, tmp_path):
    blocked = tmp_path / "file"
    blocked.write_text("")
    monkeypatch.setenv(notice.TIMES_ENVIRONMENT, str(blocked / notice.TIMES))  # no such dir
    notice.record("the numeric solvers", 3.0)
    assert notice.measured() == {}


def test_a_line_open_at_exit_is_measured_to_its_last_compilation(quick, tmp_path):
    n = notice._Notice(io.StringIO())
    _compile(n)
    n._close()  # what the exit does when the closing timer has not run
    took = json.loads((tmp_path / notice.TIMES).read_text())[_key("the numeric solvers")]
    assert took >= 0.0
    assert notice.measured() == {_key("the numeric solvers"): took}


def test_a_line_ended_by_another_part_is_measured_too(quick, tmp_path):
    stream = io.StringIO()
    n = notice._Notice(stream)
    _compile(n, "armik.solvers.closed_form.planar2r_kernel")
    _compile(n)  # the numeric solvers, before the first line's timer ran
    _closed(n)
    assert set(notice.measured()) == {
        _key("the planar 2-link closed form", "armik.solvers.closed_form.planar2r_kernel"),
        _key("the numeric solvers"),
    }
    assert stream.getvalue().count("armik: compiling") == 2


def test_a_burst_that_begins_elsewhere_is_not_told_another_bursts_time(quick, tmp_path):
    """A part compiled whole once, then only in part (its cache partly filled): the second
    burst begins at another function, and is not told the first one's time."""
    stream = io.StringIO()
    n = notice._Notice(stream)
    notice.record(_key("the numeric solvers"), 30.0)
    _compile(n, "armik.kernel.entry")  # another entry of the same part
    _closed(n)
    assert "it took 30 s here last time" not in stream.getvalue()
    assert "about 25 s on a quiet 2-core machine" in stream.getvalue()
    _compile(n)  # the burst that was measured
    _closed(n)
    assert "it took 30 s here last time" in stream.getvalue()
