"""armik's numba caches are stamped by every source they depend on (``armik.compiled_cache``):
an edit to a callee or a constant in another module makes every cached caller stale; the
same sources elsewhere or with other modification times keep the cache; numba keys each
entry by the CPU it was compiled for."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from numba import njit
from numba.core import types
from numba.core.registry import cpu_target

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


def _edit(path: Path, text: str = "# edited\n") -> None:
    path.write_text(path.read_text() + text)


def test_the_stamp_follows_compiled_modules_and_what_they_import(tmp_path):
    root = _package(tmp_path)
    names = [str(p.relative_to(root)) for p in compiled_cache.depended_on(root)]
    assert names == ["consts.py", "helper.py", "kernel.py"]
    before = compiled_cache.stamp(root)
    _edit(root / "other.py")  # no compiled module reads it
    _edit(root / "sub" / "plain.py")
    _edit(root / "api.py")  # a class, which compiled code cannot read
    assert compiled_cache.stamp(root) == before
    for name in names:  # the compiled module, a module it reads a constant of, one it imports
        _edit(root / name)
        after = compiled_cache.stamp(root)
        assert after != before
        before = after
    (root / "consts.py").write_text("X = 2\n")  # the same size, another constant
    assert compiled_cache.stamp(root) != before


def test_the_stamp_is_the_sources_not_their_times_or_place(tmp_path):
    """A cache filled once holds wherever the same sources lie: a fresh clone, a copy,
    files touched; one byte of a depended-on source changed and it is refused."""
    root = _package(tmp_path / "a")
    before = compiled_cache.stamp(root)
    for path in compiled_cache.depended_on(root):
        _touch(path)
    assert compiled_cache.stamp(root) == before
    copy = tmp_path / "b" / "armik"
    shutil.copytree(root, copy)
    for path in compiled_cache.depended_on(copy):
        _touch(path)
    assert compiled_cache.stamp(copy) == before
    (copy / "kernel.py").write_text((copy / "kernel.py").read_text().replace("X", "X "))
    assert compiled_cache.stamp(copy) != before


def test_a_cache_entry_is_keyed_by_the_cpu_it_was_compiled_for():
    """What makes a cache filled on another machine safe: numba finds an entry under the
    CPU's name and features (``codegen.magic_tuple()``), so another CPU misses it and
    compiles; and under the bytecode of the function itself."""
    codegen = cpu_target.target_context.codegen()
    sig = forward.signatures[0] if forward.signatures else ()
    key = forward._cache._index_key(sig, codegen)
    assert key[1] == codegen.magic_tuple()
    cpu_name, features = key[1][1], key[1][2]
    assert cpu_name and isinstance(features, str)
    assert len(key[2]) == 2 and all(len(h) == 64 for h in key[2])


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


_FIRST_CALL = r"""
import sys
import numpy as np
from numba.core import event
compiled = []
class Count(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__module__)
    def on_end(self, ev):
        pass
