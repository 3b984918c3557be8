"""Helpers shared by the examples: the --out folder for figures."""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path


def out_dir(description: str, figures: bool = True) -> Path | None:
    """Parse the command line; the folder for figures (None for an example without any)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--out", help="folder for figures (default: a temporary folder)")
    args = parser.parse_args()
    if not figures:
        return None
    path = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="armik-"))
    try:
        path.mkdir(parents=True, exist_ok=True)
        (path / ".armik-write-check").touch()
        (path / ".armik-write-check").unlink()
    except OSError as error:  # one line, as the command line says it, not a traceback
        parser.error(
            f"--out {args.out}: cannot write there ({error.strerror}): give a folder you can write"
        )
    return path


def pyplot():
    """matplotlib on the Agg backend: figures go to files, never to a window. None, said in
    one line, where it is not installed (the plot extra): the example runs without figures."""
    try:
        import matplotlib
    except ImportError:
        print('figures skipped: matplotlib is not installed: pip install "armik[plot]"')
        return None

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
