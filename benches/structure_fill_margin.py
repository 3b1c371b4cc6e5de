"""How strictly the ``oriented`` reconstruction's fill should judge a face of S' (issue 42).

``_fill_against_normals`` fills the tetrahedron behind a face of S' when one of the face's
corners has a known normal pointing against the face (``n_i . n_f < -margin``, margin 0 in the
library: ``_outer_surface._CONTRADICTION_MARGIN``). For each margin, on the families'
development seeds, the S' a mission flies on (``run_mission(..., rng=seed)``'s prior stream):
the share of its area facing into the structure (``reconstruction_error(...).inward_area_share``),
the share of its volume in the air (outside every real solid; 20 000 uniform points of its
bounding box) and H(S->S'), means over the seeds::

    nice python benches/structure_fill_margin.py                       # margins 0, 0.3, 0.6, 0.9
    nice python benches/structure_fill_margin.py --margins=-0.1,-0.25,-0.5
"""

from __future__ import annotations

import argparse

import numpy as np

from uavcov.experiments import parse_seeds
from uavcov.structures import STRUCTURE_FAMILIES, _outer_surface, reconstruct_structure, reconstruction_error, sample_structure_prior

AIR_SAMPLES = 20000


def measure(family: str, seed: int) -> tuple[float, float, float]:
    """(inward share, air share of S''s volume, H(S->S') m) of one structure's S'."""
    structure = STRUCTURE_FAMILIES[family](rng=seed)
    prior_rng = np.random.default_rng(seed).spawn(3)[0]
    # S' through the known points, before its envelope (margin=0): what the fill makes.
    approx = reconstruct_structure(sample_structure_prior(structure, 100, rng=prior_rng), margin=0.0, rng=prior_rng)
    error = reconstruction_error(structure, approx, n_samples=4000, rng=seed)
    box = np.random.default_rng(0).uniform(approx.bounds[0], approx.bounds[1], size=(AIR_SAMPLES, 3))
    in_approx = approx.inside(box, n_threads=1)
    air = float((in_approx & ~structure.surface.inside(box, n_threads=1)).sum() / max(int(in_approx.sum()), 1))
    return error.inward_area_share, air, error.hausdorff_m


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--margins", default="0,0.3,0.6,0.9")
    parser.add_argument("--seeds", default="1000-1003")
    args = parser.parse_args()
    seeds = parse_seeds(args.seeds)
    for margin in (float(m) for m in args.margins.split(",")):
        _outer_surface._CONTRADICTION_MARGIN = margin
        cells = []
        for family in STRUCTURE_FAMILIES:
            inward, air, hausdorff = np.mean([measure(family, seed) for seed in seeds], axis=0)
            cells.append(f"{family} inward {100 * inward:.1f} % air {air:.2f} H {hausdorff:.1f} m")
        print(f"margin {margin:+.2f} | " + " | ".join(cells), flush=True)


if __name__ == "__main__":
    main()
