"""The README's quick start runs as written, and prints a coverage in [0, 1]."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parent.parent / "README.md"


def _section(text: str, title: str) -> str:
    """The body of the ``## title`` section: up to the next heading of level 1 or 2 (outside code)."""
    body: list[str] = []
    inside = fenced = False
    for line in text.splitlines(keepends=True):
        if line.startswith("```"):
            fenced = not fenced
        heading = not fenced and re.match(r"#{1,2} ", line) is not None
        if heading:
            if inside:
                break
            inside = line[2:].strip() == title
        elif inside:
            body.append(line)
    if not inside:
        pytest.fail(f"README.md has no '## {title}' section")
    return "".join(body)


def _python_block(section: str) -> str:
    blocks = re.findall(r"^```python[ \t]*\n(.*?)^```[ \t]*$", section, flags=re.MULTILINE | re.DOTALL)
    if len(blocks) != 1:
        pytest.fail(f"the Quick start section should hold exactly one ```python block, found {len(blocks)}")
    return blocks[0]


def test_the_quick_start_runs_and_prints_a_coverage():
    code = _python_block(_section(README.read_text(encoding="utf-8"), "Quick start"))
    prints = [line.strip() for line in code.splitlines() if line.strip().startswith("print(")]
    assert prints and prints[0].startswith("print(vis.coverage("), "the quick start's first print should be the coverage"
    out = io.StringIO()
    namespace: dict[str, object] = {"__name__": "__readme__"}
    with contextlib.redirect_stdout(out):
        exec(compile(code, f"{README}:Quick start", "exec"), namespace)
    lines = out.getvalue().splitlines()
    assert lines, "the quick start printed nothing"
    coverage = float(lines[0])  # what print(vis.coverage(uavs)) wrote
    assert 0.0 <= coverage <= 1.0


def test_the_structures_snippet_runs_and_prints_what_the_readme_says():
    text = README.read_text(encoding="utf-8")
    section = _section(text, "Structures: under a deck, beside a tower")
    code = _python_block(section)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, f"{README}:Structures", "exec"), {"__name__": "__readme__"})
    best = out.getvalue().split()[0]
    assert f"It prints `{best}`" in section, "the README states the coverage its snippet prints"
    assert "deck_underside" in out.getvalue()
