"""Rows of a long experiment, one JSON line each, appended as runs finish: a kill loses at most
the run in flight (a torn last line, dropped on reading), so a resumed experiment skips every
finished run and its rows equal an uninterrupted run's."""

from __future__ import annotations

import json
import os
from collections.abc import Collection
from pathlib import Path
from typing import Any

from ..errors import ResultsFormatError

__all__ = ["append_row", "read_rows"]


def read_rows(path: Path, keys: Collection[str] = ()) -> list[dict[str, Any]]:
    """Every complete row of ``path`` (none when it does not exist), each an object with ``keys``.

    Raises
    ------
    ResultsFormatError
        A complete line that is JSON but not an object with ``keys`` (a file of another kind, not
        a torn row).
    """
    rows = []
    if path.exists() and not path.is_file():  # a FIFO would block the read forever, a device never end it
        raise ResultsFormatError(f"{path} is not a regular file (a folder, FIFO or device): no rows of a run")
    if path.exists():
        for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), start=1):
            try:
                row = json.loads(line)
            except (json.JSONDecodeError, RecursionError):
                continue  # a line torn by a kill mid-write: that run runs again
            if not isinstance(row, dict) or not set(keys) <= row.keys():
                what = f"a JSON object with {', '.join(keys)}" if keys else "a JSON object"
                raise ResultsFormatError(f"{path} holds a row that is not {what} (line {number}): {line[:120]}")
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
