"""The tables of docs/file-formats.md, made from the key lists the loaders check.

``python -m rotor_host.file_formats`` prints every table under its heading; the reference
must contain each of them verbatim (tests/test_file_formats.py), so adding or changing a key
in code without the reference fails a test. The prose around the tables is written by hand.
"""

from __future__ import annotations

from bearing_fmu import internals as registry
from bearing_fmu.params import BEARING_KEYS
from bearing_fmu.schema import markdown_table, option_keys

from .rotor import BEARING_ENTRY_KEYS, DISK_KEYS, ELEMENT_KEYS, MATERIAL_KEYS, ROTOR_KEYS
from .scene import INITIAL_KEYS, RECORD_KEYS, SCENE_KEYS, STATIC_LOAD_KEYS, TIME_KEYS, UNBALANCE_KEYS


def reference_tables() -> dict[str, str]:
    """Heading -> markdown table, in the order of the reference."""
    tables = {
        "Bearing file: [bearing]": BEARING_KEYS,
        "Rotor file: top level": ROTOR_KEYS,
        "Rotor file: [material]": MATERIAL_KEYS,
        "Rotor file: [[elements]]": ELEMENT_KEYS,
        "Rotor file: [[disks]]": DISK_KEYS,
        "Rotor file: [[bearings]]": BEARING_ENTRY_KEYS,
        "Scene file: top level": SCENE_KEYS,
        "Scene file: [time]": TIME_KEYS,
        "Scene file: [[unbalance]]": UNBALANCE_KEYS,
        "Scene file: [[static_loads]]": STATIC_LOAD_KEYS,
        "Scene file: [initial]": INITIAL_KEYS,
        "Scene file: [record]": RECORD_KEYS,
    }
    out = {h: markdown_table(k) for h, k in tables.items()}
    for spec in registry.REGISTRY.values():
        out[f"Scene file: [{spec.name}]"] = markdown_table(option_keys(spec.options))
    return out


def main() -> None:
    for heading, table in reference_tables().items():
        print(f"### {heading}\n\n{table}\n")


if __name__ == "__main__":
    main()
