"""The arm model: URDF reading and checks, the catalogue of bundled arms, building the
reduced chain and its default tip, and the model itself (per-thread Pinocchio Data, FK,
Jacobian, limits, coordinates, seeds, axis geometry). It knows no solver."""
