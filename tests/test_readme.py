"""The README's quick start and structures snippet run as written and print what the README shows."""

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


def _shown_output(section: str) -> str:
    """The ```text block that follows the section's python block: what the README says it prints."""
    found = re.search(r"^```python[ \t]*\n.*?^```[ \t]*$.*?^```text[ \t]*\n(.*?)^```[ \t]*$", section, flags=re.MULTILINE | re.DOTALL)
    if found is None:
        pytest.fail("the Quick start should show what it prints in a ```text block after its code")
    return found.group(1)


def test_the_quick_start_prints_what_the_readme_shows():
    section = _section(README.read_text(encoding="utf-8"), "Quick start")
    code = _python_block(section)
    out = io.StringIO()
    namespace: dict[str, object] = {"__name__": "__readme__"}
    with contextlib.redirect_stdout(out):
        exec(compile(code, f"{README}:Quick start", "exec"), namespace)
    printed = out.getvalue()
    shown = _shown_output(section)
    assert printed.rstrip("\n") == shown.rstrip("\n"), f"the quick start printed\n{printed}\nbut the README shows\n{shown}"
    coverage = float(printed.splitlines()[0])  # the first line is vis.coverage(uavs): a share
    assert 0.0 < coverage < 1.0


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
