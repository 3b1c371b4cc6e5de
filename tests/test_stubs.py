"""The hand-written stub ``python/uavcov/_core.pyi`` must match the compiled extension.

``mypy.stubtest`` imports ``uavcov._core`` and compares every name, signature and type in the
stub with the runtime object; it exits non-zero on any drift (a missing or extra function, a
renamed argument, a wrong default).
"""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

PYTHON_SOURCE = Path(__file__).resolve().parent.parent / "python"


def test_stub_file_and_marker_exist():
    assert (PYTHON_SOURCE / "uavcov" / "_core.pyi").is_file()
    assert (PYTHON_SOURCE / "uavcov" / "py.typed").is_file()


def test_core_stub_matches_extension(tmp_path):
    if importlib.util.find_spec("mypy") is None:
        pytest.skip("mypy is not installed in this environment (it is in the 'test' extra)")
    env = dict(os.environ)
    env["MYPYPATH"] = str(PYTHON_SOURCE)
    env["MYPY_CACHE_DIR"] = str(tmp_path / "mypy_cache")  # keep the work tree clean
    result = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "uavcov._core"],
        capture_output=True,
        text=True,
        env=env,
        cwd=PYTHON_SOURCE.parent,
        timeout=300,
    )
    assert result.returncode == 0, f"stubtest found drift:\n{result.stdout}\n{result.stderr}"
