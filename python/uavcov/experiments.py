"""Deprecated: the sweep machinery now lives along its seams.

=====================================  ==============================================
what                                   where
=====================================  ==============================================
experiments, run specs, executors      :mod:`uavcov.sweep`
runs.csv, config.json, the lock        :mod:`uavcov.results`
Markdown tables, coverage curves       :mod:`uavcov.reports`
the paper's experiments end to end     :mod:`uavcov.jobs` (:func:`~uavcov.jobs.reproduce`)
=====================================  ==============================================

Every name this module had is still importable from it for one release, with a
``DeprecationWarning``.
"""

from __future__ import annotations

import warnings
from typing import Any

_MOVED: dict[str, tuple[str, str]] = {
    "RUN_COLUMNS": ("results", "RUN_COLUMNS"),
    "read_runs": ("results", "read_runs"),
    "RunSpec": ("sweep", "RunSpec"),
    "ExecutionPlan": ("sweep", "ExecutionPlan"),
    "experiment_specs": ("sweep", "experiment_specs"),
    "settings_hash": ("sweep", "settings_hash"),
    "execute_run": ("sweep", "execute_run"),
    "run_specs": ("sweep", "run_specs"),
    "available_cores": ("sweep", "available_cores"),
    "plan_execution": ("sweep", "plan_execution"),
    "local_executor": ("sweep", "local_executor"),
    "dask_executor": ("sweep", "dask_executor"),
    "parse_seeds": ("sweep", "parse_seeds"),
    "reproduce": ("jobs", "reproduce"),
    "REPRODUCIBLE": ("jobs", "REPRODUCIBLE"),
    "summarise": ("reports", "summarise"),
    "table1_markdown": ("reports", "table1_markdown"),
    "pyramid_markdown": ("reports", "pyramid_markdown"),
    "comparison_markdown": ("reports", "comparison_markdown"),
    "buildings_markdown": ("reports", "buildings_markdown"),
    "example_markdown": ("reports", "example_markdown"),
}

__all__ = sorted(_MOVED)  # noqa: PLE0605 (the moved names, each importable through __getattr__)


def __getattr__(name: str) -> Any:
    if name not in _MOVED:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module, attribute = _MOVED[name]
    warnings.warn(f"uavcov.experiments.{name} is deprecated; use uavcov.{module}.{attribute}", DeprecationWarning, stacklevel=2)
    import importlib

    return getattr(importlib.import_module(f"uavcov.{module}"), attribute)
