"""A plain install (no extras): a missing peer is named with its extra."""

from __future__ import annotations

import sys

from armik.tools import compare

from .cli_run import run

PEERS = 'pip install "armik[peers]"'


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
