"""A plain install (no extras): a flag that needs one says what to install in one line,
before the run it would otherwise end, and a missing peer is named with its extra."""

from __future__ import annotations

import sys

import pytest

from armik.errors import ArmikError
from armik.tools import compare, compare_plots

from .cli_run import run

PLOT = 'pip install "armik[plot]"'
PEERS = 'pip install "armik[peers]"'


def _refuse(*args, **kwargs):
    raise AssertionError("the run started before the missing extra was said")


def test_reach_plot_without_matplotlib_stops_before_the_map(capsys, monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib fails
    out = tmp_path / "reach.npz"
    code, _, err = run(
        capsys, "reach", "planar_2link", "--resolution", "0.5", "-o", out,
        "--plot", tmp_path / "reach.png",
    )  # fmt: skip
    assert code == 2 and PLOT in err and len(err.strip().splitlines()) == 1
    assert not out.exists()  # nothing computed: the map would have been written first


def test_compare_plot_without_matplotlib_stops_before_the_run(capsys, monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setattr(compare, "run", _refuse)
    code, out, err = run(capsys, "compare", "-n", "2", "--plot", tmp_path / "figures")
    assert code == 2 and out == ""
    assert err.startswith("armik: error: --plot") and PLOT in err
    assert len(err.strip().splitlines()) == 1


def test_comparison_figures_without_matplotlib_raise_an_armik_error(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ArmikError, match=r'pip install "armik\[plot\]"'):
        compare_plots.plot(compare.Report(), tmp_path)


def test_view_without_viser_says_so_before_loading_or_solving(capsys, monkeypatch, tmp_path):
    from armik.tools.cli import view

    monkeypatch.setitem(sys.modules, "viser", None)
    monkeypatch.setattr(view, "load_arm", _refuse)
    monkeypatch.setattr(view, "_solve_paths", _refuse)
    code, out, err = run(capsys, "view", "ur5", "--no-browser", "--path", tmp_path / "x.npy")
    assert code == 2 and out == ""
    assert 'pip install "armik[view]"' in err and len(err.strip().splitlines()) == 1


def _without_peers(monkeypatch):
    for name in ("roboticstoolbox", "eaik", "eaik.IK_URDF"):
        monkeypatch.setitem(sys.modules, name, None)


def test_bench_names_the_extra_of_a_missing_peer_and_still_times_armik(capsys, monkeypatch):
    _without_peers(monkeypatch)
    code, out, _ = run(
        capsys, "bench", "--arms", "ur5", "--solvers", "dls", "-n", "2", "--peers", "rtb", "eaik"
    )
    assert code == 0 and "| ur5 | dls | 2 |" in out
    assert f"rtb skipped on ur5: roboticstoolbox-python is not installed: {PEERS}" in out
    assert f"eaik skipped on ur5: EAIK is not installed: {PEERS}" in out


def test_compare_says_once_that_eaik_is_not_installed(monkeypatch):
    _without_peers(monkeypatch)
    notes: list[str] = []
    for name in ("ur5", "abb_irb120"):  # two arms, one note
        assert compare._eaik_row(compare.load(name), [], notes) is None
    assert notes == [f"eaik not timed: EAIK is not installed: {PEERS}"]
    report = compare.Report(notes=notes)
    assert report.text().splitlines()[-1] == notes[0]
    assert report.as_dict()["notes"] == notes


def test_compare_speed_says_eaik_is_not_installed(capsys, monkeypatch):
    _without_peers(monkeypatch)
    code, out, _ = run(capsys, "compare", "--speed", "-n", "2")
    assert code == 0 and "| ur5 | three_parallel | 2/2 |" in out
    assert out.strip().splitlines()[-1] == f"eaik not timed: EAIK is not installed: {PEERS}"


@pytest.mark.parametrize(
    "command, extra",
    [("reach", "plot"), ("compare", "plot"), ("batch", "cluster"), ("bench", "peers"),
     ("view", "view")],
)  # fmt: skip
def test_help_names_the_extra_a_flag_needs(capsys, command, extra):
    code, out, _ = run(capsys, command, "--help")
    assert code == 0 and f"(needs armik[{extra}])" in " ".join(out.split())
