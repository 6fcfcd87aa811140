"""The generated parts of the documentation (rotor_host/scenes/file_formats.py) against the code:
every table the code makes stands in docs/file-formats.md verbatim under its heading, every marked
list of README.md and docs/*.md equals its generator's text (the internals from the registry, the
oil presets from their records), and the command lines' help texts list what the registry has."""

import shutil
from pathlib import Path

import pytest

from bearing_fmu.internals import registry
from rotor_host.scenes import file_formats as ff
from rotor_host.scenes.file_formats import GENERATED, marked_documents, marked_lists, reference_tables

from conftest import run_cli

DOC = Path(__file__).resolve().parents[1] / "docs" / "file-formats.md"
# a made-up internal (test only): registered, it must appear in every generated list and table
MADE_UP = registry.InternalSpec(
    "made_up", lambda params, o, context: None, "test only",
    options=(registry.Option("made_up_k", float, 1.0, "a made-up option", "N/m"),),
    can=registry.Capabilities(any_state=True, native=True, film_flow=True))


@pytest.fixture
def made_up():
    registry.register(MADE_UP)
    yield MADE_UP
    registry.unregister(MADE_UP.name)


def test_reference_holds_every_table_of_the_code():
    text = DOC.read_text()
    stale = [h for h, table in reference_tables().items() if f"### {h}\n\n{table}\n" not in text]
    assert not stale, ("docs/file-formats.md differs from the code in: " + ", ".join(stale)
                       + "; regenerate the tables with `python -m rotor_host.scenes.file_formats --write`")


def test_every_marked_list_is_its_generators_and_every_list_is_shown():
    shown, stale = set(), []
    for path in marked_documents():
        for name, text in marked_lists(path.read_text()):
            assert name in GENERATED, f"{path.name}: no generated list named {name!r}"
            shown.add(name)
            if text != GENERATED[name]():
                stale.append(f"{path.name}: {name}")
    assert not stale, (f"stale lists: {', '.join(stale)}; write them with "
                       "`python -m rotor_host.scenes.file_formats --write`")
    assert shown == set(GENERATED), f"lists no document shows: {', '.join(sorted(set(GENERATED) - shown))}"


def test_the_lists_follow_the_registry(made_up):
    # what a newcomer's internal gets without writing a word: its name in each list of its
    # capabilities (the registry's order: registration order)
    assert GENERATED["internals"]() == " | ".join(registry.names())  # in the registry's order
    assert GENERATED["internals"]().endswith(" | made_up")
    assert GENERATED["native-internals"]().endswith("|made_up")
    assert "`reynolds` (default)" in GENERATED["fmu-internal"]()


def test_write_makes_whole_sections_and_lists(made_up, tmp_path):
    """--write on a copy: a missing section (a newly registered internal's) is added with its
    heading after the section before it, a section the code no longer makes is removed, a table
    under its heading is replaced with the prose after it kept, and the marked lists are written."""
    doc = tmp_path / "file-formats.md"
    text = DOC.read_text()
    text = text.replace("### Scene file: [time]\n",
                        "### Scene file: [gone]\n\n| key |\n|---|\n\n### Scene file: [time]\n")
    doc.write_text(text)
    added, removed = ff.write_reference(doc)
    assert added == ["Scene file: [made_up]"] and removed == ["Scene file: [gone]"]
    new = doc.read_text()
    table = reference_tables()["Scene file: [made_up]"]
    assert "| `made_up_k` | a made-up option [N/m] | `1.0` |" in table
    # after the section of the internal registered before it (its table and prose), before the next part
    before = [n for n in registry.names() if n != "made_up"][-1]
    assert new.index(f"### Scene file: [{before}]") < new.index(f"### Scene file: [made_up]\n\n{table}\n\n## Run result")
    assert new.replace(f"### Scene file: [made_up]\n\n{table}\n\n", "") == DOC.read_text()
    readme = tmp_path / "README.md"
    shutil.copyfile(DOC.parents[1] / "README.md", readme)
    assert ff.write_lists([readme]) == [str(readme)]
    assert f"<!-- generated: internals -->{' | '.join(registry.names())}<!-- end -->" in readme.read_text()
    bad = tmp_path / "bad.md"
    bad.write_text("<!-- generated: nothing -->x<!-- end -->")
    with pytest.raises(ValueError, match=rf"{bad}: no generated list named nothing \(known: internals,"):
        ff.write_lists([bad])


@pytest.mark.parametrize("prog, argv, capability", [
    ("bearing-fmu", ["demo", "--help"], "film_flow"),
    ("bearing-fmu", ["build", "--help"], "native"),
    ("rotor-host", ["stability", "--help"], "any_state"),
])
def test_help_texts_list_the_registrys_internals(made_up, capsys, prog, argv, capability):
    code, out, _ = run_cli(prog, argv, capsys)
    assert code == 0
    words = " ".join(out.split())
    for name in registry.having(**{capability: True}):
        assert name in words, f"{prog} {argv[0]} --help does not name {name}"
