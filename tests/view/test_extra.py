"""The viewer is an optional extra: ``import armik`` loads neither viser nor matplotlib, the
core never imports armik.view, and without viser armik.view says how to install it."""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import armik

SRC = Path(armik.__file__).parent


def run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)


def test_import_armik_stays_light():
    proc = run(
        "import sys, armik\n"
        "heavy = ('viser', 'matplotlib', 'trimesh', 'armik.view', 'scipy.optimize', "
        "'qpsolvers')\n"
        "print(sorted(m for m in heavy if m in sys.modules))"
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


def test_without_viser_view_says_how_to_install_it():
    proc = run(
        "import sys; sys.modules['viser'] = None\n"  # as if it were not installed
        "import armik\n"
        "try:\n"
        "    armik.view(armik.load('planar_2link'), port=0, open_browser=False)\n"
        "except armik.ViewerError as exc:\n"
        "    print(exc)\n"
    )
    assert proc.returncode == 0, proc.stderr
    (line,) = proc.stdout.splitlines()
    assert 'pip install "armik[view]"' in line


def test_without_pycollada_the_dae_meshes_warning_says_how_to_install_it():
    """The Kinova's .dae meshes without pycollada: the stick figure, and a warning naming
    the extra to install, not a path to check."""
    proc = run(
        "import sys, warnings; sys.modules['collada'] = None\n"  # as if it were not installed
        "import armik\n"
        "from armik.view.scene import arm_body\n"
        "with warnings.catch_warnings(record=True) as caught:\n"
        "    warnings.simplefilter('always')\n"
        "    body = arm_body(armik.load('kinova').kinematics)\n"
        "print(body.kind)\n"
        "for w in caught:\n"
        "    print(w.message)\n"
    )
    assert proc.returncode == 0, proc.stderr
    kind, said = proc.stdout.splitlines()  # one warning
    assert kind == "stick"
    assert "base.dae" in said and 'pip install "armik[view]"' in said, said
    assert "ROS_PACKAGE_PATH" not in said


def test_the_view_names_are_there():
    assert {"view", "plot", "Viewer", "ViewerError", "Box", "Sphere"} <= set(armik.__all__)
    assert callable(armik.view) and callable(armik.plot)
    importlib.import_module("armik.view.plot")  # a submodule: armik.view stays callable
    assert callable(armik.view) and armik.Viewer.__name__ == "Viewer"


def test_the_core_never_imports_the_viewer():
    offenders = []
    for path in SRC.rglob("*.py"):
        rel = path.relative_to(SRC)
        if rel.parts[0] in ("view", "tools") or rel == Path("__init__.py"):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            if any(n == "armik.view" or n.startswith("armik.view.") for n in names):
                offenders.append(str(rel))
    assert not offenders, f"the core imports armik.view: {sorted(set(offenders))}"