event.register("numba:compile", Count())
import armik
from armik.kernel.se3 import rotation_angle
assert armik.__file__.startswith(sys.argv[1]), armik.__file__
assert rotation_angle(np.eye(3)) == 0.0
print(sum(m.startswith("armik") for m in compiled))
"""


def _armik_compiles(root: Path, **env: str) -> int:
    """How many armik functions a first call of a small compiled function compiles in a new
    process importing the package at ``root``, its cache in the tree (numba's in-tree
    locator)."""
    environment = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    environment |= {"PYTHONPATH": str(root.parent), "ARMIK_COMPILE_HELPER": "0", **env}
    done = subprocess.run(
        [sys.executable, "-c", _FIRST_CALL, str(root)],
        env=environment,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    return int(done.stdout.split()[-1])


def test_a_cache_filled_for_one_copy_of_the_sources_serves_another(tmp_path):
    """What an image or an install that ships a filled cache relies on: the same sources
    at another path with other times load it; an edited callee's source, or another CPU,
    compile again."""
    first = tmp_path / "a" / "armik"
    shutil.copytree(compiled_cache.PACKAGE, first, ignore=shutil.ignore_patterns("__pycache__"))
    assert _armik_compiles(first) > 0
    second = tmp_path / "b" / "armik"
    shutil.copytree(first, second, copy_function=shutil.copy)  # new times, the cache too
    for path in second.rglob("*.py"):
        _touch(path)
    assert _armik_compiles(second) == 0
    assert _armik_compiles(second, NUMBA_CPU_NAME="generic") > 0  # another CPU's key
    edited = tmp_path / "c" / "armik"
    shutil.copytree(first, edited)
    _edit(edited / "kernel" / "measure.py")  # any depended-on source: here not even a callee
    assert _armik_compiles(edited) > 0


def test_every_package_with_compiled_code_registers_the_rule_first():
    """``import armik`` imports no numba: each package holding a compiled module imports
    ``armik.kernel`` (which imports ``compiled_cache`` first) before its modules, so no
    armik function is decorated under numba's own stamp, whichever module is imported
    first."""
    first = ("import armik.kernel  #", "from armik import compiled_cache  #")
    packages = set()
    for path in compiled_cache.depended_on():
        if compiled_cache._COMPILED.search(path.read_text(encoding="utf-8")):
            packages.add(path.parent)
    assert compiled_cache.PACKAGE not in packages  # a compiled module at the top: no package
    for package in packages:
        text = (package / "__init__.py").read_text(encoding="utf-8")
        imports = [line for line in text.splitlines() if line.startswith(("import ", "from "))]
        assert imports and imports[0].startswith(first), package
    code = (
        "import sys\n"
        "from numba.core.registry import CPUDispatcher\n"
        "name = sys.argv[1]\n"
        "__import__(name)\n"
        "for f in vars(sys.modules[name]).values():\n"
        "    if isinstance(f, CPUDispatcher) and f.py_func.__module__ == name:\n"
        "        print(type(f._cache._impl.locator).__name__.startswith('Armik'))\n"
    )
    for name in ("armik.constraints.bounds", "armik.servo.tick", "armik.solvers.closed_form.roots"):
        out = subprocess.run(
            [sys.executable, "-c", code, name], capture_output=True, text=True, timeout=300
        )
        assert out.returncode == 0, out.stderr
        assert out.stdout and set(out.stdout.split()) == {"True"}, (name, out.stdout)


# The notices a first call gives while the cache lacks a part (``armik.kernel.notice``) and
# the command they name, which builds what that call needs (``armik.precompile``).


def test_a_first_numeric_solve_in_the_background_says_one_line_naming_the_command(
    monkeypatch, capsys, tmp_path
):
    from armik.kernel import notice

    monkeypatch.delenv(notice.ENVIRONMENT, raising=False)
    monkeypatch.setenv(notice.TIMES_ENVIRONMENT, str(tmp_path / "times.json"))
    monkeypatch.setattr(notice, "_BACKGROUND", set())
    # a first dls solve sends its entry, then the verdict's FK check, to the helper
    notice.in_background("armik.kernel.single", "solve_pose_dls")
    notice.in_background("armik.kernel.measure", "placement_check")
    err = capsys.readouterr().err
    assert err.count("armik: compiling") == 1, err
    assert "the numeric solvers" in err and "`armik compile dls qp batch tasks`" in err
    # the FK check alone (nothing said before it) is still said, with its command
    monkeypatch.setattr(notice, "_BACKGROUND", set())
    notice.in_background("armik.kernel.measure", "placement_check")
    err = capsys.readouterr().err
    assert err.count("armik: compiling the forward-kinematics check") == 1
    assert "`armik compile`" in err


def test_every_command_a_notice_names_is_parts_armik_compile_has():
    from armik.kernel import notice
    from armik.precompile import PARTS

    for _prefix, what, _seconds in notice.PARTS:
        words = notice.command(what).split()
        assert words[:2] == ["armik", "compile"], what
        assert all(part in PARTS for part in words[2:]), (what, words)


def test_the_tasks_part_builds_a_tip_only_task_list(after_parts):
    """After ``armik compile tasks`` alone, a task list on the tip alone (a position, with an
    axis: what the numeric solver's entry solves) needs no compiled function more."""
    uses = (
        "a = armik.load('kinova')\nT = a.fk(a.middle)\n"
        "a.solve([armik.Position(T.translation)])\n"
        "a.solve([armik.Position(T.translation), armik.Axis((0, 0, 1), T.rotation[:, 2], 0.05)])\n"
    )
    assert after_parts.new("tasks", uses) == []


def test_armik_compile_gives_no_notice_of_its_own_parts(monkeypatch):
    """``armik compile`` prints each part's time: a notice telling to run ``armik compile``
    would be what is running. Its parts run with the notice off, and it is on again after."""
    from armik import precompile
    from armik.kernel import notice

    monkeypatch.setenv(notice.ENVIRONMENT, "1")
    seen = []
    monkeypatch.setitem(
        precompile.PARTS, "probe", lambda: seen.append(os.environ.get(notice.ENVIRONMENT))
    )
    precompile.compile(["probe"], jobs=1, progress=False)
    assert seen == ["0"] and os.environ[notice.ENVIRONMENT] == "1"


def test_armik_compile_refuses_names_that_are_no_part_names_by_value():
    import pytest

    for names in (3, [["dls"]], b"dls", [None]):
        with pytest.raises(armik.OptionError, match=r"names must be a part's name.*got"):
            armik.compile(names)  # type: ignore[arg-type]


def test_two_processes_saving_one_function_at_once_keep_both_entries(tmp_path):
    """Two processes compiling one function for two signatures at once (``armik compile``'s
    two, a helper and the program it serves), forced here: the second saves its entry
    whole while the first is writing its own, at each write of the first's in turn. A
    later process loads each signature's own code."""
    cache = forward._cache
    codegen = cpu_target.target_context.codegen()
    keys = [cache._index_key((t,), codegen) for t in (types.float64, types.int64)]
    codes = [("code for", str(k[0])) for k in keys]
    files = type(cache._cache_file)
    stamp = cache._impl.locator.get_source_stamp()

    class Interrupted(files):  # type: ignore[misc, valid-type]
        def _open_for_write(self, path):
            if self.writes == self.interrupted_at:
                files(**where).save(keys[1], codes[1])  # the second process, all of it
            self.writes += 1
            return super()._open_for_write(path)

    for at in range(3):  # numba's save writes twice (its index, then the code)
        folder = tmp_path / str(at)
        folder.mkdir()
        where = {"cache_path": str(folder), "filename_base": "f-1.py311", "source_stamp": stamp}
        first = Interrupted(**where)
        first.writes, first.interrupted_at = 0, at
        first.save(keys[0], codes[0])
        if first.writes <= at:  # the second saves after the first
            files(**where).save(keys[1], codes[1])
        later = files(**where)
        assert [later.load(k) for k in keys] == codes, at


def test_an_entry_saved_from_other_sources_is_not_loaded(tmp_path):
    """An entry's file is named after its signature and CPU, not its sources: another
    version's save of the same entry replaces it, and is then compiled again here."""
    cache = forward._cache
    key = cache._index_key((types.float64,), cpu_target.target_context.codegen())
    files = type(cache._cache_file)
    where = {"cache_path": str(tmp_path), "filename_base": "f-1.py311"}
    files(**where, source_stamp="other sources").save(key, ("other code",))
    assert files(**where, source_stamp=cache._impl.locator.get_source_stamp()).load(key) is None


def test_armik_functions_alone_are_cached_a_file_per_entry():
    assert type(forward._cache._cache_file) is compiled_cache.Entries
    assert type(solve_into._cache._cache_file) is compiled_cache.Entries

    @njit(cache=True)
    def other(x):  # not armik's: cached as numba caches it
        return x

    assert type(other._cache._cache_file) is not compiled_cache.Entries


def test_flush_removes_the_functions_own_entries(tmp_path):
    """numba's flush empties its index, which armik's entries (a file each) do not read:
    every entry stayed and was loaded again after the flush."""
    cache = forward._cache
    codegen = cpu_target.target_context.codegen()
    keys = [cache._index_key((t,), codegen) for t in (types.float64, types.int64)]
    stamp = cache._impl.locator.get_source_stamp()
    files = type(cache._cache_file)
    flushed = files(str(tmp_path), "m.f-1.py311", stamp)
    other = files(str(tmp_path), "m.f-10.py311", stamp)  # another function, a longer name
    for k in keys:
        flushed.save(k, ("code", str(k[0])))
        other.save(k, ("other", str(k[0])))
    (tmp_path / "m.f-1.py311.1.nbc").write_bytes(b"numba's own")  # not an entry of armik's
    assert len(os.listdir(tmp_path)) == 5
    flushed.flush()
    assert [flushed.load(k) for k in keys] == [None, None]
    assert [other.load(k) for k in keys] == [("other", str(k[0])) for k in keys]
    assert sorted(os.listdir(tmp_path)) == sorted(
        ["m.f-1.py311.1.nbc", *(os.path.basename(other._entry_path(k)) for k in keys)]
    )
    assert not list(tmp_path.glob("*.nbi"))  # no index written either
    flushed.flush()  # nothing left: nothing to do
    files(str(tmp_path / "none"), "m.f-1.py311", stamp).flush()  # no folder: nothing to do
