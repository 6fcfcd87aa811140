"""Result files that cannot collide or vanish.

* ``ensure_writable(folder, option)``: the output folder exists (created) and accepts a file,
  checked before any work, with one line naming the option when it does not.
* ``write_text`` / ``write_json`` / ``savez``: written under a temporary name in the same
  folder and renamed into place (``os.replace`` is atomic on POSIX and Windows), so a reader
  -- or a second run writing the same name -- sees the old file or the new one, never half.
* ``claim(folder, stem)``: a result name no running process holds. A run holds its name
  through a ``<stem>.lock`` file with its process id; a second run started meanwhile gets
  ``<stem>-2`` (then ``-3``, ...), a run started after the first finished (or died: its pid is
  gone) takes the name over and overwrites its files.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path


def ensure_writable(folder, option: str = "--out") -> Path:
    """Create ``folder`` (with parents) and check a file can be written there."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"{option} {folder}: is a file, not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".write_probe_", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except (FileExistsError, NotADirectoryError):
        raise ValueError(f"{option} {folder}: a part of this path is a file, not a folder") from None
    except PermissionError:
        raise ValueError(f"{option} {folder}: not writable (permission denied); choose another folder") from None
    except OSError as exc:
        raise ValueError(f"{option} {folder}: cannot write there ({exc.strerror or exc})") from None
    return folder


def ensure_output_file(path, option: str = "-o") -> Path:
    """A file the command will write at the end: its folder exists and is writable, and the
    path is not a folder. Checked before any work."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{option} {path}: is a folder; give a file name")
    ensure_writable(path.parent if str(path.parent) else Path("."), option)
    return path


def _atomic(path, write) -> Path:
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return path


def write_text(path, text: str) -> Path:
    return _atomic(path, lambda f: f.write(text.encode("utf-8")))


def write_json(path, data, indent: int = 2) -> Path:
    return write_text(path, json.dumps(data, indent=indent) + "\n")


def write_bytes(path, data: bytes) -> Path:
    return _atomic(path, lambda f: f.write(data))


def savez(path, **arrays) -> Path:
    """numpy.savez, atomically (``path`` is used as given: name it ``*.npz``)."""
    import numpy as np

    return _atomic(path, lambda f: np.savez(f, **arrays))


def pid_alive(pid: int) -> bool:
    if pid <= 0:
        return False
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, someone else's
        return True
    return True


class Claim:
    """A result name held by this process (see the module docstring); ``release()`` frees it."""

    def __init__(self, folder: Path, stem: str, lock: Path | None):
        self.folder, self.stem, self._lock = folder, stem, lock

    def path(self, suffix: str) -> Path:
        return self.folder / f"{self.stem}{suffix}"

    def release(self) -> None:
        if self._lock is not None:
            try:
                self._lock.unlink()
            except OSError:
                pass
            self._lock = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.release()


def claim(folder, stem: str, limit: int = 1000) -> Claim:
    """Hold ``<folder>/<stem>`` (or the first free ``<stem>-N``) for this process."""
    folder = Path(folder)
    for n in range(1, limit + 1):
        name = stem if n == 1 else f"{stem}-{n}"
        lock = folder / f"{name}.lock"
        for _ in range(2):  # a stale lock is removed once, then the name is tried again
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                try:
                    pid = int(lock.read_text().strip())
                except (OSError, ValueError):  # being written this instant: held
                    break
                if pid_alive(pid):
                    break
                try:
                    lock.unlink()
                except FileNotFoundError:
                    pass
                continue
            with os.fdopen(fd, "w") as f:
                f.write(str(os.getpid()))
            return Claim(folder, name, lock)
    raise RuntimeError(f"{folder}: {limit} runs named {stem} are running at once")
