"""What an answer must satisfy besides the pose: obstacles (``shapes``) and collisions
(``collision``). Joint limits, the first constraint, live with the arm model and kernels."""

import armik.kernel  # noqa: F401  (first: numba's cache rule, the compile notice)
