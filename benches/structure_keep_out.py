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
    nice python benches/structure_keep_out.py --starts-only           # what the vote does to the starts
    nice python benches/structure_keep_out.py --zoo                   # the same on tests/shape_zoo.py

``--starts-only`` flies the CVT start's generators out (``fly_out`` as the mission does, 3 m)
on the pylon and the arch bridge (development seeds 1000-1005, normal weight 10 m) and on report
seed 5's building (the paper's CVT, the case that chose 4 spacings over 3), for each reach: the
UAVs lifted over S', the start points inside the real structure, and how far (in spacings) the
steps the vote marked are from the nearest known point. ``--zoo`` counts, over the 23 kinds of
tests/shape_zoo.py (seeds 0-4, on a ground sheet as a user hands them over; the CVT start 3 m
out with normal weight 10 m and 6 m out without), the start points inside the real structure
and the UAVs lifted over S', for the vote everywhere and within 4 spacings.
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


def starts_only(reaches: list[float]) -> None:
    from scipy.spatial import cKDTree

    from uavcov.cover import surface_normals
    from uavcov.placement import CVTSettings, cvt
    from uavcov.placement._starts3d import facing_directions, fly_out
    from uavcov.structures import reconstruct_structure, sample_structure_prior

    experiment = experiment_module.StructuresExperiment()
    cases = [(f, s, 10.0) for f in ("pylon", "arch_bridge") for s in range(1000, 1006)] + [("building", 5, 0.0)]
    print("| family | seed | normal weight | reach (spacings) | lifted | inside the structure | marked steps (spacings away) |")
    print("|---|---|---|---|---|---|---|")
    for family, seed, weight in cases:
        structure = experiment_module._structure(experiment, family, seed)
        prior_rng, start_rng, _ = np.random.default_rng(seed).spawn(3)  # run_mission's streams
        prior = sample_structure_prior(structure, experiment.n_prior, rng=prior_rng)
        approx = reconstruct_structure(prior, margin=0.0, rng=prior_rng)
        settings = CVTSettings(normal_weight=weight)
        tessellation = cvt(approx, experiment.n_uavs, settings, rng=start_rng, n_threads=1)
        anchors, normals = surface_normals(approx, tessellation.generators)
        normals = facing_directions(tessellation, normals, settings)
        floor = float(structure.surface.bounds[0, 2])
        for reach in reaches:
            keep_out = prior.behind if np.isinf(reach) else functools.partial(prior.behind, reach=reach * prior.spacing)
            positions, lifted = fly_out(approx, anchors, normals, 3.0, floor=floor, keep_out=keep_out, n_threads=1)
            inside = int(structure.surface.inside(positions, n_threads=1).sum())
            steps = anchors[None] + np.array([1.0, 1.5, 2.0, 3.0, 4.0])[:, None, None] * 3.0 * normals[None]
            steps = steps.reshape(-1, 3)
            steps[:, 2] = np.maximum(steps[:, 2], floor + 3.0)
            marked = steps[keep_out(steps) & ~approx.inside(steps, n_threads=1)]
            far = cKDTree(prior.points).query(marked)[0] / prior.spacing if marked.shape[0] else np.empty(0)
            span = f"{far.min():.1f}-{far.max():.1f} ({far.size})" if far.size else "-"
            print(f"| {family} | {seed} | {weight:g} | {reach:g} | {int(lifted.sum())} | {inside} | {span} |", flush=True)


def zoo() -> None:
    import sys
    from pathlib import Path

    from uavcov.cover import surface_normals
    from uavcov.errors import UavcovError
    from uavcov.placement import CVTSettings, cvt
    from uavcov.placement._starts3d import facing_directions, fly_out
    from uavcov.structures import reconstruct_structure, sample_structure_prior

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
    import shape_zoo  # type: ignore[import-not-found]

    inside = {"inf": 0, "4": 0}
    lifted = {"inf": 0, "4": 0}
    starts = 0
    for kind in shape_zoo.KINDS:
        for seed in range(5):
            try:
                structure = shape_zoo.as_structure(shape_zoo.make(kind, seed))
            except UavcovError:
                continue  # a clear refusal (a model wound inside out, zero-area faces)
            for weight, offset in ((10.0, 3.0), (0.0, 6.0)):
                prior_rng, start_rng, _ = np.random.default_rng(seed).spawn(3)
                prior = sample_structure_prior(structure, 100, rng=prior_rng)
                approx = reconstruct_structure(prior, margin=0.0, rng=prior_rng)
                settings = CVTSettings(normal_weight=weight)
                tessellation = cvt(approx, 8, settings, rng=start_rng, n_threads=1)
                anchors, normals = surface_normals(approx, tessellation.generators)
                normals = facing_directions(tessellation, normals, settings)
                floor = float(structure.surface.bounds[0, 2])
                starts += anchors.shape[0]
                for key, keep_out in (("inf", prior.behind), ("4", functools.partial(prior.behind, reach=4.0 * prior.spacing))):
                    positions, up = fly_out(approx, anchors, normals, offset, floor=floor, keep_out=keep_out, n_threads=1)
                    inside[key] += int(structure.surface.inside(positions, n_threads=1).sum())
                    lifted[key] += int(up.sum())
    print(f"{starts} start points; inside the structure: vote everywhere {inside['inf']}, within 4 spacings {inside['4']};")
    print(f"lifted over S': vote everywhere {lifted['inf']}, within 4 spacings {lifted['4']}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reaches", default="inf,1,2,3,4,6")
    parser.add_argument("--starts", default="cvt3d,greedy3d")
    parser.add_argument("--seeds", default="1000-1007")
    parser.add_argument("--starts-only", action="store_true")
    parser.add_argument("--zoo", action="store_true")
    args = parser.parse_args()
    if args.zoo:
        zoo()
        return
    if args.starts_only:
        starts_only([float(r) for r in args.reaches.split(",")])
        return
    seeds = parse_seeds(args.seeds)
    experiment = experiment_module.StructuresExperiment()
    # The reach was chosen on S' through the known points, before its envelope (margin=0).
    uavcov.mission.reconstruct_structure = functools.partial(uavcov.mission.reconstruct_structure, margin=0.0)  # type: ignore[attr-defined]
    library = uavcov.mission._keep_out
    print("| start | reach (spacings) | " + " | ".join(experiment.families) + " | all | starts inside |")
    print("|---|---|" + "---|" * (len(experiment.families) + 2))
    try:
        for start in args.starts.split(","):
            offset, spacing, weight, step = SETTINGS[start]
            for reach in (float(r) for r in args.reaches.split(",")):
                uavcov.mission._keep_out = _keep_out_within(reach)
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
