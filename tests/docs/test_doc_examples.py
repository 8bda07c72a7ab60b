"""Every ```python block of the README and of the documentation pages runs as written.

The blocks of one page run in order in one namespace (a page reads like a notebook), in a
fresh temporary directory (the examples may write files). ```sh and ```text blocks are not
run. The docstrings' >>> examples are run by test_docstrings.py, the gallery by the docs
build.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
DOCS = ROOT / "docs"

FENCE = re.compile(r"^```python[ \t]*\n(.*?)^```[ \t]*$", re.S | re.M)


def pages() -> list[Path]:
    found = [README] + sorted(p for p in DOCS.rglob("*.md")
                              if "_build" not in p.parts and "_generated" not in p.parts)
    return [p for p in found if p.exists()]


def python_blocks(text: str) -> list[tuple[int, str]]:
    """(first line number, code) of every ```python block."""
    return [(text.count("\n", 0, m.start(1)) + 1, m.group(1)) for m in FENCE.finditer(text)]


def test_the_block_finder_finds_blocks_and_skips_others():
    text = "a\n```python\nx = 1\n```\n```sh\nls\n```\n```python\ny = 2\n```\n"
    assert python_blocks(text) == [(3, "x = 1\n"), (9, "y = 2\n")]  # lines of the code


def test_the_readme_and_the_main_pages_have_examples():
    have = {p.name for p in pages() if python_blocks(p.read_text())}
    for name in ("README.md", "getting-started.md", "robots.md", "method.md", "painting.md"):
        assert name in have


@pytest.mark.parametrize("page", [p for p in pages() if python_blocks(p.read_text())],
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_page_examples_run(page, tmp_path, monkeypatch):
    blocks = python_blocks(page.read_text())
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    namespace: dict = {"__name__": "__doc_example__"}
    out = io.StringIO()
    for line, code in blocks:
        # line numbers in tracebacks point into the page
        source = "\n" * (line - 1) + code
        with contextlib.redirect_stdout(out):
            exec(compile(source, str(page), "exec"), namespace)  # noqa: S102
    if page == README:
        assert "out of reach" in out.getvalue()  # the README's example prints its error
    with contextlib.suppress(ImportError):
        import matplotlib.pyplot as plt

        plt.close("all")
    assert os.getcwd() == str(tmp_path)
