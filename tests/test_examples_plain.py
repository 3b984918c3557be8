"""The examples on a plain install (no matplotlib, no viser): each runs, prints its results,
and says in one line what the figures need, never a ModuleNotFoundError."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

EXAMPLES = Path(__file__).parents[1] / "examples"
RUNNER = Path(__file__).with_name("run_examples.py")
SKIPPED = 'figures skipped: matplotlib is not installed: pip install "armik[plot]"'
# 07_compare.py, the slowest, takes the same _common.pyplot() guard as these
EXPECT = {
    "02_elbow_branches.py": [],
    "06_cartesian_path.py": ["100/100 points reached"],
    "08_many_targets.py": ["batch:", "no snap back", "reach:"],
    "09_view.py": ["8 branches, all verified: True", 'viewer skipped: pip install "armik[view]"'],
}
HIDE = "import sys, runpy\nfor m in ('matplotlib', 'viser'):\n    sys.modules[m] = None\n"


def test_examples_run_without_the_extras(tmp_path):
    scripts = [str(EXAMPLES / name) for name in EXPECT]
    code = HIDE + f"sys.argv = {[str(RUNNER), str(tmp_path), *scripts]!r}\n"
    code += f"runpy.run_path({str(RUNNER)!r}, run_name='__main__')\n"
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=1200
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for name, words in EXPECT.items():
        stem = Path(name).stem
        stdout = (tmp_path / f"{stem}.stdout").read_text(encoding="utf-8")
        stderr = (tmp_path / f"{stem}.stderr").read_text(encoding="utf-8")
        assert (tmp_path / f"{stem}.code").read_text() == "0", (name, stderr)
        assert stdout.splitlines()[0] == SKIPPED, (name, stdout)
        assert "Error" not in stderr, (name, stderr)
        for w in words:
            assert w in stdout, (name, w, stdout)
        assert not list((tmp_path / stem).glob("*.png")), name
