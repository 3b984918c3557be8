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
        "looks_at": result.looks_at,
        "free": list(result.free),
        "aims": result.aims,
        "claim": result.claim,
        "branch_names": list(result.branch_names),
        "statuses": _WORDS,
        "pair_names": [list(p) for p in result.pair_names],
        "weighted": result.weighted,
        "error_tips": list(result.errors),  # several tips: each tip's errors, in order
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
        **_texts("said", result.said),  # a success's words (``reasons`` holds them too)
        **_texts("solver", result.solvers),
        **{f"errors_{k}": e for k, e in enumerate(result.errors.values())},
    )
    return npz.save(path, meta, arrays)


def _texts(name: str, texts: dict[int, str]) -> dict[str, np.ndarray]:
    """A row -> text field as two arrays, the rows and their texts."""
    keys = np.array(sorted(texts), dtype=np.int64)
    texts_of = np.array([texts[k] for k in keys.tolist()], dtype=str)
    return {f"{name}_index": keys, f"{name}_text": texts_of}


def _read(arrays: dict, name: str) -> dict[int, str]:
    """A row -> text field ``_texts`` wrote (empty from files written before it was kept)."""
    if f"{name}_index" not in arrays:
        return {}
    rows, texts = arrays[f"{name}_index"].tolist(), arrays[f"{name}_text"]
    return {int(k): str(t) for k, t in zip(rows, texts)}


def fields(path: str | Path) -> dict[str, Any]:
    """The fields of the ``BatchResult`` written to ``path`` by ``save``; raises
    ``InputError`` if it is not one."""
    meta, arrays = npz.load(path, FORMAT, "a batch result written by BatchResult.save")
    codes = np.array([Status(w).code for w in meta["statuses"]], dtype=np.int8)
    said = _read(arrays, "said")
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
        reasons={k: t for k, t in _read(arrays, "reason").items() if said.get(k) != t},
        said=said,  # saved in ``reasons`` too, for files read by armik before it was kept
        solvers=_read(arrays, "solver"),  # absent from files before it was kept
        weighted=bool(meta.get("weighted", False)),  # absent from files before it was kept
        errors={tip: arrays[f"errors_{k}"] for k, tip in enumerate(meta.get("error_tips", []))},
        min_distance=arrays.get("min_distance"),  # absent from files of armik <= 0.x
        pair_index=arrays.get("pair_index"),
        pair_names=[tuple(p) for p in meta.get("pair_names", [])],
        score=arrays.get("score"),  # absent from files written before preferences
        region=bool(meta.get("region", False)),  # absent from files before regions
        cone=_cone(meta.get("cone")),  # absent from files before it was kept
        looks_at=bool(meta.get("looks_at", False)),  # absent from files before it was kept
        free=tuple(bool(f) for f in meta.get("free", (False, False))),  # absent before too
        # absent from files before it was kept: an aim's distance was then its axis' angle
        aims=bool(meta.get("aims", meta.get("cone") is not None)),
        measured=arrays.get("measured"),  # absent from files before it was kept
        claim=str(meta.get("claim", "")),  # absent from files before it was kept
        branch_code=arrays.get("branch_code"),  # absent from files before it was kept
        branch_names=[str(b) for b in meta.get("branch_names", [])],
    )


def _cone(saved: object) -> float | None:
    """A saved cone (rad), None where the file has none (written without an aim, or
    before the cone was kept: its successes' reasons then name no cone, as they did)."""
    return None if saved is None else float(saved)  # type: ignore[arg-type]
