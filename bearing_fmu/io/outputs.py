"""Result files that cannot collide or vanish.

* ``ensure_writable(folder, option)``: the output folder exists (created) and accepts a file
  (a byte: a full disk still takes empty files), checked once per command before any work,
  with one line naming the option when it does not.
* ``write_text`` / ``write_json`` / ``savez``: written under a temporary name in the same
  folder and renamed into place (``os.replace`` is atomic on POSIX and Windows), so a reader
  -- or a second run writing the same name -- sees the old file or the new one, never half.
* ``claim(folder, stem)``: a result name no running process holds. A run holds its name
  through a ``<stem>.lock`` file with its process id; a second run started meanwhile gets
  ``<stem>-2`` (then ``-3``, ...), a run started after the first finished (or died: its pid is
  gone) takes the name over and overwrites its files. ``release_held()`` frees every name this
  process still holds: the command's end (``exits.run_command``) calls it, so a signal landing
  between a run's last write and its own release leaves no lock behind.
* Rescue: a result that cannot be written where asked (a full disk, a folder made read-only
  during the run, its name taken by a folder) is written to ``<folder>.rescued/`` beside its
  folder, else to ``<system temp>/<folder>.rescued/``, with one line on stderr naming the path,
  why, and where it went; the writer returns where the file is. ``take_rescued()`` hands the
  list to the command's end (``exits.run_command``: exit code 1). Once a folder refused a
  write, this process's later results for it go to the rescue at once, so the files of one
  result stay together. When even the rescue fails: :class:`ResultNotWritten` (exit code 1).
  ``rescue=False`` (a checkpoint) raises the OSError instead, naming the path.
  ``take_written()``: what the command wrote, for an interrupt's last line.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .interrupts import deferred


def ensure_writable(folder, option: str = "--out", probe: bool = True) -> Path:
    """Create ``folder`` (with parents) and (``probe``) check a file can be written there. A
    folder this command checked already is not probed again: once the work started, a folder
    that refuses a write has its results rescued, not the command refused."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"{option} {folder}: is a file, not a folder")
    probe = probe and folder.resolve() not in _checked
    try:
        folder.mkdir(parents=True, exist_ok=True)
        if not probe:
            return folder
        fd, probe = tempfile.mkstemp(prefix=".write_probe_", dir=folder)
        try:  # one byte, not an empty file: a full disk still creates those
            os.write(fd, b"\0")
        finally:
            os.close(fd)
            os.unlink(probe)
    except (FileExistsError, NotADirectoryError):
        raise ValueError(f"{option} {folder}: a part of this path is a file, not a folder") from None
    except PermissionError:
        raise ValueError(f"{option} {folder}: not writable (permission denied); choose another folder") from None
    except OSError as exc:
        raise ValueError(f"{option} {folder}: cannot write there ({exc.strerror or exc})") from None
    _checked.add(folder.resolve())
    return folder


