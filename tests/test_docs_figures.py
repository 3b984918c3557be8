"""Counts the docs state are what the benchmark script named beside them prints: the
scripts are seeded, so a count that moves with the code moves the test (the docs are
updated with the script's new output). Their counts use no clock:
``benchmarks/global_paths.py``'s numeric xArm7 solves run on an ``iteration_budget`` here,
which gives the counts its timeout gives (``max_restarts`` ends them first)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
needs_docs = pytest.mark.skipif(not DOCS.is_dir(), reason="docs/ is not part of this tree")


def _flat(page: str) -> str:
    return " ".join((DOCS / page).read_text().split())


@needs_docs
def test_several_tips_collisions_among_close_targets_are_the_script_s():
    from benchmarks.arms_collisions import measure

    text = _flat("several-tips.md")
    found = re.search(
        r"(\d+) collisions in (\d+) targets where each chain checked alone leaves (\d+), "
        r"every success re-checked; `python benchmarks/arms_collisions.py -n (\d+)`",
        text,
    )
    assert found, "several-tips.md no longer states the script's collision counts"
    collisions, n, alone, n_command = map(int, found.groups())
    assert n == n_command
    m = measure(n, 0)
    assert (m["statuses"].get("collision", 0), m["alone"]) == (collisions, alone)
    assert m["false"] == 0 and m["batch_agrees"]


@needs_docs
def test_servo_settle_counts_are_the_script_s():
    from benchmarks.servo_settle import totals

    text = _flat("servo.md")
    found = re.search(
        r"`python benchmarks/servo_settle.py` \(20 random reachable targets .*?5 s each\): "
        r"(\d+) of (\d+) reached, (\d+) ending on `singularity`, (\d+) `stalled`, "
        r"(\d+) still moving",
        text,
    )
    assert found, "servo.md no longer states the script's settle counts"
    reached, n, singular, stalled, moving = map(int, found.groups())
    total = totals()
    got = (total["reached"], total["targets"], total["last singularity"])
    assert got == (reached, n, singular)
    assert (total["last stalled"], total["moving"]) == (stalled, moving)
    assert total["stalled_on_way"] == 0


@needs_docs
def test_paths_numeric_arm_counts_are_the_script_s():
    from benchmarks.global_paths import run

    text = _flat("paths.md")
    found = re.search(
        r"`python benchmarks/global_paths.py --arms xarm7 --paths 20 -n 100`: solved end to "
        r"end: follow (\d+) / 20, global from q0 (\d+) / 20, global from any start (\d+) / 20; "
        r"waypoints flagged (\d+) / (\d+) / (\d+);",
        text,
    )
    assert found, "paths.md no longer states the script's xArm7 counts"
    shown = list(map(int, found.groups()))
    counts = run("xarm7", 20, 100, 0.005, iteration_budget=10**7)
    plans = ("follow", "global", "global, any start")
    assert [counts[p][0] for p in plans] + [counts[p][1] for p in plans] == shown


@needs_docs
def test_readme_s_misses_of_the_one_dimensional_searches_are_the_script_s():
    from benchmarks.families_6r import FAMILIES, measure

    text = " ".join((DOCS.parent / "README.md").read_text().split())
    found = re.search(
        r"(\d+) of (\d+) in `benchmarks/families_6r.py --arms (\d+) --configs (\d+)`", text
    )
    assert found, "README no longer states the searches' misses"
    missed, total, arms, configs = map(int, found.groups())
    searches = ("two_parallel", "two_intersecting")
    assert total == len(searches) * arms * configs
    got = [measure(s, FAMILIES[s], arms, configs, 0) for s in searches]
    assert sum(m["false"] + m["limits"] for m in got) == 0
    assert sum(m["checked"] - m["found"] + m["near"] - m["near_found"] for m in got) == missed
