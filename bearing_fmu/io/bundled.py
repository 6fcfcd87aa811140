"""Bundled model files by name, for both command lines (``bearing-fmu demo --bearing bearing_paper``,
``rotor-host run paper_22hz``).

The files are package data of ``rotor_host.bundled`` (its docstring lists them): bearings, maps and
surrogates beside the rotors and scenes that name them relatively, so the folder stays together.
The bearing side never imports the host (docs/architecture.md), so this module finds that folder
as files: ``importlib.util.find_spec`` of the top-level package ``rotor_host`` locates it without
running it. ``rotor_host.bundled`` calls the same functions with its own folder.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

# the kinds of bundled file a command takes by stem: where they are and how their names end
KINDS = {"scene": ("scenes", "*.toml"), "rotor": ("", "rotor_*.toml"), "bearing": ("", "bearing_*.toml"),
         "map": ("maps", "*.json"), "surrogate": ("surrogates", "*.json")}


def data_folder() -> Path | None:
    """The bundled folder of the installed ``rotor_host`` (not imported), or None without one."""
    spec = importlib.util.find_spec("rotor_host")
    for loc in (spec.submodule_search_locations or []) if spec is not None else []:
        if (Path(loc) / "bundled").is_dir():
            return Path(loc) / "bundled"
    return None


def names(kind: str, root: Path | None = None) -> list[str]:
    """The stems of the bundled files of one kind (``KINDS``) in ``root`` (default ``data_folder``), sorted."""
    root = root or data_folder()
    if root is None:
        return []
    sub, pattern = KINDS[kind]
    return sorted(p.name.removesuffix(pattern.rsplit("*", 1)[1]) for p in (root / sub).glob(pattern))


def find(name: str, kind: str | None = None, root: Path | None = None) -> Path | None:
    """The bundled file ``name`` names in ``root`` (default ``data_folder``), or None: a path within
    the folder (``scenes/paper_22hz.toml``, ``rotor_paper.toml``) or, with ``kind``, a stem of that
    kind (``paper_22hz``) with or without its suffix."""
    root = root or data_folder()
    rel = Path(name)
    if root is None or rel.is_absolute() or ".." in rel.parts or not rel.parts:
        return None
    if (root / rel).is_file():
        return root / rel
    if kind is not None and len(rel.parts) == 1:
        sub, pattern = KINDS[kind]
        suffix = pattern.rsplit("*", 1)[1]
        for candidate in (root / sub / name, root / sub / (name + suffix)):
            if candidate.is_file() and candidate.match(pattern):
                return candidate
    return None


def bundled_or_file(kind: str):
    """An argparse type: a file, or a bundled file of ``kind`` by its name."""
    from .cliargs import existing_file_or

    return existing_file_or(lambda text: find(text, kind), f"a bundled {kind} ({', '.join(names(kind))})")


__all__ = ["KINDS", "data_folder", "names", "find", "bundled_or_file"]