def ensure_output_file(path, option: str = "-o") -> Path:
    """A file the command will write at the end: its folder exists and is writable, and the
    path is not a folder. Checked before any work."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{option} {path}: is a folder; give a file name")
    ensure_writable(path.parent if str(path.parent) else Path("."), option)
    return path


class ResultNotWritten(RuntimeError):
    """A result could be written neither where asked nor in a rescue folder (the run failed)."""


@dataclass(frozen=True)
class Rescue:
    """A result written elsewhere: where it was meant to go, why not, where it is."""

    path: str
    reason: str
    to: str


_rescued: list[Rescue] = []
_refused: dict[Path, str] = {}  # folder -> why it refused a write (this command)
_written: list[Path] = []  # what this command wrote, where it is: an interrupt's last line names it
_checked: set[Path] = set()  # output folders this command probed before its work


def take_written() -> list[Path]:
    """The files written since the last call, each once, in order (rescued ones where they are)."""
    out = list(dict.fromkeys(_written))
    _written.clear()
    return out


def take_rescued() -> list[Rescue]:
    """The results rescued since the last call; forget which folders refused or were checked
    (called at a command's start and end, and by a sweep's worker after each run)."""
    out = list(_rescued)
    _rescued.clear()
    _refused.clear()
    _checked.clear()
    return out


def note_rescued(path: str, reason: str, to: str) -> None:
    """Count a rescue made in another process (a sweep's worker) as this command's."""
    _rescued.append(Rescue(str(path), str(reason), str(to)))


def rescue_folders(folder) -> list[Path]:
    """Where results meant for ``folder`` go when it refuses them, in the order tried."""
    folder = Path(folder).resolve()
    name = folder.name or "root"
    places = [folder.parent / f"{name}.rescued"] if folder.name else []
    temp = Path(tempfile.gettempdir()).resolve() / f"{name}.rescued"
    return places + [temp] if temp not in places else places


def _write_at(path: Path, write) -> Path:
    fd = tmp = None
    try:
        with deferred():  # a signal inside mkstemp would leave a temporary no one knows the name of
            fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            fd = None  # the file object closes it
            write(f)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            if fd is not None:
                os.close(fd)
        with contextlib.suppress(OSError):
            if tmp is not None:
                os.unlink(tmp)
        raise
    return path


def _atomic(path, write, rescue: bool = True) -> Path:
    path = Path(path)
    folder = path.parent.resolve()
    if rescue and folder in _refused:
        where = _rescue(path, write, _refused[folder])
    else:
        try:
            where = _write_at(path, write)
        except OSError as exc:
            reason = exc.strerror or str(exc)
            if not rescue:
                raise OSError(exc.errno, reason, str(path)) from None
            if exc.errno != errno.EISDIR:  # the folder refused, not just this name
                _refused[folder] = reason
            where = _rescue(path, write, reason)
    _written.append(where)
    return where


def _rescue(path: Path, write, reason: str) -> Path:
    failed = []
    for place in rescue_folders(path.parent):
        try:
            place.mkdir(parents=True, exist_ok=True)
            to = _write_at(place / path.name, write)
        except OSError as exc:
            failed.append(f"{place}: {exc.strerror or exc}")
            continue
        try:  # an older file at the asked name (a checkpoint saying running) must not pass for this result
            if path.is_file() and not path.is_symlink():
                path.unlink()
        except OSError:
            pass
        _rescued.append(Rescue(str(path), reason, str(to)))
        print(f"warning: cannot write {path} ({reason}); written to {to} instead", file=sys.stderr, flush=True)
        return to
    raise ResultNotWritten(f"cannot write {path} ({reason}), nor in a rescue folder ({'; '.join(failed)})")


def write_text(path, text: str, rescue: bool = True) -> Path:
    return _atomic(path, lambda f: f.write(text.encode("utf-8")), rescue)


def write_json(path, data, indent: int = 2, rescue: bool = True) -> Path:
    return write_text(path, json.dumps(data, indent=indent) + "\n", rescue)


def write_bytes(path, data: bytes, rescue: bool = True) -> Path:
    return _atomic(path, lambda f: f.write(data), rescue)


def write_with(path, write, rescue: bool = True) -> Path:
    """``write(file object)`` into ``path``, atomically and with the rescue (a figure's savefig)."""
    return _atomic(path, write, rescue)


def savez(path, rescue: bool = True, **arrays) -> Path:
    """numpy.savez, atomically (``path`` is used as given: name it ``*.npz``)."""
    import numpy as np

    return _atomic(path, lambda f: np.savez(f, **arrays), rescue)


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
        if lock is not None:
            _HELD.add(self)

    def path(self, suffix: str) -> Path:
        return self.folder / f"{self.stem}{suffix}"

    def release(self) -> None:
        if self._lock is not None:
            try:
                self._lock.unlink()
            except OSError:
                pass
            self._lock = None
        _HELD.discard(self)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.release()


_HELD: set[Claim] = set()  # the names this process holds now


def release_held() -> None:
    """Free every name this process still holds (a command's end: nothing of it runs any more)."""
    for held in list(_HELD):
        held.release()


def _take(folder: Path, name: str, lock: Path) -> Claim | None:
    """``name`` held through a new ``lock`` (None: a lock is there already). A signal between the
    lock's creation and its registration in ``_HELD`` would leave it behind (a fresh-clone CI hit
    this window), so it is held until the Claim exists; raised then, the name is freed first."""
    held = None
    try:
        with deferred():
            held = _new_lock(folder, name, lock)
    except BaseException:  # the interrupt held meanwhile: nothing of this run started
        if held is not None:
            held.release()
        raise
    return held


def _new_lock(folder: Path, name: str, lock: Path) -> Claim | None:
    try:
        fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
    except FileExistsError:
        return None
    except OSError:  # the folder refuses files now: its results go to the rescue, under this name
        return Claim(folder, name, None)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(str(os.getpid()))
    except OSError:  # a full disk: an empty lock would look held forever
        lock.unlink(missing_ok=True)
        return Claim(folder, name, None)
    return Claim(folder, name, lock)


def claim(folder, stem: str, limit: int = 1000) -> Claim:
    """Hold ``<folder>/<stem>`` (or the first free ``<stem>-N``) for this process."""
    folder = Path(folder)
    for n in range(1, limit + 1):
        name = stem if n == 1 else f"{stem}-{n}"
        lock = folder / f"{name}.lock"
        for _ in range(2):  # a stale lock is removed once, then the name is tried again
            held = _take(folder, name, lock)
            if held is not None:
                return held
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
    raise RuntimeError(f"{folder}: {limit} runs named {stem} are running at once")
