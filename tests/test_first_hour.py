"""The worked examples of the documentation pages run as written and print what the pages say.

``docs/first-hour.md`` (and the getting-started page's first mission) is read as one Python
session: every ```python block runs in order in one namespace, in a fresh folder, and what it
prints must equal the ```text block right after it (a block that prints nothing has none). So
the pages cannot go stale: a change to what the library prints or does fails here.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parent.parent / "docs"
FENCE = re.compile(r"^```(\w*)[ \t]*\n(.*?)^```[ \t]*$", flags=re.MULTILINE | re.DOTALL)


def examples(text: str) -> list[tuple[int, str, str | None]]:
    """``(line, code, expected output)`` of each python block; the output is the text block that follows it."""
    blocks = [(m.group(1), m.group(2), m.start(), m.end()) for m in FENCE.finditer(text)]
    found = []
    for k, (language, code, start, end) in enumerate(blocks):
        if language != "python":
            continue
        following = blocks[k + 1] if k + 1 < len(blocks) else None
        adjacent = following is not None and following[0] == "text" and not text[end : following[2]].strip()
        found.append((text.count("\n", 0, start) + 1, code, following[1] if adjacent and following else None))
    return found


def run_page(page: Path) -> list[tuple[int, str, str | None]]:
    """Run the page's python blocks in order in one namespace: ``(line, printed, expected)`` each."""
    namespace: dict[str, object] = {"__name__": "__main__"}
    outcomes = []
    for line, code, expected in examples(page.read_text(encoding="utf-8")):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, f"{page}:{line}", "exec"), namespace)
        outcomes.append((line, out.getvalue(), expected))
    return outcomes


@pytest.mark.parametrize("name", ["first-hour.md", "getting-started.md"])
def test_the_page_prints_what_it_shows(name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("trimesh")
    pytest.importorskip("matplotlib")
    pytest.importorskip("plotly")  # the getting-started page writes the 3D view
    pytest.importorskip("rasterio")  # the first hour's flight plan: its coverage GeoTIFFs
    pytest.importorskip("pyproj")  # ... and its UTM DEM
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    outcomes = run_page(DOCS / name)
    assert outcomes, f"{name} holds no python block"
    for line, printed, expected in outcomes:
        where = f"docs/{name}, the block at line {line}"
        if expected is None:
            assert printed == "", f"{where} prints but the page shows no output after it:\n{printed}"
        else:
            assert printed.rstrip("\n") == expected.rstrip("\n"), f"{where} printed\n{printed}\nbut the page shows\n{expected}"


def test_a_wrong_output_is_caught(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    page.write_text("```python\nprint(1 + 1)\n```\n\n```text\n3\n```\n\n```python\nx = 1\n```\n")
    (line, printed, expected), (_, silent, none) = run_page(page)
    assert (line, printed, expected) == (1, "2\n", "3\n")
    assert silent == "" and none is None
