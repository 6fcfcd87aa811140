"""The keys of the project's files, as data: one list of ``Key`` per table of a file kind.

The loaders check a table's keys with ``check_keys`` (missing and unknown keys named with the
allowed ones), and the file-format reference (docs/file-formats.md) shows the same lists as
tables (``markdown_table``; a test keeps the two equal), so neither can drift from the code.
The values themselves are checked by each loader, which names the file, table and key.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Sequence

REQUIRED = object()  # the default of a key that must be given


@dataclass(frozen=True)
class Key:
    """One key of a file table: its name (carrying its unit, e.g. ``speed_hz``), what it means,
    its default (REQUIRED: must be given) and the allowed values in words."""

    name: str
    help: str
    default: Any = REQUIRED
    allowed: str = ""

    @property
    def required(self) -> bool:
        return self.default is REQUIRED


def check_keys(table, keys: Sequence[Key], where: str, error: type[Exception] = ValueError) -> None:
    """Raise ``error`` naming ``where`` if ``table`` is not a table, lacks a required key or has
    an unknown one (listing the allowed keys)."""
    if not isinstance(table, Mapping):
        raise error(f"{where}: expected a table, got {table!r}")
    names = [k.name for k in keys]
    required = [k.name for k in keys if k.required]
    missing = [k for k in required if k not in table]
    if missing:
        optional = [n for n in names if n not in required]
        raise error(f"{where}: missing key(s) {', '.join(missing)}; required: {', '.join(required)}"
                    + (f"; optional: {', '.join(optional)}" if optional else ""))
    unknown = sorted(set(table) - set(names))
    if unknown:
        raise error(f"{where}: unknown key(s) {', '.join(unknown)}; allowed: {', '.join(names)}")


def _cell(value) -> str:
    return str(value).replace("|", "\\|")


def markdown_table(keys: Sequence[Key]) -> str:
    """The keys as a markdown table: key, meaning, default, allowed values."""
    rows = ["| key | meaning | default | allowed |", "|---|---|---|---|"]
    for k in keys:
        default = "required" if k.required else ("none" if k.default is None else f"`{k.default!r}`")
        rows.append(f"| `{k.name}` | {_cell(k.help)} | {default} | {_cell(k.allowed)} |")
    return "\n".join(rows)


def option_keys(options) -> list[Key]:
    """The options of an internal (``internals.Option``) as file keys."""
    out = []
    for o in options:
        unit = f" [{o.unit}]" if o.unit and o.unit != "1" else ""
        out.append(Key(o.name, o.help + unit, o.default, o.allowed()))
    return out
