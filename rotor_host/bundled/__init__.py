"""The machines installed with the package: the paper's and Friswell's rotors, bearings, scenes,
force maps and Taylor surrogates (package data, read with ``importlib.resources``).

=====================  ==========================================================
``rotor_*.toml``       rotor files; they name their bearing files relative to themselves
``bearing_*.toml``     bearing files (bore, clearance, oil)
``scenes/*.toml``      scene files; they name their rotor (``../rotor_paper.toml``) and
                       their maps and surrogates relative to themselves
``maps/*.json``        force maps (``bearing-fmu map``)
``surrogates/*.json``  Taylor surrogates (``bearing-fmu fit``, ``rotor-host fit``)
=====================  ==========================================================

The folder stays together, so the relative references hold wherever it is installed. A command
takes a file either as a path or, when no such file is there, by its bundled name: the name
within this folder (``scenes/paper_22hz.toml``) or, for one kind of file, its stem
(``rotor-host run paper_22hz``, ``rotor-host stability rotor_paper``, ``rotor-host stability --map paper_bearing``,
``bearing-fmu demo --bearing bearing_paper``). The lookup is ``bearing_fmu.io.bundled``'s, which both
command lines use: the bearing side never imports the host, so it finds this folder as files.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

from bearing_fmu.io import bundled as lookup
from bearing_fmu.io.bundled import KINDS


def folder() -> Path:
    """The bundled folder on disk (a package installed from a wheel or a checkout is a folder:
    the scene files' relative references need real paths)."""
    root = files(__name__)
    if not isinstance(root, Path):  # a zip import: the references between files cannot be followed
        raise OSError(f"the bundled models of {__name__} are not a folder on disk ({root}); install the package "
                      "unzipped (pip install)")
    return root


def names(kind: str) -> list[str]:
    """The stems of the bundled files of one kind (``KINDS``), sorted."""
    return lookup.names(kind, folder())


def find(name: str, kind: str | None = None) -> Path | None:
    """The bundled file ``name`` names, or None: a path within the bundled folder
    (``scenes/paper_22hz.toml``, ``rotor_paper.toml``) or, with ``kind``, a stem of that kind
    (``paper_22hz``) with or without its suffix."""
    return lookup.find(name, kind, folder())


def path(name: str, kind: str | None = None) -> Path:
    """``find``, or a FileNotFoundError that lists what is bundled."""
    found = find(name, kind)
    if found is None:
        shown = f" (bundled {kind}s: {', '.join(names(kind))})" if kind else ""
        raise FileNotFoundError(f"no bundled file {name!r}{shown}")
    return found


__all__ = ["KINDS", "folder", "names", "find", "path"]
