#!/usr/bin/env python
"""Reconstruction error of S' on every structure scene: the table of docs/structures.md.

For each scene of :data:`uavcov.terrain.STRUCTURE_SCENES` (seed 0), 30, 100 and 300 known points
(:func:`uavcov.terrain.sample_structure_prior`, no noise, with normals, prior seeds 0, 1 and 2) are
turned into S' by every method of :func:`uavcov.terrain.reconstruct_structure` (Open3D's only
when it is installed), and the two coarse models (:func:`uavcov.terrain.coarse_structure_prior`)
are measured too; :func:`uavcov.terrain.reconstruction_error` with 20,000 samples a surface.
Each cell is the median over the three prior seeds. The table replaces the part of
docs/structures.md between its markers (the file is made when missing)::

    python scripts/structure_reconstruction.py            # writes docs/structures.md
    python scripts/structure_reconstruction.py --print    # prints the table only
"""

from __future__ import annotations

import argparse
import importlib.util
import pathlib
import sys

import numpy as np

from uavcov.errors import UavcovError
from uavcov.terrain import (
    STRUCTURE_SCENES,
    coarse_structure_prior,
    reconstruct_structure,
    reconstruction_error,
    sample_structure_prior,
)

BEGIN = "<!-- reconstruction table: made by python scripts/structure_reconstruction.py -->"
END = "<!-- end of reconstruction table -->"
SIZES = (30, 100, 300)
PRIOR_SEEDS = (0, 1, 2)
HEADER = """# Structures

Issue 35: 3D structures (not height fields) and the prior S' made from partial knowledge of them.
Scenes: `uavcov.terrain.STRUCTURE_SCENES`; priors and reconstruction:
`uavcov.terrain.sample_structure_prior`, `coarse_structure_prior`, `reconstruct_structure`,
`reconstruction_error` (see docs/design.md).

"""


def _row(scene: str, structure: object, source: str, method: str, priors: list) -> str:
    errors = []
    for prior in priors:
        try:
            approx = reconstruct_structure(prior, method=method, rng=0)
        except UavcovError as exc:
            return f"| {scene} | {source} | {method} | refused: {exc} | | | |"
        errors.append(reconstruction_error(structure, approx, n_samples=20_000, rng=0))
    med = {name: float(np.median([getattr(e, name) for e in errors])) for name in ("hausdorff_truth_to_approx_m", "hausdorff_approx_to_truth_m", "mean_m", "area_ratio")}
    return (
        f"| {scene} | {source} | {method} | {med['hausdorff_truth_to_approx_m']:.2f} | {med['hausdorff_approx_to_truth_m']:.2f} "
        f"| {med['mean_m']:.2f} | {med['area_ratio']:.2f} |"
    )


def table() -> str:
    methods = ["alpha", "hulls"]
    has_open3d = importlib.util.find_spec("open3d") is not None
    if has_open3d:
        methods += ["poisson", "ball_pivoting"]
    lines = [
        BEGIN,
        "",
        "Reconstruction error of S' against the true structure (ground and contact faces left out), median over "
        f"prior seeds {', '.join(map(str, PRIOR_SEEDS))}; H(S->S') is the farthest a point of the structure is from S' "
        "(what S' misses), H(S'->S) the farthest a point of S' is from the structure (what it invents), mean the mean "
        "of the two mean distances, area the area of S' over the structure's. "
        + ("Open3D's methods were measured (open3d installed)." if has_open3d else "Open3D is not installed: its methods are left out."),
        "",
        "| scene | prior | method | H(S->S') m | H(S'->S) m | mean m | area S'/S |",
        "|---|---|---|---|---|---|---|",
    ]
    for scene, make in STRUCTURE_SCENES.items():
        structure = make(rng=0)
        for n in SIZES:
            priors = [sample_structure_prior(structure, n, rng=seed) for seed in PRIOR_SEEDS]
            for method in methods:
                lines.append(_row(scene, structure, f"{n} points", method, priors))
        for kind in ("boxes", "decimated"):
            lines.append(_row(scene, structure, f"{kind} model", "model", [coarse_structure_prior(structure, kind)]))
    lines += ["", END]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--print", action="store_true", help="print the table instead of writing docs/structures.md")
    parser.add_argument("--out", default=str(pathlib.Path(__file__).resolve().parents[1] / "docs" / "structures.md"))
    args = parser.parse_args(argv)
    text = table()
    if args.print:
        print(text)
        return 0
    path = pathlib.Path(args.out)
    old = path.read_text() if path.exists() else HEADER
    if BEGIN in old and END in old:
        new = old[: old.index(BEGIN)] + text + old[old.index(END) + len(END) :]
    else:
        new = old.rstrip("\n") + "\n\n## Reconstruction of S'\n\n" + text + "\n"
    path.write_text(new)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
