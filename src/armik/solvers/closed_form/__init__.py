"""The closed forms: Paden-Kahan subproblems, the shared 6R code, and one file per family
(each with its classifier beside its solver)."""

import armik.kernel  # noqa: F401  (first: numba's cache rule, the compile notice)
