"""The keys of the project's files, as data: one typed list of ``Key`` per table of a file kind.

A ``Key`` carries its name (with its unit), meaning, default and the ``Kind`` of value it takes
(``Number``, ``Text``, ``Choice``, ``FileName``, ``Table``, ``Tables``, ``List``). The loaders
check a whole file once, at the edge, with ``check_table``: a table that is not a table, a
missing or unknown key, a value of the wrong type, shape or range each give one line naming
the file, the table path and key (``[time] dt_s``, ``[[unbalance]] 2 mass_kg``), what was
expected and what was given. What depends on more than one value (a node number against the
rotor's nodes, a clearance against the diameter) is checked by the loader after that.

The file-format reference (docs/file-formats.md) shows the same lists as tables
(``markdown_table``; a test keeps the two equal), so neither can drift from the code.
``read_toml`` reads a file with the same one-line errors (not found, a directory, not text,
a TOML syntax error with its line).
"""

from __future__ import annotations

import difflib
import math
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

REQUIRED = object()  # the default of a key that must be given


class SchemaError(ValueError):
    """A file that does not follow its schema (when the caller names no error type)."""


# ----------------------------------------------------------------------------- showing values

def show(value, limit: int = 60) -> str:
    """A value as it is written in TOML (true, 'text', 1.5, [1, 2], {a = 1}), cut at ``limit``."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, Mapping):
        text = "{" + ", ".join(f"{k} = {show(v, limit)}" for k, v in value.items()) + "}"
    elif isinstance(value, (list, tuple)):
        text = "[" + ", ".join(show(v, limit) for v in value) + "]"
    else:
        text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


class Invalid(Exception):
    """Raised by a ``Kind``: the value is wrong; ``tail`` completes '<key> = <value>' (e.g.
    ' must be a finite number > 0')."""

    def __init__(self, tail: str):
        super().__init__(tail)
        self.tail = tail


# ----------------------------------------------------------------------------- kinds of value

class Kind:
    """The values a key takes. ``check`` returns the value (normalised: ints to float for a
    number) or raises ``Invalid``; a table kind checks its own keys and raises ``error``."""

    def expected(self) -> str:
        raise NotImplementedError

    def check(self, value, where: str, label: str, error: type[Exception]):
        raise NotImplementedError

    def absent(self, default):
        """The value of an optional key that is not given."""
        return list(default) if isinstance(default, list) else default

    def _bad(self, hint: str = "") -> Invalid:
        return Invalid(f" must be {self.expected()}" + (f" ({hint})" if hint else ""))


@dataclass(frozen=True)
class Number(Kind):
    """A finite number (TOML integers are accepted; true/false, inf and nan are not), or with
    ``integer`` a TOML integer; optionally bounded. ``words`` replaces the generated text."""

    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: bool = False
    exclusive_maximum: bool = False
    integer: bool = False
    words: str = ""

    def expected(self) -> str:
        if self.words:
            return self.words
        bounds = []
        if self.minimum is not None:
            bounds.append(f"{'>' if self.exclusive_minimum else '>='} {self.minimum:g}")
        if self.maximum is not None:
            bounds.append(f"{'<' if self.exclusive_maximum else '<='} {self.maximum:g}")
        word = "an integer" if self.integer else "a finite number"
        return word + ("" if not bounds else " " + " and ".join(bounds))

    def parse(self, value):
        """The value as int/float if it is one of this kind, else ``Invalid``."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self._bad()
        if self.integer:
            if not isinstance(value, int):
                raise self._bad("written without a decimal point" if math.isfinite(value) and value == int(value)
                                else "")
        elif not math.isfinite(value):
            raise self._bad()
        v = value if self.integer else float(value)
        lo, hi = self.minimum, self.maximum
        if lo is not None and (v <= lo if self.exclusive_minimum else v < lo):
            raise self._bad()
        if hi is not None and (v >= hi if self.exclusive_maximum else v > hi):
            raise self._bad()
        return v

    def check(self, value, where, label, error):
        return self.parse(value)


@dataclass(frozen=True)
class Text(Kind):
    """A TOML string."""

    def expected(self) -> str:
        return "text in quotes"

    def check(self, value, where, label, error):
        if not isinstance(value, str):
            raise self._bad()
        return value


@dataclass(frozen=True)
class FileName(Kind):
    """A non-empty string naming a file (the loader resolves it and checks it is there)."""

    def expected(self) -> str:
        return "a file name in quotes"

    def check(self, value, where, label, error):
        if not isinstance(value, str) or not value.strip():
            raise self._bad()
        return value


@dataclass(frozen=True)
class Choice(Kind):
    """One of a few words."""

    choices: tuple[str, ...]

    def expected(self) -> str:
        return "one of " + ", ".join(self.choices)

    def check(self, value, where, label, error):
        if not isinstance(value, str) or value not in self.choices:
            raise Invalid(f"; choose one of {', '.join(self.choices)}")
        return value


