"""Every tolerance and bound shared across armik, in one place (SI units: m, rad).

Compiled kernels read these as constants when they are compiled: after changing one, clear
the numba cache (``CONTRIBUTING.md``).
"""

# Joint limits: a value this close outside a limit still counts as inside (rad or m).
LIMIT_TOL = 1e-12

# Sizes: origins, tool offsets and target positions beyond MAX_LENGTH are a mistake (their
# arithmetic overflows in the solvers' restarts); limits beyond MAX_LIMIT mean "free".
MAX_LENGTH = 1e6  # m
MAX_POSITION = MAX_LENGTH  # m: the farthest target position accepted
MAX_LIMIT = 1e6  # rad or m

# Options: a timeout beyond MAX_TIMEOUT would overflow the kernel's budget, counted in
# signed 64-bit nanoseconds (and is no budget at all); counts above MAX_COUNT would overflow
# its iteration and restart counters; MAX_SOLUTIONS rows are allocated for solve_all; weights
# further apart than MAX_WEIGHT overflow the squared error of far restart candidates.
MAX_TIMEOUT = 1e6  # s (11.6 days)
MAX_COUNT = 2**62
MAX_SOLUTIONS = 10_000
MAX_WEIGHT = 1e6

# Targets: how far from orthonormal a given rotation may be before it is refused, and how
# far each entry of a 4x4 target's last row from (0, 0, 0, 1) (the Python parsers, the
# compiled plain-pose check and an exported solver alike).
ROTATION_TOL = 1e-6
LAST_ROW_TOL = 1e-12

# Verification: a tolerance below MIN_TOLERANCE is below what double precision can check
# (the FK's own rounding reaches 1e-15 on a metre-long arm), so it is refused.
MIN_TOLERANCE = 1e-12  # m or rad

# Structure: two axes are parallel when the angle between them is below ANGLE_TOL; lines
# meet when they pass within DISTANCE_TOL of one point. A near miss is refused with the
# measured number, never given a closed form that is only approximately right.
ANGLE_TOL = 1e-9  # rad
DISTANCE_TOL = 1e-9  # m
PARALLEL_TOL = 1e-9  # the planar chains' axes (norm of the cross product of unit axes)

# Collisions: a link that never moves relative to the base may sink this far into an
# obstacle before the obstacle is refused (a base resting on its table: the UR5's base
# mesh reaches 3 mm below its own origin); such pairs are checked once, not per answer.
FIXED_OVERLAP_TOL = 0.01  # m

# m: a frame nearer its point than this has no line of sight to aim along (a move of a
# micrometre turns it any way): the verdict refuses it, the task and the compiled rows
# measure pi there, so that a seed there restarts rather than claims convergence
SIGHT = 1e-6
