"""Rows of a ``runs.csv``: reading the file, and the cells the figures use.

:func:`_read_runs` is the one place that reads the file. The rest accepts rows whose cells are
strings as the ``csv`` module gives them (``"0.93"``, ``""``) or values already parsed
(``0.93``, ``None``), so the reader can change without touching the figures.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..errors import ResultsFormatError


def _read_runs(path: Any) -> list[dict[str, str]]:
    """Rows of a ``runs.csv`` as dicts of strings (the ``csv`` module's), header checked.

    Raises
    ------
    ResultsFormatError
        No such file, no header, or a required column missing (named).
    """
    path = Path(path)
    if not path.is_file():
        raise ResultsFormatError(f"no runs file at {path}")
    with path.open(newline="") as handle:
        reader = csv.DictReader(handle)
        if reader.fieldnames is None:
            raise ResultsFormatError(f"{path} is empty (no header line)")
        missing = [c for c in ("experiment", "init", "n_uavs", "max_coverage") if c not in reader.fieldnames]
        if missing:
            raise ResultsFormatError(f"{path} lacks the column(s) {', '.join(missing)}")
        return list(reader)


def _number(row: Mapping[str, Any], column: str, index: int) -> float | None:
    """The row's value, or None when the run failed (empty, "nan")."""
    if column not in row:
        raise ResultsFormatError(f"row {index} of the runs has no {column!r} column")
    raw = row[column]
    if raw is None or (isinstance(raw, str) and raw.strip().lower() in ("", "nan", "none")):
        return None
    try:
        value = float(raw)
    except (TypeError, ValueError) as exc:
        raise ResultsFormatError(f"row {index}: {column} = {raw!r} is not a number") from exc
    return value if math.isfinite(value) else None
