"""The generated parts of the documentation: the tables of docs/file-formats.md, made from the key
lists the loaders check, and the lists of the README and the docs made from the registry of
internals and the oil presets.

``python -m rotor_host.scenes.file_formats`` prints every table under its heading and every list
under its name; with ``--write`` it writes them in place: each table as its whole section of
docs/file-formats.md (``### heading``, the table; a section the code no longer makes is removed, a
new one is put after the section before it, prose under a heading is kept), and each list between
its markers in README.md and docs/*.md::

    <!-- generated: NAME -->...<!-- end -->

The reference must contain each table verbatim, and every marked list must equal its generator's
text (tests/test_file_formats.py), so a key, an internal or a preset added in code without the
documentation fails a test. The prose around them is written by hand.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path
from typing import Callable

from bearing_fmu.internals import registry
from bearing_fmu.io.schema import markdown_table, option_keys
from bearing_fmu.physics.bore.geometry import GEOMETRY_KEYS
from bearing_fmu.physics.oil import KELVIN, OIL_KEYS, PRESETS, Oil
from bearing_fmu.physics.params import BEARING_KEYS

from ..model.parts import BEARING_ENTRY_KEYS, DISK_KEYS, ELEMENT_KEYS, MATERIAL_KEYS, ROTOR_KEYS, STAGE_KEYS
from .scene import (INITIAL_KEYS, RECORD_KEYS, SCENE_KEYS, SPEED_PROFILE_KEYS, STATIC_LOAD_KEYS, TIME_KEYS,
                    UNBALANCE_KEYS)
from .thermal import thermal_arrays_table

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "file-formats.md"
# the headings of the generated sections all start so (a section under another heading is prose)
GENERATED_HEADINGS = ("Bearing file: ", "Rotor file: ", "Scene file: ", "Run result: ")
MARKED = re.compile(r"<!-- generated: ([\w-]+) -->(.*?)<!-- end -->", re.S)


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


# ----------------------------------------------------------------------------- the marked lists

def oil_presets_table() -> str:
    """The ``grade`` presets (physics.oil.PRESETS): the law's data under the [oil] table's keys, the
    viscosity they give at 40 and 100 C, and their sources."""
    rows = ["| grade | law | data | mu at 40 C, 100 C [mPa s] | source |", "|---|---|---|---|---|"]
    for p in PRESETS:
        if p.law == "walther":
            data = (f"`nu_cSt = [{p.nu_cSt[0]:g}, {p.nu_cSt[1]:g}]` at "
                    f"`temperatures_C = [{p.temperatures_C[0]:g}, {p.temperatures_C[1]:g}]`")
        else:
            data = (f"`vogel_a_Pa_s = {p.vogel_a_Pa_s:.6g}`, `vogel_b_K = {p.vogel_b_K:.6g}`, "
                    f"`vogel_c_K = {p.vogel_c_K:.6g}`")
        oil = Oil.grade(p.name)
        mus = ", ".join(f"{oil.mu(t + KELVIN) * 1e3:.4g}" for t in (40.0, 100.0))
        law = "Walther (ASTM D341)" if p.law == "walther" else "Vogel"
        rows.append(f"| {p.name} | {law} | {data} | {mus} | {p.source.replace('|', '/')} |")
    return "\n".join(rows)


def _fmu_internal_cell() -> str:
    from bearing_fmu.fmu.variables import DEFAULT_INTERNAL

    return " \\| ".join(f"`{n}`" + (" (default)" if n == DEFAULT_INTERNAL else "") for n in registry.names())


def _fmu_internal_enum() -> str:
    from bearing_fmu.fmu.variables import ENUMERATIONS

    return ", ".join(f"{k} {n}" for k, n in enumerate(ENUMERATIONS["internal_enum"][1], 1))


# name -> the list's text; each marked place in README.md and docs/*.md shows one of them
GENERATED: dict[str, Callable[[], str]] = {
    "internals": lambda: " | ".join(registry.names()),
    "fmu-internal": _fmu_internal_cell,
    "fmu-internal-enum": _fmu_internal_enum,
    "native-internals": lambda: "|".join(registry.having(native=True)),
    "oil-presets": lambda: "\n\n" + oil_presets_table() + "\n\n",
}


def marked_documents(root: Path = ROOT) -> list[Path]:
    """The documents that may hold marked lists: README.md and docs/*.md."""
    return [root / "README.md", *sorted((root / "docs").glob("*.md"))]


def marked_lists(text: str) -> list[tuple[str, str]]:
    """(name, text) of every marked list in ``text``."""
    return [(m.group(1), m.group(2)) for m in MARKED.finditer(text)]


def write_lists(paths=None) -> list[str]:
    """Write every marked list of ``paths`` (default: ``marked_documents()``) from its generator;
    returns the files changed. An unknown name is an error naming the file and the names known."""
    lists = {name: make() for name, make in GENERATED.items()}
    changed = []
    for path in paths or marked_documents():
        text = path.read_text()
        unknown = sorted({name for name, _ in marked_lists(text)} - lists.keys())
        if unknown:
            raise ValueError(f"{path}: no generated list named {', '.join(unknown)} (known: {', '.join(lists)})")
        new = MARKED.sub(lambda m: f"<!-- generated: {m.group(1)} -->{lists[m.group(1)]}<!-- end -->", text)
        if new != text:
            path.write_text(new)
            changed.append(str(path))
    return changed


# ----------------------------------------------------------------------------- the reference's sections

def _sections(text: str) -> list[tuple[int, int, str]]:
    """(start, end, heading) of every ``##``/``###`` section of a markdown text."""
    heads = [(m.start(), m.group(2)) for m in re.finditer(r"^(#{2,3}) (.*)$", text, re.M)]
    return [(start, heads[i + 1][0] if i + 1 < len(heads) else len(text), h) for i, (start, h) in enumerate(heads)]


def write_reference(path: Path = DOC) -> tuple[list[str], list[str]]:
    """Write each table of ``reference_tables`` as its section of the reference: the table under
    its heading replaced (prose after it kept), a missing section put after the section before it
    in the reference's order, a generated section the code no longer makes removed. Returns
    (headings added, headings removed)."""
    text = path.read_text()
    tables = reference_tables()
    removed = []
    for start, end, heading in reversed(_sections(text)):
        if heading.startswith(GENERATED_HEADINGS) and heading not in tables:
            text = text[:start] + text[end:]
            removed.append(heading)
    added = []
    order = list(tables)
    for i, (heading, table) in enumerate(tables.items()):
        pattern = re.compile(rf"(^### {re.escape(heading)}\n\n)(?:\|.*\n)+", re.M)
        text, n = pattern.subn(lambda m: m.group(1) + table + "\n", text)
        if n:
            continue
        sections = {h: (s, e) for s, e, h in _sections(text)}
        before = [h for h in order[:i] if h in sections]
        after = [h for h in order[i + 1:] if h in sections]
        at = sections[before[-1]][1] if before else (sections[after[0]][0] if after else len(text))
        text = text[:at] + f"### {heading}\n\n{table}\n\n" + text[at:]
        added.append(heading)
    path.write_text(text)
    return added, removed[::-1]


def main(argv: list[str] | None = None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    if argv == ["--write"]:
        added, removed = write_reference()
        changed = write_lists()
        print(f"wrote the tables into {DOC}" + (f"; added the sections {', '.join(added)}" if added else "")
              + (f"; removed the sections {', '.join(removed)}" if removed else "")
              + (f"; wrote the lists in {', '.join(changed)}" if changed else ""))
        return
    for heading, table in reference_tables().items():
        print(f"### {heading}\n\n{table}\n")
    for name, make in GENERATED.items():
        print(f"<!-- generated: {name} -->{make()}<!-- end -->\n")


if __name__ == "__main__":
    main()
