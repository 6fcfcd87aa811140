"""Reading an .npz archive that a user names: every way it can fail is one ValueError naming the
file and what it was expected to be (numpy's own messages speak of pickles, zip members and
headers: a text file given by mistake reads as "pickled data", a truncated one as BadZipFile)."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

__all__ = ["read_npz"]


def read_npz(path, what: str) -> dict[str, np.ndarray]:
    """Every array of the .npz at ``path``, read in full (no pickles), or FileNotFoundError /
    ValueError naming the file and ``what`` it should be (e.g. "a saved run (.npz of rotor-host run)")."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file ({what})")
    with open(path, "rb") as f:
        head = f.read(4)
    if head[:2] != b"PK":
        kind = "empty" if not head else "text" if head.isascii() and head.decode("ascii").isprintable() else "binary"
        raise ValueError(f"{path}: not {what}: an .npz is a zip archive of numpy arrays, this file is {kind}")
    try:
        with np.load(path, allow_pickle=False) as data:
            return {k: np.asarray(data[k]) for k in data.files}
    except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError) as exc:
        raise ValueError(f"{path}: not {what}: a damaged or truncated .npz ({type(exc).__name__}: {exc})") from None
