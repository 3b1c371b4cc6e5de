"""Rows of a long experiment, one JSON line each, appended as runs finish: a kill loses at most
the run in flight (a torn last line, dropped on reading), so a resumed experiment skips every
finished run and its rows equal an uninterrupted run's."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from ..errors import ResultsFormatError

__all__ = ["append_row", "read_rows"]


def read_rows(path: Path) -> list[dict[str, Any]]:
    """Every complete row of ``path`` (none when it does not exist)."""
    rows = []
    if path.exists():
        for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), start=1):
            try:
                row = json.loads(line)
            except json.JSONDecodeError:
                continue  # a line torn by a kill mid-write: that run runs again
            if not isinstance(row, dict):  # a torn row starts with "{" and never parses: this is not one
                raise ResultsFormatError(f"{path}, line {number}: a row is a JSON object, got {type(row).__name__}")
            rows.append(row)
    return rows


def append_row(path: Path, row: dict[str, Any]) -> None:
    """Append ``row`` as one line, on disk before returning (after a line torn by a kill, on a line
    of its own: the torn one stays unreadable, this one is read)."""
    torn = False
    if path.exists() and path.stat().st_size:
        with path.open("rb") as tail:
            tail.seek(-1, os.SEEK_END)
            torn = tail.read(1) != b"\n"
    with path.open("a", encoding="utf-8") as handle:
        handle.write(("\n" if torn else "") + json.dumps(row, sort_keys=True) + "\n")
        handle.flush()
        os.fsync(handle.fileno())
