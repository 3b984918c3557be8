"""A ``BatchResult`` as an ``.npz`` file (``armik.npz``: arrays and JSON metadata, no
pickles): ``save`` writes one, ``fields`` reads one back as the result's fields.

Fields added after the first files were written are read as absent from older files."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from armik import npz
from armik.status import Status

FORMAT = "armik.BatchResult/1"
_WORDS = [s.value for s in Status]


def save(result: Any, path: str | Path) -> Path:
    """Write ``result`` (a ``BatchResult``) to ``path``."""
    keys = np.array(sorted(result.reasons), dtype=np.int64)
    meta = {
        "format": FORMAT,
        "solver": result.solver,
        "time": result.time,
        "arm": result.arm,
        "joint_names": list(result.joint_names),
        "tol_position": result.tol_position,
        "tol_orientation": result.tol_orientation,
        "margin": result.margin,
        "region": result.region,
        "cone": result.cone,
        "claim": result.claim,
        "branch_names": list(result.branch_names),
        "statuses": _WORDS,
        "pair_names": [list(p) for p in result.pair_names],
    }
    arrays = dict(
        q=result.q,
        success=result.success,
        status_code=result.status_code,
        status=result.status,
        position_error=result.position_error,
        orientation_error=result.orientation_error,
        iterations=result.iterations,
        restarts=result.restarts,
        reason_index=keys,
        reason_text=np.array([result.reasons[int(k)] for k in keys], dtype=str),
        min_distance=result.min_distance,
        pair_index=result.pair_index,
        score=result.score,
        measured=result.measured,
        branch_code=result.branch_codes(),  # every row's, none left to read from its q
    )
    return npz.save(path, meta, arrays)


def fields(path: str | Path) -> dict[str, Any]:
    """The fields of the ``BatchResult`` written to ``path`` by ``save``; raises
    ``InputError`` if it is not one."""
    meta, arrays = npz.load(path, FORMAT, "a batch result written by BatchResult.save")
    codes = np.array([Status(w).code for w in meta["statuses"]], dtype=np.int8)
    return dict(
        q=arrays["q"],
        success=arrays["success"],
        status_code=codes[arrays["status_code"]],  # through the words: codes may move
        position_error=arrays["position_error"],
        orientation_error=arrays["orientation_error"],
        iterations=arrays["iterations"],
        restarts=arrays["restarts"],
        solver=meta["solver"],
        time=float(meta["time"]),
        joint_names=tuple(meta["joint_names"]),
        arm=meta["arm"],
        tol_position=float(meta["tol_position"]),
        tol_orientation=float(meta["tol_orientation"]),
        margin=float(meta.get("margin", 0.0)),
        reasons={
            int(k): str(t) for k, t in zip(arrays["reason_index"].tolist(), arrays["reason_text"])
        },
        min_distance=arrays.get("min_distance"),  # absent from files of armik <= 0.x
        pair_index=arrays.get("pair_index"),
        pair_names=[tuple(p) for p in meta.get("pair_names", [])],
        score=arrays.get("score"),  # absent from files written before preferences
        region=bool(meta.get("region", False)),  # absent from files before regions
        cone=_cone(meta.get("cone")),  # absent from files before it was kept
        measured=arrays.get("measured"),  # absent from files before it was kept
        claim=str(meta.get("claim", "")),  # absent from files before it was kept
        branch_code=arrays.get("branch_code"),  # absent from files before it was kept
        branch_names=[str(b) for b in meta.get("branch_names", [])],
    )


def _cone(saved: object) -> float | None:
    """A saved cone (rad), None where the file has none (written without an aim, or
    before the cone was kept: its successes' reasons then name no cone, as they did)."""
    return None if saved is None else float(saved)  # type: ignore[arg-type]
