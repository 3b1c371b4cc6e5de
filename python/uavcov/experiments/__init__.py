"""Specs x seeds on an executor into a results folder: what any study of uavcov runs with.

An :class:`Experiment` (a scenario generator or a surface of your own, a
:class:`~uavcov.mission.MissionSettings`, team sizes, starts and seeds) lists its runs
(:func:`experiment_specs`); :func:`run_specs` runs them on an executor (:func:`plan_execution`)
into a :class:`ResultsFolder` that a later call resumes; a sweep file (:class:`SweepConfig`)
runs with :func:`run_sweep`. The paper's experiments are in
:mod:`uavcov.paper`.
"""

from __future__ import annotations

from ._executors import ExecutionPlan, available_cores, dask_executor, local_executor, plan_execution
from ._results import ResultsFolder, read_runs
from ._run_options import check_run_options
from ._summary import finished_rows, row_number, run_sweep, summarise
from ._sweep import Experiment, RunSpec, experiment_specs, experiments_hash, run_specs
from ._sweep_config import STARTS, SweepConfig, load_sweep_config, parse_seeds, parse_sweep_config

__all__ = [
    "Experiment",
    "RunSpec",
    "experiment_specs",
    "run_specs",
    "check_run_options",
    "experiments_hash",
    "parse_seeds",
    "ExecutionPlan",
    "available_cores",
    "plan_execution",
    "local_executor",
    "dask_executor",
    "ResultsFolder",
    "read_runs",
    "summarise",
    "finished_rows",
    "row_number",
    "SweepConfig",
    "load_sweep_config",
    "parse_sweep_config",
    "run_sweep",
    "STARTS",
]
