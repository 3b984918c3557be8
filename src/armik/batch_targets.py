"""Many targets at once: N poses (or N positions) as arrays, in the arm's base frame."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class TargetBatch:
    """N desired tip poses in the base frame (m). ``rotations`` is None for positions."""

    positions: np.ndarray  # (N, 3)
    rotations: np.ndarray | None = None  # (N, 3, 3)

    def __len__(self) -> int:
        return len(self.positions)

    @property
    def position_only(self) -> bool:
        return self.rotations is None

    def matrices(self) -> np.ndarray:
        """(N, 4, 4) homogeneous transforms ``T_base_target`` (identity rotation for
        position targets)."""
        n = len(self)
        T = np.zeros((n, 4, 4))
        T[:, :3, :3] = np.eye(3) if self.rotations is None else self.rotations
        T[:, :3, 3] = self.positions
        T[:, 3, 3] = 1.0
        return T
