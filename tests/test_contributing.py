"""CONTRIBUTING.md names every module of the package, so that its layout table stays the
map of the code: a new module without a line there fails here."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_module_is_named_in_the_layout():
    text = (ROOT / "CONTRIBUTING.md").read_text()
    missing = [
        str(path.relative_to(ROOT / "src" / "armik"))
        for path in sorted((ROOT / "src" / "armik").rglob("*.py"))
        if path.name != "__init__.py" and f"`{path.name}`" not in text
    ]
    assert not missing, f"CONTRIBUTING.md's layout does not name: {missing}"


def test_every_package_has_a_row():
    text = (ROOT / "CONTRIBUTING.md").read_text()
    packages = [
        p.relative_to(ROOT / "src" / "armik").as_posix()
        for p in sorted((ROOT / "src" / "armik").iterdir())
        if p.is_dir() and (p / "__init__.py").exists()
    ]
    assert all(f"`{name}/`" in text for name in packages), packages
