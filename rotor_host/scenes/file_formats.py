"""The tables of docs/file-formats.md, made from the key lists the loaders check.

``python -m rotor_host.scenes.file_formats`` prints every table under its heading; with ``--write``
it puts them into docs/file-formats.md in place (each table under its existing heading). The
reference must contain each of them verbatim (tests/test_file_formats.py), so adding or
changing a key in code without the reference fails a test. The prose around the tables is
written by hand.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from bearing_fmu.internals import registry
from bearing_fmu.io.schema import markdown_table, option_keys
from bearing_fmu.physics.geometry import GEOMETRY_KEYS
from bearing_fmu.physics.oil import OIL_KEYS
from bearing_fmu.physics.params import BEARING_KEYS

from ..model.rotor import BEARING_ENTRY_KEYS, DISK_KEYS, ELEMENT_KEYS, MATERIAL_KEYS, ROTOR_KEYS, STAGE_KEYS
from .scene import (INITIAL_KEYS, RECORD_KEYS, SCENE_KEYS, SPEED_PROFILE_KEYS, STATIC_LOAD_KEYS, TIME_KEYS,
                    UNBALANCE_KEYS)
from .thermal import thermal_arrays_table


def reference_tables() -> dict[str, str]:
    """Heading -> markdown table, in the order of the reference."""
    tables = {
        "Bearing file: [bearing]": BEARING_KEYS,
        "Bearing file: [geometry]": GEOMETRY_KEYS,
        "Bearing file: [oil]": OIL_KEYS,
        "Rotor file: top level": ROTOR_KEYS,
        "Rotor file: [material]": MATERIAL_KEYS,
        "Rotor file: [[elements]]": ELEMENT_KEYS,
        "Rotor file: [[disks]]": DISK_KEYS,
        "Rotor file: [[bearings]]": BEARING_ENTRY_KEYS,
        "Rotor file: [[stages]]": STAGE_KEYS,
        "Scene file: top level": SCENE_KEYS,
        "Scene file: [speed_profile]": SPEED_PROFILE_KEYS,
        "Scene file: [time]": TIME_KEYS,
        "Scene file: [[unbalance]]": UNBALANCE_KEYS,
        "Scene file: [[static_loads]]": STATIC_LOAD_KEYS,
        "Scene file: [initial]": INITIAL_KEYS,
        "Scene file: [record]": RECORD_KEYS,
    }
    out = {h: markdown_table(k) for h, k in tables.items()}
    for spec in registry.REGISTRY.values():
        out[f"Scene file: [{spec.name}]"] = markdown_table(option_keys(spec.options))
    out["Run result: the thermal arrays"] = thermal_arrays_table()
    return out


DOC = Path(__file__).resolve().parents[2] / "docs" / "file-formats.md"


def write_reference(path: Path = DOC) -> list[str]:
    """Replace the table under each heading of the reference with the code's; return the
    headings that are missing from it (to be added by hand, with their prose)."""
    text = path.read_text()
    missing = []
    for heading, table in reference_tables().items():
        pattern = re.compile(rf"(^### {re.escape(heading)}\n\n)(?:\|.*\n)+", re.M)
        text, n = pattern.subn(lambda m: m.group(1) + table + "\n", text)
        if not n:
            missing.append(heading)
    path.write_text(text)
    return missing


def main(argv: list[str] | None = None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    if argv == ["--write"]:
        missing = write_reference()
        print(f"wrote the tables into {DOC}" + (f"; add these headings by hand: {', '.join(missing)}" if missing
                                               else ""))
        return
    for heading, table in reference_tables().items():
        print(f"### {heading}\n\n{table}\n")


if __name__ == "__main__":
    main()
