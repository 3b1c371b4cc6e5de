"""The hand-written stub ``python/uavcov/_core.pyi`` must match the compiled extension.

``mypy.stubtest`` imports ``uavcov._core`` and compares every name, signature and type in the
stub with the runtime object; it exits non-zero on any drift (a missing or extra function, a
renamed argument, a wrong default).
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

PYTHON_SOURCE = Path(__file__).resolve().parent.parent / "python"


def test_stub_file_and_marker_exist():
    assert (PYTHON_SOURCE / "uavcov" / "_core.pyi").is_file()
    assert (PYTHON_SOURCE / "uavcov" / "py.typed").is_file()


def _stubtest(search_path: Path, cache: Path) -> subprocess.CompletedProcess[str]:
    if importlib.util.find_spec("mypy") is None:
        pytest.skip("mypy is not installed in this environment (it is in the 'test' extra)")
    env = dict(os.environ)
    env["MYPYPATH"] = str(search_path)
    env["PYTHONPATH"] = os.pathsep.join([str(search_path), env.get("PYTHONPATH", "")])
    env["MYPY_CACHE_DIR"] = str(cache)  # keep the work tree clean
    return subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "uavcov._core"],
        capture_output=True,
        text=True,
        env=env,
        cwd=cache.parent,
        timeout=300,
        check=False,
    )


@pytest.fixture(scope="module")
def mypy_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    # One cache for both runs: mypy's analysis of numpy dominates the time and is shared.
    return tmp_path_factory.mktemp("stubtest") / "mypy_cache"


def _bare_package(root: Path) -> Path:
    """A copy of the package with an empty ``__init__``, the compiled module in use and the
    source tree's stub: it checks the stub under review against the extension actually built,
    whether that was installed as a wheel (CI) or in place (``maturin develop``)."""
    import uavcov._core

    package = root / "pkg" / "uavcov"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    compiled = Path(uavcov._core.__file__)
    shutil.copy2(compiled, package / compiled.name)
    shutil.copy2(PYTHON_SOURCE / "uavcov" / "_core.pyi", package / "_core.pyi")
    return package


def test_core_stub_matches_extension(tmp_path, mypy_cache):
    package = _bare_package(tmp_path)
    result = _stubtest(package.parent, mypy_cache)
    assert result.returncode == 0, f"stubtest found drift:\n{result.stdout}\n{result.stderr}"


def test_stubtest_detects_drift(tmp_path, mypy_cache):
    # The check above must be able to fail: stubtest also exits 0 when it finds no stub at all,
    # so run it on a copy whose stub declares a function the extension lacks.
    package = _bare_package(tmp_path)
    with open(package / "_core.pyi", "a") as stub:
        stub.write("\ndef not_in_the_extension(x: int) -> int: ...\n")
    result = _stubtest(package.parent, mypy_cache)
    assert result.returncode != 0
    assert "not_in_the_extension" in result.stdout
