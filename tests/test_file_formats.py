"""The file-format reference (docs/file-formats.md) against the key lists the loaders check:
every table the code makes must stand in the reference verbatim, under its heading."""

from pathlib import Path

from rotor_host.scenes.file_formats import reference_tables

DOC = Path(__file__).resolve().parents[1] / "docs" / "file-formats.md"


def test_reference_holds_every_table_of_the_code():
    text = DOC.read_text()
    stale = [h for h, table in reference_tables().items() if f"### {h}\n\n{table}\n" not in text]
    assert not stale, ("docs/file-formats.md differs from the code in: " + ", ".join(stale)
                       + "; regenerate the tables with `python -m rotor_host.scenes.file_formats`")

