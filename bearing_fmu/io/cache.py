"""Where built artefacts live between commands: one cache per user, keyed by content.

A bearing FMU that a scene needs (the Python FMU with its bundled files, a native FMU for one
bearing and speed) is built once and found again by every later command and output folder: its
file name hashes everything that determines it (``source_digest`` and the data it holds), so a
changed source or file gives a new name and an old build is never reused wrongly. Writers build
under a temporary name and rename, so parallel commands can share the folder.

The folder: ``$BEARING_FMU_BUILD_CACHE`` when set, else ``fmus`` in the platform's user cache
under ``bearing_fmu`` (``$XDG_CACHE_HOME`` or ``~/.cache`` on Linux, ``~/Library/Caches`` on
macOS, ``%LOCALAPPDATA%`` on Windows), beside the Python FMU's code cache (``fmu-code``, the same
rule: bearing_fmu/fmu/build.py). Deleting it is always safe.

The map store (``map_store``, bearing_fmu/internals/map/store.py) follows the same rule:
``$BEARING_FMU_MAP_STORE``, else ``maps`` beside ``fmus``; its maps are keyed by content too.
"""

from __future__ import annotations

import functools
import hashlib
import os
import sys
from pathlib import Path

ENV = "BEARING_FMU_BUILD_CACHE"
MAP_ENV = "BEARING_FMU_MAP_STORE"
PACKAGE = Path(__file__).resolve().parents[1]  # bearing_fmu/


def build_cache() -> Path:
    """The folder of built FMUs (not created)."""
    return _user_folder(ENV, "fmus")


def fmu_code_cache() -> Path:
    """The Python FMU's code cache (not created; ``$BEARING_FMU_CACHE_DIR`` when set: the rule of
    the FMU's own bootstrap in bearing_fmu/fmu/build.py, where "off" disables it)."""
    return _user_folder("BEARING_FMU_CACHE_DIR", "fmu-code")


def map_store() -> Path:
    """The folder of the map store (not created)."""
    return _user_folder(MAP_ENV, "maps")


def _user_folder(env: str, name: str) -> Path:
    """``$env`` when set, else ``name`` under the user cache's ``bearing_fmu``."""
    if os.environ.get(env):
        return Path(os.environ[env]).expanduser()
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Caches"
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base.expanduser() / "bearing_fmu" / name


def cache_dir(store: bool = False) -> Path:
    """``build_cache()`` (``store``: ``map_store()``), created; an OSError says which folder and how
    to choose another."""
    folder, env = (map_store(), MAP_ENV) if store else (build_cache(), ENV)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OSError(f"cannot create the cache folder {folder} ({exc.strerror or exc}); set {env} to a "
                      "writable folder") from exc
    return folder


@functools.lru_cache(maxsize=None)
def source_digest(*parts: str) -> str:
    """A hash of every source file of bearing_fmu (Python and C): what any FMU build may read;
    ``parts`` (folders or files relative to bearing_fmu/, e.g. "physics"): of those alone (a map's
    solver). Computed once per process (the sources do not change under a running command)."""
    h = hashlib.sha256()
    roots = [PACKAGE / p for p in parts] or [PACKAGE]
    files = {p for r in roots for p in ([r] if r.is_file() else r.rglob("*"))}
    for f in sorted(p for p in files if p.suffix in (".py", ".c", ".h") and "__pycache__" not in p.parts):
        h.update(f.relative_to(PACKAGE).as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()
