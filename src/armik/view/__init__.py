"""Seeing an arm: the browser viewer (viser), the arm's meshes or stick figure, and plots."""

from __future__ import annotations

import sys
import types


class _ViewPackage(types.ModuleType):
    # ``armik.view`` is both this package and the function that opens a viewer: importing a
    # submodule sets the package as ``armik``'s attribute ``view``, so the package itself
    # must be the callable.
    def __call__(self, arm, port: int = 8080, open_browser: bool = True, **kwargs):
        """Open a viewer of ``arm`` (an ``Arm``, or several tips of one robot: an ``Arms``)
        at http://127.0.0.1:``port`` (0: any free port) and, if ``open_browser``, show it
        in the browser. Keywords: ``host`` ("127.0.0.1"; "0.0.0.0"
        serves other machines too), ``solver`` ("auto"), ``q`` (the first configuration,
        default ``arm.middle``) and solve options (``timeout=...``, as for ``Arm.solve``).
        Returns an ``armik.Viewer``; raises ``ViewerError`` without viser or when the port
        is taken, ``SolverError``/``OptionError`` for a bad solver or option."""
        from armik.view.viewer import Viewer

        return Viewer(arm, port=port, open_browser=open_browser, **kwargs)


sys.modules[__name__].__class__ = _ViewPackage
