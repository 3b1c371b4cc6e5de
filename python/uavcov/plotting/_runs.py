"""Rows of a ``runs.csv``: reading the file, and reading a number out of a row's cell.

:func:`_read_runs` is the only code of the package that opens a ``runs.csv``
(:func:`~uavcov.plotting.plot_table1` given a path, :func:`~uavcov.plotting.plot_directory`).
Everything else takes rows as mappings whose cells are either strings, as the ``csv`` module
gives them (``"0.93"``, ``""`` for a failed run), or values already parsed (``0.93``, ``12``,
``None``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from ..errors import ResultsFormatError
from ..experiments import read_runs

RUNS_COLUMNS = ("experiment", "init", "n_uavs", "max_coverage")
"""Columns the figures need in a ``runs.csv``: the experiment, the start, the team size and the
best coverage (the bars of Table 1 and the grouping of the curves)."""


def _read_runs(path: Any) -> list[dict[str, Any]]:
    """The rows of the ``runs.csv`` at ``path`` (:func:`uavcov.experiments.read_runs`), header checked.

    Raises
    ------
    ResultsFormatError
        No such file, not a runs file, or a column of :data:`RUNS_COLUMNS` missing (named).
    """
    return read_runs(path, required=RUNS_COLUMNS)


def _number(row: Mapping[str, Any], column: str, index: int) -> float | None:
    """The row's value in ``column`` as a float, or None when the run has none (it failed).

    A cell may be a string (``""``, ``"nan"`` or ``"none"`` mean no value) or already a number
    or ``None``; NaN and infinities also mean no value. ``index`` names the row in errors.

    Raises
    ------
    ResultsFormatError
        The row has no such column, or its cell is neither empty nor a number.
    """
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
