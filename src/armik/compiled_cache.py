"""numba's on-disk cache of armik's compiled code, stamped by every source it depends on.

numba checks a cached function against its own source file only (its modification time
and size), yet a cached function holds the machine code of the compiled functions it calls
in other modules and the constants it reads from them. After an edit to a callee, a cached
caller would run the callee's old code. armik's functions are cached instead under a stamp
of the contents of every compiled module of the package (one that imports ``njit``) and
every armik module they import a constant from: any edit to one of them compiles armik's
code again, and nothing stale runs. The stamp reads the sources' bytes, not their
modification times, so a cache stays valid where the same sources lie with other times (a
fresh clone or checkout of the same commit, a copied tree, a restored CI cache); numba
itself still refuses an entry compiled by another numba or for another CPU (its index
keys each entry by the CPU's name and features). The cache stays where numba puts it
(``NUMBA_CACHE_DIR``, else the source tree's ``__pycache__``, else the user's cache
directory); only the stamp differs, and each entry is a file of its own (``Entries``), so
that processes compiling the same function at once keep each other's entries.

Imported by ``armik/kernel/__init__.py``, which each package holding compiled modules
(``kernel``, ``constraints``, ``servo``, ``solvers.closed_form``) imports first: numba
picks a function's cache locator when the function is decorated.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import re
import sys
from functools import cache
from pathlib import Path

from numba.core import caching

PACKAGE = Path(__file__).resolve().parent
_COMPILED = re.compile(r"^from numba import [^\n]*\bnjit\b", re.MULTILINE)  # compiles code
# a "from" import of the package, on one line or in parentheses: the module, the names
_CONSTANT = re.compile(r"[A-Z][A-Z0-9_]*")
_ADDRESS = re.compile(r" at 0x[0-9a-fA-F]+")
_IMPORT = re.compile(r"^from (armik(?:\.\w+)*) import (\([^)]*\)|[^\n]*)", re.MULTILINE)


def depended_on(root: Path = PACKAGE) -> list[Path]:
    """The package's compiled modules (they import ``njit`` from numba) and what their
    compiled code can read of other modules, sorted: compiled code calls compiled functions
    only, and reads globals: the modules a compiled module imports whole, and those it
    imports a constant (an upper-case name) from. A module it takes classes or Python
    functions from (``Options``, the registry) does not count: an edit there compiles
    nothing again."""
    # each source by its dotted name within ``root`` (a package by its __init__'s folder);
    # a module file first where both spellings exist, as the paths were tried before.
    # Plain strings, not paths, while they are looked up: hashing a path costs more.
    modules: dict[str, list[str]] = {}
    texts: dict[str, str] = {}
    prefix = len(str(root)) + 1
    for folder, _, files in os.walk(root):
        for file in files:
            if not file.endswith(".py"):
                continue
            name = os.path.join(folder, file)
            with open(name, encoding="utf-8") as f:
                texts[name] = f.read()
            parts = name[prefix:-3].split(os.sep)
            _place(modules, parts, name)
    found: set[str] = set()
    for name, text in texts.items():
        if "njit" not in text or not _COMPILED.search(text):
            continue
        found.add(name)
        for module, names in _IMPORT.findall(text):
            parts = module.split(".")[1:]
            words = re.findall(r"\w+", names)
            wheres = [[*parts, n] for n in words]  # a module imported by its name
            if parts and any(_CONSTANT.fullmatch(n) for n in words):
                wheres.append(parts)
            for where in wheres:
                found.update(modules.get(".".join(where), ()))
    return sorted(map(Path, found))


def _place(modules: dict[str, list[str]], parts: list[str], name: str) -> None:
    """Files ``name`` under its dotted name (``parts``), a package by its folder's, a module
    file before a package's __init__ of the same name."""
    if parts[-1] == "__init__":
        modules.setdefault(".".join(parts[:-1]), []).append(name)
    else:
        modules.setdefault(".".join(parts), []).insert(0, name)


def stamp(root: Path = PACKAGE) -> str:
    """A digest of each depended-on source's path (within ``root``) and contents: the same
    sources give the same stamp wherever they lie and whatever their modification times;
    an edit to any of them gives another."""
    digest = hashlib.sha256()
    for path in depended_on(root):
        content = hashlib.sha256(path.read_bytes()).hexdigest()
        digest.update(f"{path.relative_to(root).as_posix()}:{content};".encode())
    return digest.hexdigest()


@cache
def _stamp() -> str:
    return stamp()


_WRITABLE: set[str] = set()  # the cache folders numba found writable in this process


@cache
def _ours(py_file: str) -> bool:
    """Whether ``py_file`` is one of armik's sources (once per file: a path resolves by a
    system call for each of its parts)."""
    return Path(py_file).resolve().is_relative_to(PACKAGE)


