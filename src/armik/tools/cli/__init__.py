"""The ``armik`` command line.

Exit codes: 0 success, 1 no solution found (unreachable, not converged, joint limits),
2 bad input (one line on stderr, no traceback), 130 Ctrl-C (one line; ``armik view``: 0).
"""

from armik.tools.cli.main import main

__all__ = ["main"]
