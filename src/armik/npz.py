"""Arrays and their JSON metadata in one ``.npz`` file (no pickles): what ``BatchResult`` and
``ReachMap`` save and load."""

from __future__ import annotations

import json
import os
import zipfile
from pathlib import Path

import numpy as np

from armik.errors import InputError


def save(path: str | Path, meta: dict, arrays: dict[str, np.ndarray]) -> Path:
    """Write ``arrays`` and ``meta`` (JSON, with its "format") to ``path``; ``InputError``
    naming the path when it cannot be written (a missing folder, a folder, no permission)."""
    path = Path(_path(path, "save to"))
    try:
        with open(path, "wb") as f:
            # arg-type: numpy's stubs let the ** fill savez's allow_pickle, a bool
            np.savez(f, **arrays, meta=np.array(json.dumps(meta)))  # type: ignore[arg-type]
    except OSError as exc:
        raise InputError(
            f"cannot write {str(path)!r} ({exc.strerror or exc}): give a path in an existing "
            "folder you can write to"
        ) from None
    return path


def load(
    path: str | Path, format: str, what: str, keys: tuple[str, ...] | None = None
) -> tuple[dict, dict[str, np.ndarray]]:
    """(meta without its "format", the arrays ``keys`` or all) of a file ``save`` wrote with
    this ``format``; ``InputError`` saying the file is not ``what`` otherwise."""
    if not hasattr(path, "read"):  # an open file numpy reads, else a path
        _path(path, "load from")
    try:
        kind = _kind(path)
        if kind:  # numpy would read it as a pickle, or as one array
            raise ValueError(f"{kind}, not an .npz archive")
        z = np.load(path, allow_pickle=False)
        with z:
            meta = json.loads(str(z["meta"]))
            if meta.get("format") != format:
                raise KeyError("format")
            arrays = {k: z[k] for k in (keys or z.files) if k != "meta"}
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:  # truncated: the last
        raise InputError(f"{str(path)!r} is not {what} ({exc})") from None
    meta.pop("format")
    return meta, arrays


def _path(path: object, verb: str):
    """``path`` where it is a file's path (a str, a ``pathlib.Path``), else ``InputError``."""
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"cannot {verb} {path!r}: give a file's path (a str or a pathlib.Path)")
    return path


_ZIP = b"PK\x03\x04"  # an .npz archive is a zip file: it begins with these bytes


def _kind(path: str | Path) -> str:
    """What the file at ``path`` is where it is no zip archive ("" where it is one, or
    ``path`` is an open file, which numpy reads)."""
    if not isinstance(path, (str, os.PathLike)):
        return ""
    with open(path, "rb") as f:
        head = f.read(512)
    if head.startswith(_ZIP):
        return ""
    if not head:
        return "an empty file"
    if head.startswith(b"\x93NUMPY"):
        return "one array (.npy)"
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as exc:
        if exc.start < len(head) - 4:  # not a character cut at the 512th byte
            return "a binary file of another format"
    return "a text file"
