"""How far S' is grown into an envelope of the structure (issue 42): ``ENVELOPE_GAPS``.

A surface through 100 known points lies inside the structure wherever it bulges between them,
and there S' faces into it. ``reconstruct_structure`` grows S' outward by a margin, a multiple
of the mean gap between the known points on S' (``sqrt(area / n)``). For each multiple (0: the
surface through the points), on development seeds, per family of ``STRUCTURE_FAMILIES``:

- the share of S''s area facing into the structure (``reconstruction_error(...).inward_area_share``,
  the experiment's measure: 4000 points, mean and largest over the seeds);
- the structures experiment's ``cvt3d`` mission flown from that S' (normal weight 10 m, CAO step
  0.5 m, 100 iterations) at offsets 2.5 and 3 m from S': mean best coverage.

The default is the least multiple whose share is under 1 % on every family::

    nice python benches/structure_envelope.py                   # seeds 1000-1007, 2 processes
    nice python benches/structure_envelope.py --gaps=0,0.75 --seeds=1000-1003
"""

from __future__ import annotations

import argparse
import functools
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

import uavcov.mission
from uavcov.experiments import parse_seeds
from uavcov.paper import _structures as experiment_module
from uavcov.structures import STRUCTURE_FAMILIES, reconstruct_structure

OFFSETS = (2.5, 3.0)
WEIGHT, STEP = 10.0, 0.5


def _grown_by(gaps: float, prior: Any, *, rng: Any = None) -> Any:
    """``reconstruct_structure`` with the margin ``gaps`` mean gaps (a stand-in for the mission's)."""
    surface = reconstruct_structure(prior, margin=0.0, rng=rng)
    return reconstruct_structure(prior, margin=gaps * float(np.sqrt(surface.area / prior.points.shape[0])), rng=rng)


def _run(task: tuple[float, str, int, float]) -> tuple[float, str, int, float, float, float]:
    gaps, family, seed, offset = task
    uavcov.mission.reconstruct_structure = functools.partial(_grown_by, gaps)  # type: ignore[attr-defined]
    row = experiment_module.run_task(experiment_module.StructuresExperiment(), (family, "cvt3d", seed, offset, 0.0, WEIGHT, STEP))
    if row["error"]:
        raise RuntimeError(row["error"])
    return gaps, family, seed, offset, float(row["best"]), float(row["inward_share"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gaps", default="0,0.5,0.6,0.75,0.9,1")
    parser.add_argument("--seeds", default="1000-1007")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    multiples = [float(g) for g in args.gaps.split(",")]
    tasks = [(g, f, s, o) for g in multiples for f in STRUCTURE_FAMILIES for s in parse_seeds(args.seeds) for o in OFFSETS]
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(_run, tasks))
    print("S' grown by k mean gaps: share facing inward per family (mean / largest), cvt3d mean best at 2.5 m / 3 m\n")
    print("| k | " + " | ".join(STRUCTURE_FAMILIES) + " | mean best 2.5 m / 3 m |")
    print("|---|" + "---|" * (len(STRUCTURE_FAMILIES) + 1))
    for gaps in multiples:
        mine = [r for r in rows if r[0] == gaps]
        cells = []
        for family in STRUCTURE_FAMILIES:
            share = [r[5] for r in mine if r[1] == family and r[3] == OFFSETS[0]]
            cells.append(f"{100 * np.mean(share):.2f} % / {100 * np.max(share):.2f} %")
        best = [np.mean([r[4] for r in mine if r[3] == offset]) for offset in OFFSETS]
        print(f"| {gaps:g} | " + " | ".join(cells) + f" | {best[0]:.4f} / {best[1]:.4f} |", flush=True)


if __name__ == "__main__":
    main()
