"""Open an HTML file in headless Chromium (Debian's ``chromium`` and ``chromium-driver``, driven
by selenium) with the network cut, wait for a plotly figure to render, and report what a reader
would see: the browser console's errors and a screenshot of the plot.

No browser is downloaded at run time: the binaries are the system's (``.ci/run`` installs them).
A test that needs them calls :func:`require_chromium`: it skips when they are missing on a
developer's machine, and fails under CI (``CI`` set), where they must be present.
"""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

BROWSERS = ("chromium", "chromium-browser")
DRIVERS = ("chromedriver", "chromium.chromedriver")


def _which(names: tuple[str, ...]) -> str | None:
    for name in names:
        found = shutil.which(name) or (f"/usr/bin/{name}" if os.access(f"/usr/bin/{name}", os.X_OK) else None)
        if found:
            return found
    return None


def require_chromium() -> tuple[str, str]:
    """The paths of Chromium and its driver; skip the test without them (fail under CI)."""
    browser, driver = _which(BROWSERS), _which(DRIVERS)
    missing = [what for what, path in (("chromium", browser), ("chromium-driver", driver)) if path is None]
    try:
        import selenium  # noqa: F401
    except ImportError:
        missing.append("selenium (the test extra)")
    if missing:
        reason = f"no {', '.join(missing)}: apt-get install chromium chromium-driver (.ci/run does)"
        if os.environ.get("CI"):
            pytest.fail(f"CI must run the browser test, but finds {reason}")
        pytest.skip(reason)
    assert browser is not None and driver is not None
    return browser, driver


@dataclass(frozen=True)
class PageReport:
    """What the browser showed: console errors (SEVERE entries, uncaught exceptions included),
    whether the plot rendered in time, and the plot's screenshot ``(h, w, 3)`` uint8."""

    errors: tuple[str, ...]
    rendered: bool
    screenshot: np.ndarray

    @property
    def colours(self) -> int:
        """Distinct colours in the screenshot (1: a blank canvas)."""
        return int(np.unique(self.screenshot.reshape(-1, 3), axis=0).shape[0])


# Rendered: plotly has laid the figure out and drawn its WebGL scene (a 3D plot's canvas exists
# and has a size); a 2D plot needs only the layout.
RENDERED = """
const div = document.querySelector('.js-plotly-plot');
if (!div || !div._fullLayout) return false;
const scene = div.querySelector('.gl-container canvas');
return !div._fullLayout.scene || (scene !== null && scene.width > 0 && scene.height > 0);
"""


@contextlib.contextmanager
def chromium(*, window: tuple[int, int] = (1200, 900)) -> Iterator[Any]:
    """A headless Chromium (selenium's driver) with the network cut, quit on exit.

    Skips (fails under CI) without Chromium, its driver or selenium: see :func:`require_chromium`.
    """
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    browser, driver_path = require_chromium()
    options = webdriver.ChromeOptions()
    options.binary_location = browser
    for flag in (
        "--headless=new",
        "--no-sandbox",  # CI runs as root
        "--disable-dev-shm-usage",
        f"--window-size={window[0]},{window[1]}",
        # WebGL without a GPU: SwiftShader, which Chromium now enables only when asked.
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--ignore-gpu-blocklist",
        # Offline: every request leaves through a proxy that does not exist, so a page that
        # fetches anything (a script from a CDN) logs a console error.
        "--proxy-server=http://127.0.0.1:9",
        "--proxy-bypass-list=<-loopback>",
    ):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    os.environ.setdefault("SE_OFFLINE", "true")  # selenium's manager must fetch nothing
    driver = webdriver.Chrome(options=options, service=Service(executable_path=driver_path))
    try:
        yield driver
    finally:
        driver.quit()


def wait_until(driver: Any, script: str, timeout_s: float) -> bool:
    """Whether ``script`` (JavaScript returning a boolean) became true within ``timeout_s``."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if driver.execute_script(script):
            return True
        time.sleep(0.2)
    return False


def open_page(html: Path, *, timeout_s: float = 60.0, settle_s: float = 1.0) -> PageReport:
    """Load ``html`` in headless Chromium with no network and report on it (see :class:`PageReport`)."""
    from PIL import Image
    from selenium.webdriver.common.by import By

    with chromium() as driver:
        # Loading is not rendering: a loaded machine takes seconds to load even a blank page.
        driver.set_page_load_timeout(max(timeout_s, 30.0))
        driver.get(Path(html).resolve().as_uri())
        rendered = wait_until(driver, RENDERED, timeout_s)
        time.sleep(settle_s)  # WebGL draws on the next animation frames
        plots = driver.find_elements(By.CSS_SELECTOR, ".js-plotly-plot")
        png = plots[0].screenshot_as_png if plots else driver.get_screenshot_as_png()
        image = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))
        errors = tuple(str(entry.get("message", "")) for entry in driver.get_log("browser") if entry.get("level") == "SEVERE")
    return PageReport(errors=errors, rendered=rendered, screenshot=image)
