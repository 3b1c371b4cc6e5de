"""The documentation site as a reader meets it: its getting-started page and its gallery opened in
headless Chromium (``browser.py``), offline.

The site must be built first (``bash scripts/docs.sh``, into ``docs/_build/html``):
``scripts/test.sh`` builds it and then runs this file, so CI runs it for real; without a built
site the tests skip and say so (and fail under CI, ``CI`` set, like the browser itself).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest

from browser import RENDERED, chromium, wait_until

SITE = Path(__file__).resolve().parents[1] / "docs" / "_build" / "html"

# Each kind of result the gallery must show, and the example page that shows it.
GALLERY = {
    "terrain": "g01_coverage_map",
    "buildings": "g07_buildings",
    "structure from several sides": "g08_structure",
    "plan on a DEM": "g09_plan",
    "certified bound": "g11_bound",
}
VIEW_PAGE = "g10_view"

INSTALL_COMMANDS = (
    "python3 -m venv .venv",
    'pip install -e ".[test,docs]"',
    "maturin develop --release",
    "bash scripts/demo.sh",
    "bash scripts/test.sh",
)

# Every image of the page loaded, with its size in CSS pixels.
_IMAGES = """
return Array.from(document.querySelectorAll('article img')).map(
    img => [img.getAttribute('src'), img.complete && img.naturalWidth > 0, img.naturalWidth, img.naturalHeight]);
"""


@pytest.fixture(scope="module")
def site() -> Path:
    if not (SITE / "index.html").is_file() or not (SITE / "auto_gallery" / "index.html").is_file():
        reason = f"the documentation site is not built at {SITE}: run `bash scripts/docs.sh` first (scripts/test.sh does, then this test)"
        if os.environ.get("CI"):
            pytest.fail(f"CI must run the site's browser test, but {reason}")
        pytest.skip(reason)
    return SITE


@pytest.fixture(scope="module")
def driver(site: Path) -> Any:
    with chromium(window=(1400, 1000)) as browser:
        browser.set_page_load_timeout(120)
        yield browser


def _open(driver: Any, page: Path) -> None:
    driver.get(page.resolve().as_uri())
    assert wait_until(driver, "return document.readyState === 'complete';", 60.0), page


# The theme's one console error on a file:// page (no stored light / dark mode to read back),
# which it answers itself by falling back to "auto".
_THEME_NOTE = "Got invalid theme mode"


def _severe(driver: Any) -> list[str]:
    """The page's console errors (a failed fetch, a script error), the theme's note left out."""
    messages = [str(e.get("message", "")) for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
    return [m for m in messages if _THEME_NOTE not in m]


def test_getting_started_shows_the_install_commands(site: Path, driver: Any) -> None:
    from selenium.webdriver.common.by import By

    _open(driver, site / "getting-started.html")
    code = "\n".join(block.text for block in driver.find_elements(By.CSS_SELECTOR, "article pre, article code"))
    missing = [command for command in INSTALL_COMMANDS if command not in code]
    assert not missing, f"the getting-started page's code lacks {missing}"
    assert any(ok and width > 100 for _, ok, width, _ in driver.execute_script(_IMAGES)), "the page shows no picture"
    # Reachable from the landing page and the API landing.
    for page in ("index.html", "api/index.html"):
        _open(driver, site / page)
        links = [a.get_attribute("href") or "" for a in driver.find_elements(By.CSS_SELECTOR, "article a")]
        assert any(link.endswith("getting-started.html") for link in links), f"{page} does not link to getting started"
    assert not _severe(driver)


@pytest.mark.parametrize("kind", list(GALLERY))
def test_the_gallery_shows_every_kind_of_result(site: Path, driver: Any, kind: str) -> None:
    from selenium.webdriver.common.by import By

    _open(driver, site / "auto_gallery" / "index.html")
    links = [a.get_attribute("href") or "" for a in driver.find_elements(By.CSS_SELECTOR, "article a")]
    assert any(link.endswith(f"{GALLERY[kind]}.html") for link in links), f"the gallery's index does not list {kind}"
    _open(driver, site / "auto_gallery" / f"{GALLERY[kind]}.html")
    images = [(src, ok, w, h) for src, ok, w, h in driver.execute_script(_IMAGES) if "sphx_glr" in (src or "")]
    assert images, f"no figure on the {kind} page"
    assert all(ok and w >= 200 and h >= 150 for _, ok, w, h in images), images
    assert not _severe(driver)


def test_the_gallery_embeds_the_3d_view(site: Path, driver: Any) -> None:
    from selenium.webdriver.common.by import By

    _open(driver, site / "auto_gallery" / f"{VIEW_PAGE}.html")
    assert wait_until(driver, RENDERED, 90.0), "the embedded 3D view did not render"
    plot = driver.find_element(By.CSS_SELECTOR, ".uavcov-view .js-plotly-plot")
    assert plot.size["width"] > 400 and plot.size["height"] > 400
    legend = driver.execute_script("return Array.from(document.querySelectorAll('.legendtext')).map(t => t.textContent);")
    assert {"surface: seen", "surface: not seen"} <= set(legend), legend
    assert not _severe(driver)


def test_the_methods_equations_render_offline(site: Path, driver: Any) -> None:
    """MathJax is served by the site itself (sphinx-mathjax-offline): with the network cut, every
    equation of the method page is typeset, none left as TeX."""
    _open(driver, site / "method.html")
    typeset = "document.querySelectorAll('mjx-container').length"
    assert wait_until(driver, f"return {typeset} >= 10;", 60.0), driver.execute_script(f"return {typeset};")
    text = driver.execute_script("return document.querySelector('article').innerText;")
    assert "\\mathbf" not in text and "\\frac" not in text, "TeX left untypeset on the method page"
    assert not _severe(driver)
