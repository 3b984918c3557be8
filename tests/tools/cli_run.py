"""The command line run in-process for the tests: its exit code and what it printed."""

from __future__ import annotations

from armik.tools.cli import main


def run(capsys, *argv):
    """(exit code, stdout, stderr) of ``armik ARGV`` (argparse's own exits included)."""
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def words(values) -> list[str]:
    """Numbers as command-line words that read back to the same floats."""
    return [repr(float(v)) for v in values]
