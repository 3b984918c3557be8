"""Reachability maps: per voxel of the workspace, the fraction of tool orientations reached.

The workspace is a grid of cubic voxels (side ``resolution``, m) around the first joint,
over the ball of the arm's reach bound (``ArmModel.reach``). At every voxel centre the same
``orientations`` tool orientations (uniformly distributed rotations, seeded) are solved
with ``solve_batch``; a voxel's value is the fraction of them that were solved and
verified. This is the reachability part of a capability map (Zacharias et al., 2007):
1 where the arm reaches the point in every sampled orientation, 0 where it reaches it in
none. Voxels outside the reach bound are not sampled (NaN).

An arm of fewer than 6 joints (a planar arm, a SCARA) reaches no point in every
orientation, nor in almost any sampled one: its map is of positions, each voxel centre
solved once as a position target (1: reached, 0: not), ``orientations`` unused and
``ReachMap.position_only`` set; so is the map of any arm asked ``position_only=True``.

Most targets of such a map are unreachable, and an unreachable target costs the solver's
whole budget: the budget (``timeout``, default here 5 ms) sets the price of a map.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from armik import checked, npz
from armik.errors import InputError, OptionError
from armik.model.arm_model import ArmModel, model_of
from armik.solve.batch import solve_batch
from armik.solve.progress import ProgressArg
from armik.solve.read import read_batch
from armik.targets.batch import TargetBatch

FORMAT = "armik.ReachMap/1"
MAX_SOLVES = 50_000_000
DEFAULT_OPTIONS = {"timeout": 0.005, "tol_position": 1e-5, "tol_orientation": 1e-5}


@dataclass(frozen=True, eq=False)
class ReachMap:
    """``fraction[i, j, k]``: the share of orientations solved at (xs[i], ys[j], zs[k])
    (m, base frame); NaN outside the reach bound. ``position_only``: a map of positions
    (an arm of fewer than 6 joints): 1 where the point is reached, 0 where not."""

    arm: str
    xs: np.ndarray
    ys: np.ndarray
    zs: np.ndarray
    fraction: np.ndarray
    orientations: int
    resolution: float
    solver: str
    time: float
    solves: int
    position_only: bool = False

    def summary(self) -> str:
        sampled = np.isfinite(self.fraction)
        f = self.fraction[sampled]
        any_ = int((f > 0).sum())
        full = int((f == 1).sum())
        if self.position_only:
            return (
                f"{self.arm}: {sampled.sum()} voxels of {self.resolution:g} m, positions only "
                f"(an arm of fewer than 6 joints reaches no point in every orientation; "
                f"{self.solves} solves, {self.solver}) in {self.time:.3g} s; "
                f"position reached: {any_}"
            )
        return (
            f"{self.arm}: {sampled.sum()} voxels of {self.resolution:g} m x {self.orientations} "
            f"orientations ({self.solves} solves, {self.solver}) in {self.time:.3g} s; "
            f"reached in some orientation: {any_}, in every orientation: {full}; "
            f"mean fraction {f.mean() if f.size else 0.0:.3f}"
        )

    def save(self, path: str | Path) -> Path:
        meta = {
            "format": FORMAT,
            "arm": self.arm,
            "orientations": self.orientations,
            "resolution": self.resolution,
            "solver": self.solver,
            "time": self.time,
            "solves": self.solves,
            "position_only": self.position_only,
        }
        arrays = dict(xs=self.xs, ys=self.ys, zs=self.zs, fraction=self.fraction)
        return npz.save(path, meta, arrays)

    @classmethod
    def load(cls, path: str | Path) -> ReachMap:
        keys = ("xs", "ys", "zs", "fraction")
        meta, arrays = npz.load(path, FORMAT, "a reachability map", keys)
        xs, ys, zs, fraction = (arrays[k] for k in keys)
        return cls(xs=xs, ys=ys, zs=zs, fraction=fraction, **meta)

    def plot(self, path: str | Path, slices: int = 5) -> Path:
        """Write a PNG: a vertical slice (x, z) through the first joint and ``slices``
        horizontal slices (x, y) at evenly spaced heights. Needs matplotlib (``plot``
        extra)."""
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            from matplotlib.figure import Figure
        except ImportError:
            raise InputError('plotting needs matplotlib: pip install "armik[plot]"') from None
        path = Path(path)
        if not path.suffix:  # matplotlib writes "name.png": the path returned is the file written
            path = path.with_suffix(".png")
        kinds = Figure().canvas.get_supported_filetypes()  # no pyplot figure: the user's stay
        if path.suffix[1:].lower() not in kinds:
            raise InputError(
                f"ReachMap.plot: matplotlib writes no {path.suffix} file ({str(path)!r}): name "
                f"it .png, or one of {', '.join('.' + k for k in sorted(kinds))}"
            )
        cols = 3
        rows = math.ceil((slices + 1) / cols)
        fig, axes = plt.subplots(
            rows, cols, figsize=(4.2 * cols, 3.8 * rows), squeeze=False, layout="constrained"
        )
        extent_xz = _extent(self.xs, self.zs)
        j0 = len(self.ys) // 2
        panels = [("x (m)", "z (m)", self.fraction[:, j0, :].T, extent_xz,
                   f"vertical slice y = {self.ys[j0]:.2f} m")]  # fmt: skip
        filled = np.flatnonzero(np.isfinite(self.fraction).any(axis=(0, 1)))
        if filled.size:
            for k in np.linspace(filled[0], filled[-1], slices).round().astype(int):
                panels.append(("x (m)", "y (m)", self.fraction[:, :, k].T,
                               _extent(self.xs, self.ys), f"z = {self.zs[k]:.2f} m"))  # fmt: skip
        image = None
        for ax, (xl, yl, data, extent, title) in zip(axes.flat, panels):
            image = ax.imshow(
                np.ma.masked_invalid(data), origin="lower", extent=extent, vmin=0, vmax=1,
                cmap="viridis", interpolation="nearest",
            )  # fmt: skip
            ax.set_xlabel(xl)
            ax.set_ylabel(yl)
            ax.set_title(title, fontsize=9)
        for ax in list(axes.flat)[len(panels) :]:
            ax.axis("off")
        what = (
            "positions reached"
            if self.position_only
            else f"fraction of {self.orientations} tool orientations reached"
        )
        fig.suptitle(f"{self.arm}: {what} ({self.resolution:g} m voxels)")
        if image is not None:
            label = "position reached" if self.position_only else "fraction reached"
            fig.colorbar(image, ax=axes.ravel().tolist(), shrink=0.8, label=label)
        fig.savefig(path, dpi=100)
        plt.close(fig)
        return path


def _extent(a: np.ndarray, b: np.ndarray) -> tuple[float, float, float, float]:
    ha = (a[1] - a[0]) / 2 if len(a) > 1 else 0.5
    hb = (b[1] - b[0]) / 2 if len(b) > 1 else 0.5
    return (a[0] - ha, a[-1] + ha, b[0] - hb, b[-1] + hb)


def grid(arm: ArmModel, resolution: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Voxel centres around the first joint (xs, ys, zs) and the mask of those within the
    reach bound (plus half a voxel diagonal)."""
    reach = arm.reach
    if not math.isfinite(reach):
        raise InputError(
            f"arm {arm.name!r} has an unlimited prismatic joint, so its workspace has no "
            "bound to grid: set its limits with Arm.with_limits"
        )
    half = math.ceil(reach / resolution)
    offsets = np.arange(-half, half + 1) * resolution
    o = arm.first_joint_origin
    xs, ys, zs = o[0] + offsets, o[1] + offsets, o[2] + offsets
    X, Y, Z = np.meshgrid(offsets, offsets, offsets, indexing="ij")
    inside = np.sqrt(X**2 + Y**2 + Z**2) <= reach + resolution * math.sqrt(3) / 2
    return xs, ys, zs, inside


