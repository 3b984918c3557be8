"""Run example scripts one after another in this one interpreter, each as ``python SCRIPT
--out DIR`` would run it: ``__main__``, its own argv and globals, the examples folder first
on sys.path, its stdout and stderr (file descriptors 1 and 2) in files of its own.

    python tests/run_examples.py OUT SCRIPT...

For each script, OUT/NAME/ is its --out folder, OUT/NAME.stdout and OUT/NAME.stderr what it
printed, and OUT/NAME.code its exit code (0, or 1 after an exception, whose traceback ends
its stderr). The examples then share one start of Python, numpy, Pinocchio and the numba
kernels they load, instead of paying for it each.
"""

from __future__ import annotations

import os
import runpy
import sys
import traceback
from pathlib import Path


def run(script: Path, out: Path) -> int:
    """Run ``script`` as its own ``__main__``; its exit code."""
    (out / script.stem).mkdir(parents=True, exist_ok=True)
    saved_argv, saved_path = sys.argv, sys.path[:]
    sys.argv = [str(script), "--out", str(out / script.stem)]
    sys.path.insert(0, str(script.parent))
    saved_fds = {}
    code = 0
    with (
        open(out / f"{script.stem}.stdout", "wb") as stdout,
        open(out / f"{script.stem}.stderr", "wb") as stderr,
    ):
        for fd, file in ((1, stdout), (2, stderr)):
            saved_fds[fd] = os.dup(fd)
            os.dup2(file.fileno(), fd)
        try:
            runpy.run_path(str(script), run_name="__main__")
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
            if exc.code is not None and not isinstance(exc.code, int):
                print(exc.code, file=sys.stderr)
        except Exception:  # the script's exit code 1, as Python's own
            traceback.print_exc()
            code = 1
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            for fd, saved in saved_fds.items():
                os.dup2(saved, fd)
                os.close(saved)
            sys.argv, sys.path[:] = saved_argv, saved_path
            if "matplotlib.pyplot" in sys.modules:
                sys.modules["matplotlib.pyplot"].close("all")
    (out / f"{script.stem}.code").write_text(str(code), encoding="utf-8")
    return code


def main(argv: list[str]) -> int:
    out = Path(argv[0])
    for script in argv[1:]:
        run(Path(script), out)
    return 0


if __name__ == "__main__":
    del sys.path[0]  # this folder: each script gets its own first, as ``python SCRIPT``
    sys.exit(main(sys.argv[1:]))
