"""Every public name has a page in the documentation site (docs/api, one page per name).

The site's API reference lists, per layer, the names of its ``__all__`` in an autosummary with
``:toctree:`` (one generated page each); the build itself (``scripts/docs.sh``, warnings as
errors) also fails on a public name without a page (``docs/_ext/crossrefs.py``). This test
holds the listing without building the site.
"""

from __future__ import annotations

import importlib
import re
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parent.parent / "docs"
sys.path.insert(0, str(DOCS))
_public = importlib.import_module("_ext.public")
MODULES, TOP, public_names = _public.MODULES, _public.TOP, _public.public_names


def _listed(page: Path) -> tuple[set[str], bool]:
    """The names an API page's autosummary lists, and whether it gives each its own page."""
    text = page.read_text()
    block = re.search(r"\.\. autosummary::\n((?:   .*\n|\n)+)", text)
    assert block is not None, f"{page} has no autosummary"
    lines = [line.strip() for line in block.group(1).splitlines()]
    names = {line for line in lines if line and not line.startswith(":")}
    return names, ":toctree: generated" in block.group(1)


def _page(module: str) -> Path:
    return DOCS / "api" / f"{'uavcov' if module == TOP else module.removeprefix('uavcov.')}.rst"


@pytest.mark.parametrize("module", MODULES)
def test_every_public_name_of_a_layer_has_a_page(module: str) -> None:
    names, own_pages = _listed(_page(module))
    assert own_pages, f"{_page(module)} lists its names without giving them pages (:toctree:)"
    missing = [n for n in public_names(module) if n not in names]
    assert not missing, f"{module} names without a page in {_page(module).name}: {missing}"
    stale = sorted(names - set(public_names(module)))
    assert not stale, f"{_page(module).name} lists names {module} no longer has: {stale}"


def test_every_top_level_name_is_documented_where_it_is_defined() -> None:
    top = importlib.import_module(TOP)
    listed, _ = _listed(_page(TOP))
    documented = {id(getattr(importlib.import_module(m), n)) for m in MODULES for n in public_names(m)}
    documented |= {id(importlib.import_module(m)) for m in MODULES}
    assert "__version__" in public_names(TOP) and ".. data:: __version__" in _page(TOP).read_text()
    for name in public_names(TOP):
        if name == "__version__":
            continue
        assert name in listed, f"uavcov.{name} is not in docs/api/uavcov.rst"
        assert id(getattr(top, name)) in documented, f"uavcov.{name} has no page at any layer"


def test_every_layer_has_a_page_in_the_reference() -> None:
    index = (DOCS / "api" / "index.rst").read_text()
    for module in (TOP, *MODULES):
        assert _page(module).is_file()
        assert f"\n   {_page(module).stem}\n" in index, f"{_page(module).name} is not in docs/api/index.rst"


def test_the_check_fails_on_a_missing_name(tmp_path: Path) -> None:
    page = tmp_path / "engine.rst"
    page.write_text(_page("uavcov.engine").read_text().replace("   Terrain\n", ""))
    names, _ = _listed(page)
    assert "Terrain" in public_names("uavcov.engine") and "Terrain" not in names
