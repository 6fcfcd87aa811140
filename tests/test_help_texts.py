"""The command lines' help texts against the options they describe: every option says something
that names it (a word of its name or metavar, or the thing an abbreviation stands for), no two
options of one command share a help text (the copy-paste that put --map's text under --surrogate
in `rotor-host stability --help`), and the file options name their kind of file. Reads the
parsers only: no command runs."""

from __future__ import annotations

import argparse
import re

import pytest

from bearing_fmu.cli import main as _bearing_main  # noqa: F401  (the module the parser is built in)

# what an option's name stands for where its help says it in other words (an abbreviation, a symbol)
MEANS = {"dt": ("time step",), "o": ("write",), "out": ("folder",), "output": ("write",), "debug": ("traceback",),
         "quiet": ("progress",), "workers": ("worker", "process"), "hold": ("held",), "revs": ("revolution",),
         "tol": ("converged", "band"), "rel_tol": ("trend",), "eps_max": ("eccentricity",), "v_max": ("velocity",),
         "t_end": ("time",), "settle_s": ("transient",), "scale": ("factor",), "points": ("values",),
         "phases": ("attitude",), "note": ("text",), "n_test": ("held-out",), "no_anchor": ("constant",),
         "designed": ("samples",), "no_prune": ("all terms",)}


def _parsers():
    """(command, subparser) of both command lines."""
    import rotor_host.cli as rh
    import bearing_fmu.cli as bf

    out = []
    for prog, build in (("rotor-host", rh.build_parser), ("bearing-fmu", _bearing_parser(bf))):
        parser = build()
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                out += [(f"{prog} {name}", sub) for name, sub in action.choices.items()]
    return out


def _bearing_parser(bf):
    """bearing-fmu builds its parser inside main(): catch it at parse_args."""
    def build():
        seen = {}

        class Caught(Exception):
            pass

        original = argparse.ArgumentParser.parse_args

        def grab(self, *a, **k):
            seen["parser"] = self
            raise Caught

        argparse.ArgumentParser.parse_args = grab
        try:
            bf.main(["demo"])
        except Caught:
            pass
        finally:
            argparse.ArgumentParser.parse_args = original
        return seen["parser"]

    return build


def _options(sub):
    return [a for a in sub._actions if a.option_strings and a.help != argparse.SUPPRESS
            and not isinstance(a, argparse._HelpAction)]


def _words(action) -> list[str]:
    names = [action.dest] + [s.lstrip("-") for s in action.option_strings]
    words = {w for n in names for w in re.split(r"[-_]", n) if len(w) >= 3 or n == w}
    if isinstance(action.metavar, str):
        words |= {w for w in re.split(r"[^A-Za-z]", action.metavar) if len(w) >= 3}
    words |= {w for n in names for w in MEANS.get(n.replace("-", "_"), ())}
    return sorted(words)


PARSERS = _parsers()


@pytest.mark.parametrize("command,sub", PARSERS, ids=[c for c, _ in PARSERS])
def test_every_option_has_a_help_that_names_it(command, sub):
    bad = []
    for a in _options(sub):
        text = (a.help or "").lower()
        words = _words(a)
        # a word counts with its stem (speeds -> speed, unbalance -> unbalanc)
        if not text or not any(w.lower()[: max(3, len(w) - 2)] in text for w in words):
            bad.append(f"{'/'.join(a.option_strings)}: {a.help!r} (expected one of {words})")
    assert not bad, f"{command}: help texts that do not name their option:\n" + "\n".join(bad)


@pytest.mark.parametrize("command,sub", PARSERS, ids=[c for c, _ in PARSERS])
def test_no_two_options_share_a_help_text(command, sub):
    seen = {}
    for a in _options(sub):
        if a.help:
            assert a.help not in seen, f"{command}: {a.option_strings} has the help of {seen[a.help]}: {a.help!r}"
            seen[a.help] = a.option_strings


@pytest.mark.parametrize("command,sub", PARSERS, ids=[c for c, _ in PARSERS])
def test_file_options_name_their_kind_of_file(command, sub):
    for a in _options(sub):
        for flag, kind in (("--map", "map"), ("--surrogate", "surrogate"), ("--bearing", "bearing")):
            if flag in a.option_strings:
                assert kind in a.help.lower(), f"{command} {flag}: {a.help!r} does not say {kind}"
                other = {"map": "surrogate", "surrogate": "map"}.get(kind)
                if other:  # the --surrogate help with --map's text was the bug
                    assert f"{other} file" not in a.help.lower(), f"{command} {flag}: {a.help!r}"


def test_the_check_catches_a_copied_help():
    """The checks fail on the bug they were written for (a copy of --map's help under --surrogate)."""
    p = argparse.ArgumentParser()
    p.add_argument("--map", help="the map internal's map file")
    p.add_argument("--surrogate", help="the map internal's map file")
    with pytest.raises(AssertionError):
        test_no_two_options_share_a_help_text("x", p)
    with pytest.raises(AssertionError):
        test_file_options_name_their_kind_of_file("x", p)
