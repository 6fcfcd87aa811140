"""Typed command-line values: ``type=`` callables for argparse that refuse a bad value by name.

argparse calls the ``type`` of an option on its text; an ``ArgumentTypeError`` raised there
becomes ``<prog>: error: argument --dt: expected a finite number > 0 s, got 'inf'`` and exit
status 2, before any work is done. Each factory below returns such a callable whose message
says what was expected (with the unit) and what was given:

* numbers: ``number`` (any bounds, integers), ``positive_float``, ``nonneg_float``,
  ``finite_float``, ``positive_int``, ``int_at_least``; ``typed`` wraps any check that
  raises ValueError (the fit recipe's own settings use it, so the command line and the
  recipe refuse the same values with the same words);
* Reynolds grids written ``NxM`` (``grid``), checked against the Reynolds options' ranges;
* ranges written ``START:STOP:STEP`` (``float_range``: the values, both ends included),
  intervals ``MIN:MAX`` (``interval``), point loads written ``NODE:FY:FZ`` (``node_load``) and
  unbalances ``NODE:MASS_G:RADIUS_MM[:PHASE_DEG]`` (``unbalance``);
* paths: ``existing_file``, ``existing_dir``, ``output_dir``, ``output_file``: an output path
  that names the wrong kind of thing (a file for a folder, a folder for a file, a file in the
  middle of the path) is refused while parsing; whether the folder accepts files is checked
  when the command starts (``outputs.ensure_writable``, which creates it).

Choices need nothing here: argparse's ``choices=`` already names the option and the choices.
Zero is a value like any other: callers test ``is None`` for an option left out, never truth.
"""

from __future__ import annotations

import argparse
import math
import os
import re
from pathlib import Path
from typing import Any, Callable

from .schema import Invalid, Number


# what reads as a negative number after an option (``cli.Parser``): argparse's own test (-5, -.5)
# misses exponents (-1e3) and -inf / -nan, so `--load-z -1e3` failed as "expected one argument"
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)


def _refuse(expected: str, text: str, why: str = "") -> argparse.ArgumentTypeError:
    return argparse.ArgumentTypeError(f"expected {expected}, got {text!r}" + (f" ({why})" if why else ""))


def typed(expected: str, convert: Callable[[str], Any], check: Callable[[Any], Any] | None = None):
    """An argparse type: ``convert`` the text (e.g. float), then ``check`` it (returns the value
    or raises ValueError); either failing refuses the text with 'expected <expected>, got ...'."""

    def parse(text: str):
        try:
            value = convert(text)
            return check(value) if check is not None else value
        except (ValueError, TypeError, Invalid):
            raise _refuse(expected, text) from None

    parse.__name__ = expected  # what argparse shows if anything else goes wrong
    parse.expected = expected
    return parse


def number(unit: str = "", minimum: float | None = None, maximum: float | None = None, *,
           exclusive_minimum: bool = False, exclusive_maximum: bool = False, integer: bool = False):
    """A finite number (or an integer) within the bounds; ``unit`` is named in the message."""
    kind = Number(minimum, maximum, exclusive_minimum, exclusive_maximum, integer)
    return typed(kind.expected() + (f" {unit}" if unit else ""), int if integer else float, kind.parse)


def positive_float(unit: str = ""):
    """A finite number > 0 (a time step, a duration, a speed)."""
    return number(unit, 0.0, exclusive_minimum=True)


def nonneg_float(unit: str = ""):
    """A finite number >= 0."""
    return number(unit, 0.0)


def finite_float(unit: str = ""):
    """Any finite number (a load that may point either way)."""
    return number(unit)


def int_at_least(minimum: int, unit: str = ""):
    """An integer >= minimum."""
    return number(unit, minimum, integer=True)


def positive_int(unit: str = ""):
    """An integer >= 1."""
    return int_at_least(1, unit)


# ----------------------------------------------------------------------------- Reynolds grids

_GRID = re.compile(r"^\s*(\d+)\s*[xX]\s*(\d+)\s*$")


def _grid_ranges() -> tuple[Number, Number, bool]:
    """(n_theta, n_x) ranges of the Reynolds solver's options, and whether n_x must be even."""
    from ..internals.registry import get

    opts = {o.name: o for o in get("reynolds").options}
    t, x = opts["n_theta"], opts["n_x"]
    return Number(t.minimum, t.maximum, integer=True), Number(x.minimum, x.maximum, integer=True), x.even


