"""The paper (Renzaglia et al., section V) as data, its reproduction, reports and claims.

The top layer of the library below the plotting and the command line: nothing under it imports
it (``tests/test_layers.py``). Its experiments (:data:`EXPERIMENTS`: :data:`TABLE1`,
:data:`PYRAMID`, :data:`EXAMPLE`, :data:`COMPARISON`, :data:`BUILDINGS`) are
:class:`uavcov.experiments.Experiment` values with every open parameter chosen;
:func:`reproduce` runs one into a results folder beside the published numbers,
:func:`reproduce_all` all of them with the claims of section V-C measured, :func:`ablate` the
ablations; :func:`oracle` is the greedy placement and certified bound of Table 1's scenarios;
:func:`reproduce_structures` the project's own study of structures no one tuned on.
A study of one's own needs only :mod:`uavcov.experiments`.
"""

from __future__ import annotations

from ._claims import PUBLISHED_GAIN, speed
from ._data import (
    ABLATIONS_BY_NAME,
    BUILDINGS,
    COMPARISON,
    EXAMPLE,
    EXPERIMENTS,
    HELD_OUT_SEEDS,
    PUBLISHED_FIG6_MAX,
    PUBLISHED_PYRAMID,
    PUBLISHED_TABLE1,
    PYRAMID,
    TABLE1,
    PublishedValue,
)
from ._jobs import ablate, reproduce, reproduce_all
from ._oracle import OracleRow, oracle
from ._realistic import reproduce_flown_table1, reproduce_realistic
from ._realistic_report import write_realistic_report
from ._structures import StructuresExperiment, reproduce_structures

__all__ = [
    "reproduce",
    "reproduce_all",
    "ablate",
    "EXPERIMENTS",
    "TABLE1",
    "PYRAMID",
    "EXAMPLE",
    "COMPARISON",
    "BUILDINGS",
    "ABLATIONS_BY_NAME",
    "HELD_OUT_SEEDS",
    "PublishedValue",
    "PUBLISHED_TABLE1",
    "PUBLISHED_PYRAMID",
    "PUBLISHED_FIG6_MAX",
    "PUBLISHED_GAIN",
    "speed",
    "oracle",
    "OracleRow",
    "StructuresExperiment",
    "reproduce_structures",
    "reproduce_realistic",
    "reproduce_flown_table1",
    "write_realistic_report",
]
