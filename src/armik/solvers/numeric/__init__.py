"""The numeric solvers (dls, qp, clik) and their shared driver around the compiled core."""
