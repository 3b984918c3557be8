"""armik's numba caches are stamped by every source they depend on (``armik.compiled_cache``):
an edit to a callee or a constant in another module makes every cached caller stale."""

from __future__ import annotations

import os
from pathlib import Path

import armik  # noqa: F401  (registers the locators)
from armik import compiled_cache
from armik.kernel.descent import solve_one_dls
from armik.kernel.fk import forward
from armik.solvers.closed_form.three_parallel import solve_into


def test_armik_functions_are_cached_under_the_stamp_of_every_source():
    for dispatcher in (forward, solve_one_dls, solve_into):
        locator = dispatcher._cache._impl.locator
        assert type(locator).__name__.startswith("Armik"), type(locator)
        assert locator.get_source_stamp() == compiled_cache.stamp()


def _package(tmp_path: Path) -> Path:
    root = tmp_path / "armik"
    (root / "sub").mkdir(parents=True)
    files = {
        "kernel.py": "from numba import njit\nfrom armik.consts import X\n"
        "from armik import (\n    helper,\n)\nfrom armik.api import Options\n\n"
        "@njit\ndef f():\n    return X\n",
        "api.py": "class Options:\n    pass\n",
        "consts.py": "X = 1\n",
        "helper.py": "Y = 2\n",
        "other.py": "Z = 3\n",
        "sub/__init__.py": "",
        "sub/plain.py": "from armik.other import Z\n",
    }
    for name, text in files.items():
        (root / name).write_text(text)
    return root


def _touch(path: Path) -> None:
    st = path.stat()
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))


def test_the_stamp_follows_compiled_modules_and_what_they_import(tmp_path):
    root = _package(tmp_path)
    names = [str(p.relative_to(root)) for p in compiled_cache.depended_on(root)]
    assert names == ["consts.py", "helper.py", "kernel.py"]
    before = compiled_cache.stamp(root)
    _touch(root / "other.py")  # no compiled module reads it
    _touch(root / "sub" / "plain.py")
    _touch(root / "api.py")  # a class, which compiled code cannot read
    assert compiled_cache.stamp(root) == before
    for name in names:  # the compiled module, a module it reads a constant of, one it imports
        _touch(root / name)
        after = compiled_cache.stamp(root)
        assert after != before
        before = after


def test_every_module_with_compiled_code_is_stamped():
    """A module that compiles (``@njit``, ``njit(``) is found by its import of ``njit``: one
    that spelled it otherwise would cache stale code unseen."""
    stamped = set(compiled_cache.depended_on())
    for path in compiled_cache.PACKAGE.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        if "@njit" in text or "= njit(" in text:
            assert path in stamped, path


def test_this_numba_takes_the_stamped_locators():
    """The locators registered (an unknown numba's caching module would leave numba's own:
    this catches the day that happens)."""
    assert len(compiled_cache.LOCATORS) == 3
