#!/usr/bin/env python
"""Choose reconstruct_structure's default by the mission it gives (issue 42), on development seeds.

For each family of :data:`uavcov.structures.STRUCTURE_FAMILIES` and development seed, the same 100
known points (with normals) are turned into S' by each dependency-light method, and the same
``cvt3d`` mission (the experiment's settings, S' given directly) runs on each; the table is the
mean best coverage, the mean number of start points inside the real structure before
``closest_admissible``, and the share of S' facing inward, per method::

    nice python scripts/structure_method_choice.py --seeds 1000-1003 --workers 2
"""

from __future__ import annotations

import argparse
import itertools
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from uavcov import MissionSettings, run_mission
from uavcov.errors import UavcovError
from uavcov.experiments import parse_seeds
from uavcov.paper import StructuresExperiment
from uavcov.paper._structures import _limits
from uavcov.placement import StartSettings
from uavcov.structures import STRUCTURE_FAMILIES, reconstruct_structure, reconstruction_error, sample_structure_prior

METHODS = ("oriented", "alpha", "hulls")


def one(task: tuple[str, int, str, float]) -> tuple[str, int, str, float, float, float]:
    family, seed, method, offset = task
    experiment = StructuresExperiment()
    structure = STRUCTURE_FAMILIES[family](rng=seed)
    prior_rng = np.random.default_rng(seed)
    try:
        surface = reconstruct_structure(sample_structure_prior(structure, experiment.n_prior, rng=prior_rng), method=method, rng=prior_rng)
    except UavcovError:
        return family, seed, method, np.nan, np.nan, np.nan
    settings = MissionSettings(
        n_uavs=experiment.n_uavs,
        d_max=experiment.d_max,
        iterations=experiment.iterations,
        start=StartSettings(kind="cvt", altitude=offset, altitude_reference="normal", climb=0.5),
        constraints=_limits(experiment, structure),
    )
    result = run_mission(
        structure, settings, known=surface, targets=structure.targets(spacing=experiment.target_spacing), rng=seed, n_threads=1
    )
    inside = float(structure.surface.inside(result.start_positions, n_threads=1).sum())
    inward = reconstruction_error(structure, surface, n_samples=4000, rng=seed).inward_area_share
    return family, seed, method, result.best_coverage, inside, inward


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1000-1003")
    parser.add_argument("--offset", type=float, default=3.0)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    tasks = [(f, s, m, args.offset) for f, s, m in itertools.product(STRUCTURE_FAMILIES, parse_seeds(args.seeds), METHODS)]
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(one, tasks))
    print(f"| family | {' | '.join(METHODS)} |  (mean best; starts inside the structure per run; S' facing inward)")
    print("|---|" + "---|" * len(METHODS))
    for family in [*STRUCTURE_FAMILIES, "all"]:
        cells = []
        for method in METHODS:
            mine = [r for r in rows if r[2] == method and (family == "all" or r[0] == family)]
            best, inside, inward = (np.nanmean([r[k] for r in mine]) for k in (3, 4, 5))
            cells.append(f"{best:.3f}; {inside:.2f}; {100 * inward:.1f} %")
        print(f"| {family} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
