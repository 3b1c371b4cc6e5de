"""The options and records of a run of specs, checked before any folder is made.

:func:`check_run_options` checks the flags and records :func:`~uavcov.experiments.run_specs`
takes (a job calls it first: it makes its folder before it runs the specs), ``as_extra`` a
spec's extra columns. What ``config.json`` records must be JSON: checked here, not when written.
"""

from __future__ import annotations

import concurrent.futures as cf
import json
from collections.abc import Mapping
from typing import Any

from .._validate import as_bool, as_optional_str, as_tuple
from ..errors import InvalidInputError, InvalidTypeError
from ._executors import ExecutionPlan, plan_execution
from ._results import json_default


def _check_json_record(record: Mapping[Any, Any], name: str) -> None:
    """``record`` has string keys and JSON values (``config.json`` records it), else a uavcov error naming ``name``."""
    if any(not isinstance(key, str) or not key for key in record):
        raise InvalidTypeError(f"{name} must have non-empty string keys, got {list(record)!r}")
    try:
        json.dumps(record, default=json_default, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise InvalidTypeError(f"{name} must hold JSON values (it is recorded in config.json): {exc}") from exc


def as_extra(extra: Any) -> tuple[tuple[str, Any], ...]:
    """A spec's ``extra`` as ``((column, value), ...)``: columns of runs.csv, each named once."""
    pairs = as_tuple(extra, "extra")
    if any(not isinstance(pair, (tuple, list)) or len(pair) != 2 for pair in pairs):
        raise InvalidTypeError(f"extra must hold (column, value) pairs, got {extra!r}")
    keys = [key for key, _ in pairs]
    if any(not isinstance(key, str) or not key for key in keys):
        raise InvalidTypeError(f"extra must name its columns with non-empty strings, got {keys!r}")
    if len(set(keys)) != len(keys):
        raise InvalidInputError(f"extra names a column more than once: {keys}")
    _check_json_record(dict(pairs), "extra")
    return tuple((key, value) for key, value in pairs)


def check_run_options(
    *, resume: Any, save_runs: Any, exclusive: Any, progress: Any, command: Any, execution: Any
) -> tuple[bool, bool, bool, bool | None, str | None, dict[str, Any]]:
    """The flags and records of :func:`~uavcov.experiments.run_specs`, checked: a job calls it before it makes a folder.

    Returns
    -------
    tuple
        ``(resume, save_runs, exclusive, progress, command, execution)``: three bools, a bool or
        None, a string or None, and ``execution`` as a dict ``config.json`` can hold.

    Raises
    ------
    InvalidTypeError
        A flag not True or False, a command not a string, an ``execution`` not a mapping with
        string keys and JSON values.
    """
    flags = [as_bool(value, name) for name, value in (("resume", resume), ("save_runs", save_runs), ("exclusive", exclusive))]
    shown = None if progress is None else as_bool(progress, "progress")
    text = as_optional_str(command, "command")
    return flags[0], flags[1], flags[2], shown, text, as_json_record(execution, "execution")


def as_json_record(value: Any, name: str) -> dict[str, Any]:
    """``value`` (None or a mapping of strings to JSON values) as a dict ``config.json`` can hold.

    Checked before anything is run or written: NaN or inf would be written as ``NaN`` or
    ``Infinity``, which no strict JSON reader reads back; a set or bytes would fail the write.
    """
    if value is not None and not isinstance(value, Mapping):
        raise InvalidTypeError(f"{name} must be None or a mapping, got {type(value).__name__}")
    record = dict(value or {})
    _check_json_record(record, name)
    return record


def checked_execution(executor: Any, workers: Any, n_threads: Any, on_result: Any, about: Any) -> tuple[ExecutionPlan, dict[str, Any]]:
    """:func:`~uavcov.experiments.run_specs`' executor, counts, callback and ``about``, checked before any folder is made.

    Returns the execution plan (with an ``executor``, ``workers`` and ``n_threads`` are only
    recorded: 0 is refused, not read as "unset") and ``about`` as a dict ``config.json`` can hold.
    """
    if executor is not None and not isinstance(executor, cf.Executor):
        raise InvalidTypeError(f"executor must be a concurrent.futures.Executor (or None), got {type(executor).__name__}")
    if on_result is not None and not callable(on_result):
        raise InvalidTypeError(f"on_result must be None or a function of (spec, row, result), got {type(on_result).__name__}")
    record = as_json_record(about, "about")
    if executor is None:
        return plan_execution(workers, n_threads), record
    return ExecutionPlan(1 if workers is None else workers, 1 if n_threads is None else n_threads), record
