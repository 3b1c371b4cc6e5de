"""How well S' approximates the true surface as the prior grows: the table in docs/approximation.md.

For each of ``--terrains`` Gaussian-hill terrains (the paper's model, seeds 0, 1, ...), draws
``n`` random prior points plus the 4 corners (and the paper's pyramid: corners + centre),
builds S' by Delaunay interpolation and measures the height error of S' over the true surface
(:func:`uavcov.terrain._prior.approximation_error`: 1 m cells, midpoint rule). Prints a Markdown table of
the mean and standard deviation over terrains.

    python benches/approximation_error.py                # 40 terrains, n = 5, 30, 50, 200
    python benches/approximation_error.py --terrains 10 --counts 5 30
"""

from __future__ import annotations

import argparse
import platform
import sys
import time

import numpy as np

from uavcov import gaussian_hills
from uavcov.terrain import approximation_error, sample_prior


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--terrains", type=int, default=40, help="number of terrains (seeds 0..T-1)")
    parser.add_argument("--counts", type=int, nargs="+", default=[5, 30, 50, 200], help="random samples per prior")
    parser.add_argument("--spacing", type=float, default=1.0, help="grid spacing of the true terrains (m)")
    parser.add_argument("--first-seed", type=int, default=0, help="seed of the first terrain")
    args = parser.parse_args(argv)
    if args.terrains < 1 or any(n < 0 for n in args.counts):
        parser.error("--terrains must be >= 1 and --counts >= 0")

    rows = [("pyramid", None)] + [(str(n), n) for n in args.counts]
    rms = np.zeros((len(rows), args.terrains))
    max_abs = np.zeros_like(rms)
    relative = np.zeros_like(rms)
    start = time.perf_counter()
    for t in range(args.terrains):
        seed = args.first_seed + t
        truth = gaussian_hills(spacing=args.spacing, rng=seed)
        relief = float(np.std(truth.grid.z))  # the error of the flat surface at the mean height
        for r, (_, n) in enumerate(rows):
            # Independent draws per (terrain, n): the prior stream is not the terrain's.
            prior = sample_prior(truth, kind="pyramid") if n is None else sample_prior(truth, n=n, rng=np.random.default_rng([seed, n, 1]))
            result = approximation_error(truth, prior.surface())
            rms[r, t] = result.rms
            max_abs[r, t] = result.max_abs
            relative[r, t] = result.rms / relief
    elapsed = time.perf_counter() - start

    print(
        f"Height error of S' over the true surface, {args.terrains} Gaussian-hill terrains "
        f"(seeds {args.first_seed}-{args.first_seed + args.terrains - 1}, 100 m x 100 m, 7 hills, "
        f"heights U[5, 25] m, sigma 10 m, {args.spacing:g} m grid); mean (std) over terrains."
    )
    print()
    print("| prior samples | known points | RMS error (m) | max abs error (m) | RMS / std of true heights |")
    print("|---|---|---|---|---|")
    for r, (label, n) in enumerate(rows):
        known = 5 if n is None else n + 4
        name = "pyramid (corners + centre)" if n is None else f"{label} random + 4 corners"
        print(
            f"| {name} | {known} | {rms[r].mean():.2f} ({rms[r].std():.2f}) | "
            f"{max_abs[r].mean():.2f} ({max_abs[r].std():.2f}) | {relative[r].mean():.3f} ({relative[r].std():.3f}) |"
        )
    print()
    print(f"{elapsed:.1f} s on {platform.machine()}, Python {sys.version.split()[0]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