def grid_words() -> str:
    t, x, even = _grid_ranges()
    return (f"a grid NxM (n_theta x n_x, e.g. 64x8): n_theta an integer {t.minimum:g}..{t.maximum:g}, n_x "
            f"{'an even' if even else 'an'} integer {x.minimum:g}..{x.maximum:g}")


def parse_grid(text: str) -> tuple[int, int]:
    """``'64x8'`` -> (64, 8), checked against the Reynolds solver's ranges; ValueError if not."""
    m = _GRID.match(text)
    if not m:
        raise ValueError(text)
    t, x, even = _grid_ranges()
    n_theta, n_x = t.parse(int(m.group(1))), x.parse(int(m.group(2)))
    if even and n_x % 2:
        raise ValueError(text)
    return n_theta, n_x


def grid(text: str) -> tuple[int, int]:
    """An argparse type: a Reynolds grid ``NxM`` as (n_theta, n_x)."""
    try:
        return parse_grid(text)
    except (ValueError, Invalid):
        raise _refuse(grid_words(), text) from None


def grid_or_default(text: str) -> tuple[int, int] | None:
    """Like ``grid``; the empty text is None (the solver's default grid)."""
    if not text.strip():
        return None
    try:
        return parse_grid(text)
    except (ValueError, Invalid):
        raise _refuse(grid_words() + ", or '' for the default grid", text) from None


# ----------------------------------------------------------------------------- ranges and loads

MAX_RANGE_VALUES = 100_000  # a range longer than this is a typo (a step in the wrong unit), not a study


def float_range(unit: str = "", minimum: float = 0.0, *, exclusive_minimum: bool = True):
    """An argparse type: ``START:STOP:STEP`` -> the values START, START + STEP, ... up to STOP
    (included when the steps reach it to round-off), a list of floats; a single number is one
    value. START > ``minimum`` (or >= without ``exclusive_minimum``), STOP >= START, STEP > 0, at
    most MAX_RANGE_VALUES values. Values are START + i STEP rounded to 12 significant digits, so
    10:70:0.1 gives 22.3, not 22.300000000000004."""
    lo = Number(minimum, exclusive_minimum=exclusive_minimum)
    step_kind = Number(0.0, exclusive_minimum=True)
    u = f" {unit}" if unit else ""
    expected = (f"START:STOP:STEP{u} (e.g. 10:70:1) or one number, with START {lo.expected().removeprefix('a finite number ')}"
                f", STOP >= START, STEP > 0, at most {MAX_RANGE_VALUES} values")

    def parse(text: str) -> list[float]:
        parts = text.split(":")
        try:
            if len(parts) == 1:
                return [lo.parse(float(parts[0]))]
            if len(parts) != 3:
                raise ValueError(text)
            start, stop, step = (float(p) for p in parts)
            start, step = lo.parse(start), step_kind.parse(step)
            stop = Number().parse(stop)
        except (ValueError, Invalid):
            raise _refuse(expected, text) from None
        if stop < start:
            raise _refuse(expected, text, f"STOP {stop:g} < START {start:g}")
        n = int(math.floor((stop - start) / step * (1.0 + 1e-12) + 1e-9)) + 1
        if n > MAX_RANGE_VALUES:
            raise _refuse(expected, text, f"{n} values")
        return [float(f"{start + i * step:.12g}") for i in range(n)]

    parse.__name__ = "START:STOP:STEP"
    parse.expected = expected
    return parse


def node_load(text: str) -> tuple[int, float, float]:
    """An argparse type: ``NODE:FY:FZ`` -> (node, Fy, Fz): a static point load [N] on a 1-based
    node (its range is checked against the rotor by the command that reads the rotor)."""
    expected = "NODE:FY:FZ (a node number >= 1 and two finite forces [N], e.g. 6:0:-50)"
    parts = text.split(":")
    try:
        if len(parts) != 3:
            raise ValueError(text)
        node = Number(1, integer=True).parse(int(parts[0]))
        fy, fz = (Number().parse(float(p)) for p in parts[1:])
    except (ValueError, Invalid):
        raise _refuse(expected, text) from None
    return node, fy, fz