def reachability(
    arm: object,
    resolution: float = 0.1,
    orientations: int = 16,
    *,
    solver: str = "auto",
    workers: int | None = None,
    seed: int = 0,
    progress: ProgressArg = None,
    client=None,
    **options: object,
) -> ReachMap:
    """Compute a reachability map (see the module docstring).

    ``resolution``: voxel side (m). ``orientations``: tool orientations per voxel (an arm
    of fewer than 6 joints: unused, its map is of positions, one solve a voxel).
    ``seed``: the orientation sample. ``workers`` / ``progress``: as for ``solve_batch``;
    ``client``: a Dask client to run on a cluster instead (``armik.solve.distributed``).
    ``options``: solver options (default ``timeout=0.005``, tolerances 1e-5 m / rad).
    """
    if hasattr(arm, "tips") and hasattr(arm, "chain"):  # an armik.Arms: a map per tip
        raise InputError(
            f"a reachability map is of one arm's tip, got {arm!r}: map each chain, "
            "reachability(robot.chain(tip), ...)"
        )
    arm = model_of(arm)
    given = resolution
    try:
        resolution = float(resolution)
    except (TypeError, ValueError):
        resolution = math.nan
    if not (math.isfinite(resolution) and resolution > 0):
        raise OptionError(  # the value as given: a word read as NaN is no NaN of the user's
            f"resolution must be a voxel side > 0 (m), got {given!r}",
            option="resolution",
            value=given,
        )
    if isinstance(orientations, bool) or not isinstance(orientations, int) or orientations < 1:
        raise OptionError(
            f"orientations must be a whole number >= 1, got {orientations!r}",
            option="orientations",
            value=orientations,
        )
    sample = checked.sampling_seed("seed", seed)  # numpy's own ValueError otherwise
    # no orientation sample for fewer than 6 joints: it would reach none (module)
    position_only = arm.dof < 6 or options.get("position_only") is True
    per_voxel = 1 if position_only else orientations
    ratio = arm.reach / resolution  # a tiny resolution: its cube would overflow a float
    voxels = 4.0 / 3.0 * math.pi * ratio**3 if ratio < 1e100 else math.inf  # about
    if voxels * per_voxel > MAX_SOLVES:
        raise OptionError(
            f"about {voxels:.3g} voxels x {per_voxel} orientations is too many solves "
            f"(more than {MAX_SOLVES:.0e}): raise resolution or lower orientations",
            option="resolution",
            value=resolution,
        )
    xs, ys, zs, inside = grid(arm, resolution)
    centres = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), axis=-1)[inside]  # (V, 3)
    # scipy.spatial at the first map, not with the CLI (0.3 s of every armik command)
    from scipy.spatial.transform import Rotation

    v, k = len(centres), per_voxel
    targets: TargetBatch | np.ndarray = centres  # positions: one a voxel
    if not position_only:
        rotations = Rotation.random(orientations, random_state=sample).as_matrix()  # (K, 3, 3)
        targets = TargetBatch(
            np.repeat(centres, k, axis=0), np.tile(rotations, (v, 1, 1))
        )  # voxel-major: rows v k .. v k + k - 1 are voxel v
    opts: dict[str, Any] = {**DEFAULT_OPTIONS, **options}
    if client is not None:
        # Dask is imported only when a cluster is used: it takes a second to import
        from armik.solve.distributed import solve_batch as cluster_solve

        result = cluster_solve(
            arm, targets, solver=solver, client=client, progress=progress, **opts
        )
    else:
        request = read_batch(arm, targets, None, solver, opts)
        result = solve_batch(arm, request, workers, progress=progress)
    fraction = np.full(inside.shape, np.nan)
    fraction[inside] = result.success.reshape(v, k).mean(axis=1)
    return ReachMap(
        arm=arm.name,
        xs=xs,
        ys=ys,
        zs=zs,
        fraction=fraction,
        orientations=k,
        resolution=resolution,
        solver=result.solver,
        time=result.time,
        solves=len(result),
        position_only=position_only,
    )
