"""The smallest paper experiment the sweep, results-folder and command-line tests run.

A 40 m terrain meshed every 4 m, 2-3 UAVs, 8 known points, 20 CAO candidates and a short CVT: a
run takes a few milliseconds, so the tests can run dozens of them, on pools and through the CLI.
"""

from __future__ import annotations

from typing import Any

from uavcov.experiments import Experiment
from uavcov.paper import _data as paper

TINY_TOML = """
name = "tiny"
seeds = [0, 1]
team_sizes = [2]
starts = ["cvt", "corner"]
d_max = 12.0
n_prior = 8
iterations = {iterations}

[terrain]
size = 40.0
spacing = 4.0
heights = [2.0, 8.0]
sigma = 6.0

[cao]
n_candidates = 20

[cvt]
samples_per_iteration = 400
max_iterations = 20
"""
"""A sweep file of the tiny experiment; ``.format(iterations=K)`` fills in the CAO iterations."""


def tiny_experiment(iterations: int = 2, **changes: Any) -> Experiment:
    """Table 1's experiment on the tiny terrain (``changes`` as in ``Experiment.with_changes``)."""
    return paper.TABLE1.with_changes(
        **{
            "terrain.size": 40.0,
            "terrain.spacing": 4.0,
            "terrain.heights": (2.0, 8.0),
            "terrain.sigma": 6.0,
            "d_max": 12.0,
            "n_prior": 8,
            "iterations": iterations,
            "cao.n_candidates": 20,
            "cvt.max_iterations": 20,
            "cvt.samples_per_iteration": 400,
            **changes,
        }
    )