def unbalance(text: str) -> tuple[int, float, float, float]:
    """An argparse type: ``NODE:MASS_G:RADIUS_MM[:PHASE_DEG]`` -> (node, mass [g], radius [mm],
    phase [deg], 0 when left out): an unbalance on a 1-based node (its range is checked against
    the rotor by the command that reads the rotor)."""
    expected = ("NODE:MASS_G:RADIUS_MM[:PHASE_DEG] (a node number >= 1, a mass > 0 g, a radius > 0 mm and a "
                "finite angle [deg], e.g. 6:1.5:40:0)")
    parts = text.split(":")
    try:
        if len(parts) not in (3, 4):
            raise ValueError(text)
        node = Number(1, integer=True).parse(int(parts[0]))
        mass, radius = (Number(0.0, exclusive_minimum=True).parse(float(p)) for p in parts[1:3])
        phase = Number().parse(float(parts[3])) if len(parts) == 4 else 0.0
    except (ValueError, Invalid):
        raise _refuse(expected, text) from None
    return node, mass, radius, phase


def interval(unit: str = ""):
    """An argparse type: ``MIN:MAX`` -> (min, max) with 0 < MIN <= MAX (e.g. an operating speed range)."""
    u = f" {unit}" if unit else ""
    expected = f"MIN:MAX{u} with 0 < MIN <= MAX (e.g. 40:50)"

    def parse(text: str) -> tuple[float, float]:
        parts = text.split(":")
        try:
            if len(parts) != 2:
                raise ValueError(text)
            lo = Number(0.0, exclusive_minimum=True).parse(float(parts[0]))
            hi = Number(lo).parse(float(parts[1]))
        except (ValueError, Invalid):
            raise _refuse(expected, text) from None
        return lo, hi

    parse.__name__ = "MIN:MAX"
    parse.expected = expected
    return parse


# ----------------------------------------------------------------------------- paths

def platform_list(text: str) -> str:
    """``all`` or a comma-separated list of the native FMU's platforms (linux64, win64, darwin64)."""
    names = {"linux64", "win64", "darwin64"}  # bearing_fmu.fmu.native.compile.PLATFORMS
    parts = [t.strip() for t in text.split(",") if t.strip()]
    if parts == ["all"] or (parts and set(parts) <= names):
        return ",".join(parts)
    raise _refuse("all or a comma-separated list of " + ", ".join(sorted(names)), text)


def existing_file(text: str) -> str:
    """A file that is there (not a folder)."""
    p = Path(text)
    if p.is_file():
        return text
    raise _refuse("an existing file", text, "a directory" if p.is_dir() else "not found")


def existing_file_or(find: Callable[[str], Any], what: str):
    """An argparse type: a file that is there, else the file ``find(text)`` returns (e.g. a
    bundled file named by its stem), else refused naming both (``what``: what find looks for)."""

    def parse(text: str) -> str:
        p = Path(text)
        if p.is_file():
            return text
        found = None if p.is_dir() else find(text)
        if found is not None:
            return str(found)
        raise _refuse(f"an existing file or {what}", text, "a directory" if p.is_dir() else "not found")

    parse.__name__ = "existing file"
    return parse


def existing_dir(text: str) -> str:
    """A folder that is there."""
    p = Path(text)
    if p.is_dir():
        return text
    raise _refuse("an existing folder", text, "a file" if p.exists() else "not found")


def _file_in_the_way(p: Path) -> str:
    """'' if the folders above ``p`` exist or can be made, else which one is a file."""
    for parent in p.absolute().parents:
        if parent.exists():
            return "" if parent.is_dir() else f"{parent} is a file, not a folder"
    return ""


def output_dir(text: str) -> str:
    """A folder to write into: a folder, or a path where one can be made (no file in its way)."""
    p = Path(text)
    if not text.strip():
        raise _refuse("a folder to write into", text)
    if p.exists() and not p.is_dir():
        raise _refuse("a folder to write into", text, "it is a file")
    why = "" if p.is_dir() else _file_in_the_way(p)
    if why:
        raise _refuse("a folder to write into", text, why)
    return text


def output_file(text: str) -> str:
    """A file to write: not a folder, in a folder that exists or can be made."""
    p = Path(text)
    if not text.strip() or text.endswith(("/", os.sep)) or p.is_dir():
        raise _refuse("a file to write", text, "a directory" if p.is_dir() else "")
    why = _file_in_the_way(p)
    if why:
        raise _refuse("a file to write", text, why)
    return text


__all__ = ["NEGATIVE_NUMBER", "typed", "number", "positive_float", "nonneg_float", "finite_float", "int_at_least", "positive_int",
           "grid", "grid_or_default", "parse_grid", "grid_words", "float_range", "node_load", "existing_file", "existing_file_or",
           "existing_dir", "output_dir",
           "output_file"]
