"""How far from the known points their vote should keep a 3D start's UAVs out (issue 42).

``fly_out`` flies a generator (or a greedy candidate) farther, or lifts it over S', where its
step lands behind the known points' tangent planes (``StructurePrior.behind``). Far from every
known point that vote extrapolates: on a lattice pylon or under an arch it marked steps 4.6-7.5 m
from the nearest known point, and the CVT start lifted 1-3 of its 8 UAVs over the top. For each
reach (in the known points' spacings, ``StructurePrior.spacing``; ``inf``: the vote everywhere),
the structures experiment's missions with the chosen settings (``cvt3d``: 3 m, normal weight 10
m, CAO step 0.5 m; ``greedy3d``: 4 m, points 4 m apart, step 0.5 m) on development seeds:
mean best coverage per family and over the families, and the start points inside a real solid
before ``closest_admissible``::

    nice python benches/structure_keep_out.py                       # seeds 1000-1007
    nice python benches/structure_keep_out.py --reaches=inf,3 --starts=cvt3d
"""

from __future__ import annotations

import argparse
import functools
from typing import Any

import numpy as np

import uavcov.mission
from uavcov.experiments import parse_seeds
from uavcov.paper import _structures as experiment_module

# The chosen settings of each start (the experiment's report, docs/structures.md).
SETTINGS = {"cvt3d": (3.0, 0.0, 10.0, 0.5), "greedy3d": (4.0, 4.0, 0.0, 0.5)}


def _keep_out_within(spacings: float) -> Any:
    """A stand-in for ``uavcov.mission._keep_out`` giving every start the vote within ``spacings``."""

    def keep_out(known: Any, kind: str) -> Any:
        if known is None or getattr(known, "normals", None) is None:
            return None
        return known.behind if np.isinf(spacings) else functools.partial(known.behind, reach=spacings * known.spacing)

    return keep_out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reaches", default="inf,1,2,3,4,6")
    parser.add_argument("--starts", default="cvt3d,greedy3d")
    parser.add_argument("--seeds", default="1000-1007")
    args = parser.parse_args()
    seeds = parse_seeds(args.seeds)
    experiment = experiment_module.StructuresExperiment()
    library = uavcov.mission._keep_out
    print("| start | reach (spacings) | " + " | ".join(experiment.families) + " | all | starts inside |")
    print("|---|---|" + "---|" * (len(experiment.families) + 2))
    try:
        for start in args.starts.split(","):
            offset, spacing, weight, step = SETTINGS[start]
            for reach in (float(r) for r in args.reaches.split(",")):
                uavcov.mission._keep_out = _keep_out_within(reach)  # type: ignore[assignment]
                best, inside = [], 0
                for family in experiment.families:
                    rows = [experiment_module._mission(experiment, (family, start, seed, offset, spacing, weight, step)) for seed in seeds]
                    best.append(float(np.mean([row["best"] for row in rows])))
                    inside += sum(row["inside_before"] for row in rows)
                cells = " | ".join(f"{b:.3f}" for b in best)
                print(f"| {start} | {reach:g} | {cells} | {np.mean(best):.4f} | {inside} |", flush=True)
    finally:
        uavcov.mission._keep_out = library


if __name__ == "__main__":
    main()
