"""docs/api.md runs as shown: every ```python block of the page, in order, in one namespace,
in an empty working folder, as a doctest (ELLIPSIS, NORMALIZE_WHITESPACE). A snippet that
raises or prints anything other than the page shows fails the test, naming the page's line.

Blocks preceded by the line ``<!-- api-doc: slow -->`` (building and simulating FMUs) run
only in the slow test, which runs the whole page."""

import doctest
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "api.md"
SLOW = "<!-- api-doc: slow -->"
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def blocks() -> list[tuple[int, bool, str]]:
    """(0-based line of the block's first code line, slow, code) of every ```python block."""
    lines = PAGE.read_text(encoding="utf-8").splitlines()
    out, i = [], 0
    while i < len(lines):
        if lines[i].strip() == "```python":
            end = next((j for j in range(i + 1, len(lines)) if lines[j].strip() == "```"), None)
            assert end is not None, f"{PAGE}:{i + 1}: the ```python block is not closed"
            before = next((line.strip() for line in reversed(lines[:i]) if line.strip()), "")
            out.append((i + 1, before == SLOW, "\n".join(lines[i + 1:end]) + "\n"))
            i = end
        i += 1
    return out


def run_page(folder: Path, slow: bool) -> int:
    """Run the page's blocks (the slow ones too if ``slow``) in ``folder``; the number run."""
    parser = doctest.DocTestParser()
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    globs = {"__name__": "api_doc"}
    old = Path.cwd()
    os.chdir(folder)
    n = 0
    try:
        for start, is_slow, code in blocks():
            if is_slow and not slow:
                continue
            name = f"docs/api.md, block at line {start + 1}"
            test = parser.get_doctest(code, globs, name, str(PAGE), start)
            assert test.examples, f"{name}: a python block without >>> examples runs nothing"
            report = []
            result = runner.run(test, out=report.append, clear_globs=False)
            if result.failed:
                pytest.fail("".join(report), pytrace=False)
            globs = test.globs  # the next block sees what this one defined
            n += 1
    finally:
        os.chdir(old)
    assert globs["MODELS"] == ROOT / "rotor_host" / "bundled", \
        f"the page read the models of {globs['MODELS']}, not of this checkout {ROOT}"
    return n


def test_page_blocks_are_found():
    found = blocks()
    assert len(found) >= 15 and sum(slow for _, slow, _ in found) == 3


def test_api_doc(tmp_path):
    """The page without its FMU builds (about 1.5 s with a warm numba cache)."""
    run_page(tmp_path, slow=False)


@pytest.mark.slow
@pytest.mark.native  # the page's native FMU build
def test_api_doc_with_fmus(tmp_path, code_cache):
    """The whole page, the FMU builds and fmpy simulations included (about 4 s: a C compile, a
    pythonfmu build, numba in a fresh FMU code cache)."""
    assert run_page(tmp_path, slow=True) == len(blocks())