@dataclass(frozen=True)
class List(Kind):
    """A TOML array of values of one kind; ``length``: exactly that many."""

    item: Kind
    length: int | None = None

    def expected(self) -> str:
        n = f"{self.length} " if self.length else ""
        return f"an array of {n}values, each {self.item.expected()}"

    def check(self, value, where, label, error):
        if not isinstance(value, list) or (self.length is not None and len(value) != self.length):
            raise self._bad()
        out = []
        for i, v in enumerate(value):
            try:
                out.append(self.item.check(v, where, label, error))
            except Invalid as exc:
                raise Invalid(f": entry {i + 1} = {show(v)}{exc.tail}") from None
        return out


@dataclass(frozen=True)
class Table(Kind):
    """A sub-table ``[name]`` with its keys (``keys=None``: any keys, checked by the loader)."""

    keys: Sequence["Key"] | None = None

    def expected(self) -> str:
        return "a table"

    def check(self, value, where, label, error):
        if not isinstance(value, Mapping):
            raise Invalid(f" must be a table ({label} followed by its keys)")
        if self.keys is None:
            return dict(value)
        return check_table(value, self.keys, where, error, label)

    def absent(self, default):
        """An absent table: its defaults, or None when it has required keys (an optional table
        that, once given, must be whole, e.g. [speed_profile])."""
        if self.keys is None or any(k.required for k in self.keys):
            return None
        return check_table({}, self.keys, "", SchemaError)


@dataclass(frozen=True)
class Tables(Kind):
    """An array of tables ``[[name]]``, each with these keys; ``nonempty``: at least one."""

    keys: Sequence["Key"]
    nonempty: bool = False

    def expected(self) -> str:
        return ("a non-empty " if self.nonempty else "an ") + "array of tables"

    def check(self, value, where, label, error):
        name = label.strip("[]")
        if isinstance(value, Mapping):
            raise Invalid(f" must be an array of tables: write [[{name}]] above each entry (a single [{name}] "
                          "is one table, not an array)")
        if not isinstance(value, list) or (self.nonempty and not value):
            raise self._bad(f"[[{name}]] above each entry")
        out = []
        for i, t in enumerate(value):
            if not isinstance(t, Mapping):
                raise Invalid(f": entry {i + 1} = {show(t)} must be a table")
            out.append(check_table(t, self.keys, where, error, f"{label} {i + 1}"))
        return out

    def absent(self, default):
        return []


# ----------------------------------------------------------------------------- keys

@dataclass(frozen=True)
class Key:
    """One key of a file table: its name (carrying its unit, e.g. ``speed_hz``), what it means,
    its default (REQUIRED: must be given), the allowed values in words (default: from its
    kind) and its ``kind`` (None: any value, checked elsewhere)."""

    name: str
    help: str
    default: Any = REQUIRED
    allowed: str = ""
    kind: Kind | None = None

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    @property
    def words(self) -> str:
        """The allowed values in words, for the reference."""
        return self.allowed or (self.kind.expected() if self.kind is not None else "")


def check_keys(table, keys: Sequence[Key], where: str, error: type[Exception] = ValueError, *,
               toml: bool = True) -> None:
    """Raise ``error`` naming ``where`` if ``table`` is not a table, lacks a required key or has
    an unknown one (listing the allowed keys; in a TOML file, tables as [name] and [[name]])."""
    if not isinstance(table, Mapping):
        raise error(f"{where}: expected a table, got {show(table)}")
    names = [k.name for k in keys]
    required = [k.name for k in keys if k.required]
    missing = [k for k in required if k not in table]
    unknown = sorted(set(table) - set(names))
    if not (missing or unknown):
        return
    parts = []
    written = _written if toml else (lambda name, value=None, kind=None: name)
    shown = {k.name: written(k.name, kind=k.kind) for k in keys}  # tables as a TOML file writes them
    # first: a misspelt key is both unknown and missing, and its spelling is the clue; an unknown
    # table ([geometry]) is named as one, so that it does not read as a stray key
    tables = [u for u in unknown if toml and _table_like(table[u])]
    for what, names_of in (("table", tables), ("key", [u for u in unknown if u not in tables])):
        if names_of:
            hints = {u: difflib.get_close_matches(u, [n for n in names if n not in table], 1) for u in names_of}
            parts.append(f"unknown {what}(s) " + ", ".join(
                written(u, table[u]) + (f" (did you mean {shown[hints[u][0]]}?)" if hints[u] else "")
                for u in names_of))
    if missing:
        parts.append(f"missing key(s) {', '.join(missing)}")
    optional = [shown[n] for n in names if n not in required]
    allowed = (f"required: {', '.join(shown[n] for n in required)}"
               + (f"; optional: {', '.join(optional)}" if optional else "")
               if missing else f"allowed: {', '.join(shown.values())}")
    raise error(f"{where}: {'; '.join(parts)}; {allowed}")


