"""The compiled numeric core: the descent of ``dls`` and ``qp`` and their restarts.

Small modules, one concept each. numba's on-disk cache is keyed by armik's every compiled
source together (``armik.compiled_cache``): editing one compiles the kernels again, so
that no cached caller keeps a callee's old code.

- ``chain``: the kernel's view of an arm, plain arrays read once from Pinocchio's model.
- ``se3``: log3, log6 and their Jacobians.
- ``fk``: forward kinematics and the tip Jacobian (LOCAL).
- ``linalg``: Cholesky solves for the small dense systems of a step.
- ``clock``: the CPU time of the calling thread (the budget threads cannot steal).
- ``step``: the damped least-squares step and the box-QP step (active set, QP fallback).
- ``descent``: the pose error, one attempt (``descend``), restarts.
- ``entry``: ``solve_targets``, a whole solve for N targets, GIL released.
- ``measure``: the verification errors from Pinocchio placements.
- ``box_qp``: the QP backend the qp step falls back to (object mode, qpsolvers).
- ``warmup``: a cold first solve compiled on two cores (the step in a helper process).
- ``notice``: the line on stderr while a first call compiles.
- ``loop_idiom``: LLVM's loop-idiom pass off while armik's code compiles (most of the
  compile time of the 6R closed forms).
- ``linked``: a function never called from Python optimised in its callers' modules only
  (LLVM's module passes once per entry, not once per compiled function above the code).

The solve (``descent.solve_one_dls``, ``solve_one_qp``) and the functions its loop calls are
compiled with ``_nrt=False``: without numba's reference counting, whose atomic increments
and decrements for every view of the workspace and every tuple passed on took half the time
of an iteration. Nothing compiled so allocates; the entries own the arrays. A function that
allocates and may be called from there says ``_nrt=True``: a function that does not set it
is compiled with its first caller's setting.
"""

# first: numba picks a compiled function's cache when it is decorated (the cache rule)
from armik import compiled_cache  # noqa: F401  # isort: skip
from armik.kernel import flag_values, tier  # isort: skip

import warnings  # noqa: E402

from numba.core.errors import NumbaWarning  # noqa: E402

tier.install()  # first calls run as Python while a helper compiles them
flag_values.install()  # numba's flags compared in one merge: the same, 8 % faster to compile

# The qp step's rare call to the QP backend runs in object mode (it takes the GIL back for
# that call only); numba warns about it at compile time.
warnings.filterwarnings(
    "ignore", message="Code running in object mode won't allow parallel", category=NumbaWarning
)

# the compile notice, LLVM's loop-idiom pass off while armik's code compiles, and a module
# of a function never called from Python optimised in its callers only
from armik.kernel import linked, loop_idiom, notice  # noqa: E402, F401

linked.install()
