#!/usr/bin/env python
"""Reconstruction error of S' on every structure scene: the table of docs/structures.md.

For each scene of :data:`uavcov.structures.STRUCTURE_SCENES` (seed 0), 30, 100 and 300 known points
(:func:`uavcov.structures.sample_structure_prior`, no noise, with normals, prior seeds 0, 1 and 2) are
turned into S' by every method of :func:`uavcov.structures.reconstruct_structure` (Open3D's only
when it is installed), and the two coarse models (:func:`uavcov.structures.coarse_structure_prior`)
are measured too; :func:`uavcov.structures.reconstruction_error` with 20,000 samples a surface.
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
from uavcov.structures import (
    STRUCTURE_SCENES,
    coarse_structure_prior,
    height_field_violation,
    reconstruct_structure,
    reconstruction_error,
    sample_structure_prior,
)
from uavcov.structures._structure_prior import DEFAULT_METHOD
from uavcov.structures._structures import solid_components

BEGIN = "<!-- reconstruction table: made by python scripts/structure_reconstruction.py -->"
END = "<!-- end of reconstruction table -->"
SIZES = (30, 100, 300)
PRIOR_SEEDS = (0, 1, 2)
HEADER = """# Structures

Issue 35: 3D structures (not height fields) and the prior S' made from partial knowledge of them.
Scenes: `uavcov.structures.STRUCTURE_SCENES`; priors and reconstruction:
`uavcov.structures.sample_structure_prior`, `coarse_structure_prior`, `reconstruct_structure`,
`reconstruction_error` (see docs/design.md).

"""


ENVELOPE = "oriented + envelope"
"""The default S' (``reconstruct_structure``'s envelope around ``oriented``); the other rows are the
surfaces through the points (``margin=0``)."""


def _row(scene: str, structure: object, source: str, method: str, priors: list, means: dict) -> str:
    errors = []
    for prior in priors:
        try:
            if method == ENVELOPE:
                approx = reconstruct_structure(prior, method="oriented", rng=0)
            else:
                approx = reconstruct_structure(prior, method=method, margin=0.0, rng=0)
        except UavcovError as exc:
            return f"| {scene} | {source} | {method} | refused: {exc} | | | | |"
        errors.append(reconstruction_error(structure, approx, n_samples=20_000, rng=0))
    means[(scene, source, method)] = (
        float(np.median([e.mean_m for e in errors])),
        float(np.median([e.hausdorff_truth_to_approx_m for e in errors])),
    )
    med = {
        name: float(np.median([getattr(e, name) for e in errors]))
        for name in ("hausdorff_truth_to_approx_m", "hausdorff_approx_to_truth_m", "mean_m", "area_ratio", "inward_area_share")
    }
    return (
        f"| {scene} | {source} | {method} | {med['hausdorff_truth_to_approx_m']:.2f} | {med['hausdorff_approx_to_truth_m']:.2f} "
        f"| {med['mean_m']:.2f} | {med['area_ratio']:.2f} | {100 * med['inward_area_share']:.1f} % |"
    )


def _scenes_table() -> list[str]:
    lines = [
        (
            "Scenes (seed 0): faces of the whole mesh, parts, and how far each is from a height field "
            "(`height_field_violation`: share of the footprint where a vertical ray meets a downward face above the "
            "lowest surface; share of the visible area facing down)."
        ),
        "",
        "| scene | faces | solids | parts | double-hit share | downward area share |",
        "|---|---|---|---|---|---|",
    ]
    for scene, make in STRUCTURE_SCENES.items():
        structure = make(rng=0)
        double, down = height_field_violation(structure)
        parts = ", ".join(name for name in structure.part_names if name not in ("ground", "contact"))
        solids = len(solid_components(structure))
        lines.append(f"| {scene} | {structure.surface.n_faces} | {solids} | {parts} | {double:.3f} | {down:.3f} |")
    return [*lines, ""]


def _choice(means: dict, methods: list[str]) -> list[str]:
    light = [m for m in methods if m in ("oriented", "alpha", "hulls")]
    cells = sorted({(scene, source) for scene, source, method in means if method in light and "points" in source})
    wins = {m: [0, 0] for m in light}
    for scene, source in cells:
        for which in (0, 1):
            wins[min(light, key=lambda m: means[(scene, source, m)][which])][which] += 1
    summary = ", ".join(f"`{m}` {wins[m][0]} (mean) and {wins[m][1]} (H(S->S'))" for m in light)
    medians = ", ".join(f"`{m}` {np.median([means[(s, src, m)][0] for s, src in cells]):.2f} m" for m in methods)
    return [
        "",
        (
            f"Cells (scene, number of points) won out of {len(cells)} among the dependency-light methods, on the mean "
            f"distance and on what S' misses: {summary}. "
            f"Median over the cells of the mean distance: {medians}. "
            f'`reconstruct_structure(method="auto")` uses `{DEFAULT_METHOD}` for points.'
        ),
        "",
    ]


def table() -> str:
    methods = ["oriented", "alpha", "hulls"]
    has_open3d = importlib.util.find_spec("open3d") is not None
    if has_open3d:
        methods += ["poisson", "ball_pivoting"]
    lines = [
        BEGIN,
        "",
        *_scenes_table(),
        "Reconstruction error of S' against the true structure (ground and contact faces left out), median over "
        f"prior seeds {', '.join(map(str, PRIOR_SEEDS))}; H(S->S') is the farthest a point of the structure is from S' "
        "(what S' misses), H(S'->S) the farthest a point of S' is from the structure (what it invents), mean the mean "
        "of the two mean distances, area the area of S' over the structure's, inward the share of S''s area whose normal "
        "points into a real solid (reconstruction_error.inward_area_share; see the notes). The methods are measured on "
        f"the surfaces through the known points (`margin=0`), and `{ENVELOPE}` is the default S', that surface grown "
        "into an envelope of the structure (below). "
        + ("Open3D's methods were measured (open3d installed)." if has_open3d else "Open3D is not installed: its methods are left out."),
        "",
        "| scene | prior | method | H(S->S') m | H(S'->S) m | mean m | area S'/S | inward |",
        "|---|---|---|---|---|---|---|---|",
    ]
    means: dict = {}
    for scene, make in STRUCTURE_SCENES.items():
        structure = make(rng=0)
        for n in SIZES:
            priors = [sample_structure_prior(structure, n, rng=seed) for seed in PRIOR_SEEDS]
            lines.extend(_row(scene, structure, f"{n} points", method, priors, means) for method in [*methods, ENVELOPE])
        lines.extend(
            _row(scene, structure, f"{kind} model", "model", [coarse_structure_prior(structure, kind)], means)
            for kind in ("boxes", "decimated")
        )
    lines += [*_choice(means, methods), END]
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