def _table_like(value) -> bool:
    """A TOML table or a non-empty array of tables (what [name] / [[name]] write)."""
    return isinstance(value, Mapping) or (isinstance(value, list) and bool(value)
                                          and all(isinstance(v, Mapping) for v in value))


def _written(name: str, value=None, kind: "Kind | None" = None) -> str:
    """A key as a file writes it: [name] for a table, [[name]] for an array of tables."""
    if isinstance(kind, Table) or isinstance(value, Mapping):
        return f"[{name}]"
    if isinstance(kind, Tables) or (value is not None and _table_like(value)):
        return f"[[{name}]]"
    return name


def check_table(table, keys: Sequence[Key], where: str, error: type[Exception] = SchemaError,
                label: str = "") -> dict:
    """Check a table against its keys and return its values, each checked by its kind and
    optional ones filled with their defaults. ``where`` names the file, ``label`` the table's
    path in it ('[time]', '[[unbalance]] 2'; '' for the top level). Every fault raises
    ``error`` with one line: '<file>: <label> <key> = <value> must be <expected>'."""
    check_keys(table, keys, f"{where}: {label}" if label else where, error)
    prefix = f"{where}: {label + ' ' if label else ''}"
    out = {}
    for k in keys:
        sub = f"{label} [{k.name}]".strip() if isinstance(k.kind, Table) else (
            f"{label} [[{k.name}]]".strip() if isinstance(k.kind, Tables) else label)
        if k.name not in table:
            out[k.name] = None if k.required else (k.kind.absent(k.default) if k.kind else k.default)
            continue
        v = table[k.name]
        if k.kind is None:
            out[k.name] = v
            continue
        try:
            out[k.name] = k.kind.check(v, where, sub if isinstance(k.kind, (Table, Tables)) else label, error)
        except Invalid as exc:
            raise error(f"{prefix}{k.name} = {show(v)}{exc.tail}") from None
    return out


def find_non_finite(value) -> str | None:
    """The key path ('errors.Fy.rms', 'H[3][7][0]') of the first number in a parsed JSON value
    that is not a finite float (NaN, Infinity, or an integer beyond the float range), or None.
    Python's json reads NaN and Infinity though JSON has no such numbers; the project's writers
    never write them (allow_nan=False), so one in a file is damage, named before any use."""
    trail = _non_finite(value)
    if trail is None:
        return None
    return "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in reversed(trail)).lstrip(".") or "(top level)"


def _non_finite(value) -> list | None:
    """The reversed key trail to the first non-finite number (built only on the way out)."""
    if isinstance(value, float):
        return None if math.isfinite(value) else []
    if isinstance(value, int) and not isinstance(value, bool):
        return None if abs(value) <= sys.float_info.max else []
    items = value.items() if isinstance(value, Mapping) else (
        enumerate(value) if isinstance(value, (list, tuple)) else ())
    big = sys.float_info.max
    for k, v in items:
        tv = type(v)  # the common cases, without a call: a finite float, an int in the float range
        if (tv is float and v - v == 0.0) or (tv is int and -big <= v <= big):
            continue
        trail = _non_finite(v)
        if trail is not None:
            trail.append(k)
            return trail
    return None


# ----------------------------------------------------------------------------- reading

def read_toml(path, what: str, error: type[Exception] = SchemaError) -> dict:
    """The parsed TOML file at ``path``, or ``error`` in one line: '<what> <path> not found',
    '... is a directory', not readable, not text, or '<path>: not valid TOML: <why> (at line
    L, column C)'."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise error(f"{what} {path} not found") from None
    except IsADirectoryError:
        raise error(f"{what} {path} is a directory, not a file") from None
    except PermissionError:
        raise error(f"{what} {path} cannot be read (permission denied)") from None
    except UnicodeDecodeError:
        raise error(f"{what} {path} is not a text (UTF-8 TOML) file") from None
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{path}: not valid TOML: {exc}") from None
    except OSError as exc:
        raise error(f"{what} {path} cannot be read: {exc.strerror or exc}") from None


# ----------------------------------------------------------------------------- the reference

def _cell(value) -> str:
    return str(value).replace("|", "\\|")


def markdown_table(keys: Sequence[Key]) -> str:
    """The keys as a markdown table: key, meaning, default, allowed values."""
    rows = ["| key | meaning | default | allowed |", "|---|---|---|---|"]
    for k in keys:
        default = "required" if k.required else ("none" if k.default is None else f"`{k.default!r}`")
        rows.append(f"| `{k.name}` | {_cell(k.help)} | {default} | {_cell(k.words)} |")
    return "\n".join(rows)


def option_keys(options) -> list[Key]:
    """The options of an internal (``internals.Option``) as file keys."""
    out = []
    for o in options:
        unit = f" [{o.unit}]" if o.unit and o.unit != "1" else ""
        out.append(Key(o.name, o.help + unit, o.default, o.allowed()))
    return out
