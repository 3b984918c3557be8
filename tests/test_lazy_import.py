"""``import armik`` loads nothing else (not even numba); each public name imports its module
at its first use, and is then the same object as before: the functions ``armik.solvers`` and
``armik.export`` stay functions whatever of their packages is imported first."""

from __future__ import annotations

import subprocess
import sys
import types

import armik


def run(code: str) -> str:
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip()


def test_import_armik_loads_nothing_else():
    loaded = run(
        "import sys, armik\n"
        "heavy = ('numba', 'numpy', 'pinocchio', 'coal', 'scipy', 'qpsolvers', 'yourdfpy')\n"
        "print(sorted(m for m in sys.modules if m.startswith('armik')))\n"
        "print(sorted(m for m in heavy if m in sys.modules))"
    )
    assert loaded.splitlines() == ["['armik']", "[]"]


def test_every_public_name_resolves_to_its_module_object():
    from armik.errors import ArmikError
    from armik.loading import load
    from armik.precompile import compile
    from armik.problem import Pose

    for name in armik.__all__:
        assert getattr(armik, name) is not None, name
    assert set(armik.__all__) <= set(dir(armik))
    assert armik.load is load and armik.ArmikError is ArmikError and armik.Pose is Pose
    assert armik.compile is compile
    assert isinstance(armik.collision, types.ModuleType) and callable(armik.view)


def test_dir_lists_the_public_names_only():
    """dir(armik) listed TYPE_CHECKING and annotations (this file's imports), its private
    names and every subpackage imported so far."""
    armik.load("planar_2link").solve([1.2, 0.5])  # imports armik.model, armik.solve, ...
    listed = {n for n in dir(armik) if not (n.startswith("__") and n.endswith("__"))}
    assert listed == set(armik.__all__), listed ^ set(armik.__all__)
    assert "__version__" in dir(armik) and "__doc__" in dir(armik)


def test_an_unknown_name_is_an_attribute_error():
    try:
        armik.no_such_name  # noqa: B018
    except AttributeError as exc:
        assert "no_such_name" in str(exc)
    else:
        raise AssertionError("armik.no_such_name resolved")


def test_solvers_and_export_stay_functions_when_their_packages_load_first():
    # each package imported before the name is read: the import sets it as armik's attribute
    out = run(
        "import armik, types\n"
        "import armik.solvers.registry, armik.export.c_source\n"
        "print(isinstance(armik.solvers, types.FunctionType), "
        "isinstance(armik.export, types.FunctionType), 'dls' in armik.solvers())"
    )
    assert out == "True True True"


def test_the_cli_imports_no_scipy_spatial_until_a_reach_map():
    loaded = run(
        "import sys\n"
        "from armik.tools.cli import main\n"
        "print(sorted(m for m in ('scipy.spatial', 'qpsolvers') if m in sys.modules))"
    )
    assert loaded == "[]"
