"""A numba cache seeded with this process's entries of armik's compiled functions, for a test
that compiles on a cache of its own in a process of its own: what it is not about (the FK,
the region's rows, the linear algebra) is loaded there when the suite's cache holds it (the
tour has filled it) instead of compiled again; with nothing in the suite's cache, the test
compiles everything, as on an empty one."""

from __future__ import annotations

import importlib
import pkgutil
import shutil
from collections.abc import Callable
from pathlib import Path


def seed(
    cache: Path,
    compiled_there: Callable[[object, str], bool],
    packages: tuple[str, ...] = ("armik.kernel",),
) -> None:
    """Copy into ``cache`` (a ``NUMBA_CACHE_DIR``) this process's cache entries of every
    compiled function of ``packages`` but those ``compiled_there(dispatcher, module)`` says
    the test's processes compile themselves."""
    from numba.core.caching import UserProvidedCacheLocator
    from numba.core.registry import CPUDispatcher

    modules = [
        info.name
        for package in packages
        for info in pkgutil.iter_modules(importlib.import_module(package).__path__, package + ".")
    ]
    for name in modules:
        module = importlib.import_module(name)
        for d in vars(module).values():
            if not isinstance(d, CPUDispatcher) or d.py_func.__module__ != name:
                continue
            here = getattr(d._cache, "_cache_path", None)  # numba's names, not public API
            if here is None or compiled_there(d, name):
                continue
            index = d._cache._cache_file._index_name
            there = cache / UserProvidedCacheLocator.get_suitable_cache_subpath(
                d.py_func.__code__.co_filename
            )
            for path in Path(here).glob(index[: -len(".nbi")] + ".*"):
                there.mkdir(parents=True, exist_ok=True)
                shutil.copy2(path, there / path.name)
