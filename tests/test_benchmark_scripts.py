"""Benchmark scripts that the docs name run to their end (their figures are in
docs/performance.md and docs/servo.md): each part called with little work, for what it
prints or returns, not for its times."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest


def test_fixed_cost_measures_a_closed_form_with_or_without_eaik():
    from benchmarks.fixed_cost import NOTES, measure

    m = measure("ur5", "auto", 3)
    assert m["solver"] == "three_parallel"
    assert all(np.isfinite(m[k]) and m[k] > 0 for k in ("solve_us", "solve_all_us"))
    if importlib.util.find_spec("eaik") is None:
        assert "eaik_us" not in m and any("eaik not timed" in n for n in NOTES)
    else:
        assert m["eaik_us"] > 0


def test_servo_benchmark_runs_its_sphere_stream(capsys):
    from benchmarks.servo import sphere_stream

    sphere_stream()
    rows = [line for line in capsys.readouterr().out.splitlines() if "avoiding" in line]
    assert [r.split("|")[1].strip() for r in rows] == ["not avoiding", "avoiding"]
    plain, kept = (float(r.split("|")[2]) for r in rows)
    assert plain < 0.0 <= kept  # the sphere on the circle's way, kept clear beside it


def test_preferences_says_what_to_install_without_trac_ik(monkeypatch, capsys):
    if importlib.util.find_spec("trac_ik") is not None:
        pytest.skip("TRAC-IK is installed: the comparison runs")
    from benchmarks import preferences

    monkeypatch.setattr("sys.argv", ["preferences.py", "-n", "1"])
    with pytest.raises(SystemExit) as info:
        preferences.main()
    assert info.value.code == 2 and "pip install pytracik" in capsys.readouterr().err


def test_every_benchmark_script_is_in_the_benchmarks_page():
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    page = root / "docs" / "benchmarks.md"
    if not page.exists():
        pytest.skip("docs/ is not part of this tree")
    text = page.read_text()
    scripts = sorted(p.name for p in (root / "benchmarks").glob("*.py") if p.name != "__init__.py")
    helpers = {"ssik_prebuilt.py"}  # imported by the ssik scripts, named in their row
    assert [s for s in scripts if f"| `{s}` |" not in text and s not in helpers] == []
