"""The compile notice names the part that compiles: the conversion of joint values to
Pinocchio's (``armik.kernel.coordinates``, an arm with continuous joints, any first call,
a closed form's too) compiles in well under a second and says nothing of its own, where it
said "the numeric solvers" (``kernel.notice``)."""

from __future__ import annotations

import io
from types import SimpleNamespace

import pytest

from armik.kernel import notice

CONVERSION = "armik.kernel.coordinates"


def _compile(n: notice._Notice, module: str) -> None:
    func = SimpleNamespace(__module__=module, __qualname__="first")
    ev = SimpleNamespace(data={"dispatcher": SimpleNamespace(py_func=func)})
    n.on_start(ev)
    n.on_end(ev)


def _said(*modules: str) -> str:
    stream = io.StringIO()
    n = notice._Notice(stream)
    for module in modules:
        _compile(n, module)
    if n.closing is not None:
        n.closing.join()
    n._close()
    return stream.getvalue()


@pytest.fixture(autouse=True)
def quick(monkeypatch, tmp_path):
    monkeypatch.setenv(notice.ENVIRONMENT, "1")
    monkeypatch.setenv(notice.TIMES_ENVIRONMENT, str(tmp_path / notice.TIMES))
    monkeypatch.setattr(notice, "BURST_GAP", 0.01)


def test_the_conversion_alone_names_no_solver():
    assert "numeric solvers" not in _said(CONVERSION)


def test_a_closed_forms_first_call_on_continuous_joints_names_the_closed_form_only():
    said = _said(CONVERSION, "armik.solvers.closed_form.planar2r_kernel")
    assert said.count("armik: compiling") == 1, said
    assert "the planar 2-link closed form" in said and "numeric solvers" not in said


def test_the_conversion_within_a_numeric_solve_keeps_its_one_line():
    said = _said("armik.kernel.step", CONVERSION, "armik.kernel.entry")
    assert said.count("armik: compiling the numeric solvers") == 1 == said.count("armik:")


def test_the_conversion_in_the_background_says_nothing(monkeypatch, capsys):
    monkeypatch.setattr(notice, "_BACKGROUND", set())
    notice.in_background(CONVERSION, "pin_configuration")
    assert capsys.readouterr().err == ""