def _stamped(base: type) -> type:
    """``base``, a numba cache locator, for armik's sources only and stamped by them all."""

    class Stamped(base):  # type: ignore[valid-type, misc]
        def get_source_stamp(self) -> str:
            return _stamp()

        def ensure_cache_path(self) -> None:
            # numba's check writes a file in the folder for each function decorated; a folder
            # found writable once in this process is taken as such while it is there
            path = self.get_cache_path()
            if path in _WRITABLE and os.path.isdir(path):
                return
            super().ensure_cache_path()
            _WRITABLE.add(path)

        @classmethod
        def from_function(cls, py_func, py_file):
            if getattr(sys, "frozen", False) or not _ours(py_file):
                return None
            return super().from_function(py_func, py_file)

    Stamped.__name__ = Stamped.__qualname__ = f"Armik{base.__name__}"
    return Stamped


# numba's class of a function's cache files (``_register`` puts ``_files`` in its place)
_NUMBA_FILES = getattr(caching.IndexDataCacheFile, "numba_files", caching.IndexDataCacheFile)


class Entries(_NUMBA_FILES):  # type: ignore[valid-type, misc]
    """The cache files of one armik function: a file for each entry (a signature on a CPU),
    named after it and holding its key, where numba keeps an index of them all. numba's
    save reads the index, adds its entry, writes it back and numbers its data file after
    the entries it read: two processes compiling the function at once (``armik compile``'s
    two, a helper and the program it serves) lost one's entry, or named one's code under
    the other's signature. Here a save writes its own file only (aside, then renamed into
    place), and a load takes a file only if it holds the key asked for, compiled from the
    same sources by the same numba."""

    def __init__(self, cache_path: str, filename_base: str, source_stamp: str) -> None:
        super().__init__(cache_path, filename_base, source_stamp)
        self._base = filename_base

    def save(self, key: tuple, data: object) -> None:
        header, payload = self._dump(self._header(key)), self._dump(data)
        with self._open_for_write(self._entry_path(key)) as f:
            f.write(header)  # read alone by ``holds``
            f.write(payload)
        caching._cache_log("[cache] entry saved to %r", self._entry_path(key))

    def load(self, key: tuple) -> object:
        path = self._entry_path(key)
        try:
            with open(path, "rb") as f:
                if pickle.load(f) != self._header(key):
                    return None
                data = pickle.loads(f.read())
        except Exception:  # none, or not whole: compiled again
            return None
        caching._cache_log("[cache] entry loaded from %r", path)
        return data

    def flush(self) -> None:
        """Remove this function's entries (and any a write left aside): numba's flush
        empties an index, which armik's entries do not read, and left every entry behind."""
        own = re.compile(re.escape(self._base) + r"\.[0-9a-f]{24}\.nbc(\.tmp\.[0-9a-f]+)?")
        try:
            names = os.listdir(self._cache_path)
        except FileNotFoundError:
            return
        for name in names:
            if own.fullmatch(name):
                try:
                    os.unlink(os.path.join(self._cache_path, name))
                except FileNotFoundError:  # removed by another process meanwhile
                    pass
        caching._cache_log("[cache] entries of %r removed", self._base)

    def holds(self, key: tuple) -> bool:
        """Whether the cache holds ``key``'s entry (its file's header read, not its code)."""
        try:
            with open(self._entry_path(key), "rb") as f:
                return bool(pickle.load(f) == self._header(key))
        except Exception:
            return False

    def _header(self, key: tuple) -> tuple:
        return self._version, self._source_stamp, key

    def _entry_path(self, key: tuple) -> str:
        # the signature and the CPU name the file, so that a later compile of the same
        # entry (after an edit) replaces it; the header tells which sources it holds. No
        # address (a function's type names its object's): the same name in every process
        named = _ADDRESS.sub("", repr(key[:2]))
        digest = hashlib.sha256(named.encode()).hexdigest()[:24]
        return os.path.join(self._cache_path, f"{self._base}.{digest}.nbc")


def _files(numba_files: type):
    """What numba builds a function's cache files with: ``Entries`` for armik's functions
    (stamped by ``_stamp``), numba's own class for every other."""

    def files(cache_path: str, filename_base: str, source_stamp: object):
        kind = Entries if source_stamp == _stamp() else numba_files
        return kind(cache_path, filename_base, source_stamp)

    files.numba_files = numba_files  # type: ignore[attr-defined]
    return files


def _numba(name: str):
    """numba's class ``name`` (older releases spell it with a leading underscore)."""
    return getattr(caching, name, None) or getattr(caching, f"_{name}")


def _register() -> tuple:
    """The stamped locators, put before numba's own; none where this numba's caching
    module is not the one they were written for (its classes are not public API): numba's
    own stamps then, as before, rather than an import that fails."""
    try:
        bases = [
            _numba(name)
            for name in ("UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator")
        ]
        classes = _numba("CacheImpl")._locator_classes
    except AttributeError:
        return ()
    # where numba would cache a function, in its order: NUMBA_CACHE_DIR, the source tree,
    # the user's cache directory
    locators = tuple(_stamped(base) for base in bases)
    if not any(c.__name__ == locators[0].__name__ for c in classes):  # once, if reloaded
        classes[:0] = list(locators)
    # what numba's Cache builds a function's files with, when the function is decorated
    caching.IndexDataCacheFile = _files(_NUMBA_FILES)  # type: ignore[misc]
    return locators


LOCATORS = _register()
