"""Where S''s share facing into the structure comes from, and what would remove it (issue 42).

Four measurements on the families' development seeds (means over the seeds), each on the S' a
mission flies on (``run_mission(..., rng=seed)``'s prior stream, so at 100 known points the
structures experiment's own S'):

``density``
    The default ``oriented`` reconstruction and Open3D's screened Poisson (depth 8; the
    ``reconstruct`` extra) from 100, 1000 and 3000 known points: the share of S''s area facing
    into the structure (``reconstruction_error(...).inward_area_share``), the share of S''s
    volume in the air (outside every real solid; 20 000 uniform points of its bounding box),
    the mean of the two mean distances and H(S->S').
``vote``
    The ``oriented`` reconstruction with other inside votes for its Delaunay tetrahedra (the
    library's: the six nearest known points' tangent planes, closer ones weighing more; the
    nearest point's alone; the generalised winding number of the oriented points, each a disc
    of its six neighbours' area, inside above 1/2), each with and without the fill behind the
    faces the known normals contradict, at 100 and 3000 known points.
``grow``
    The default S' grown outward by 0.5-3 m (each vertex along its area-weighted normal): the
    measure rewards an S' that holds the structure, whatever its distance to it.
``missions``
    The structures experiment's ``cvt3d`` mission (the CVT on S' flown 3 m out, normal weight
    10 m, CAO step 0.5 m, 100 iterations) given the S' of ``oriented`` and of Poisson from 100,
    1000 and 3000 known points: mean initial and best coverage.

::

    nice python benches/structure_inward_sources.py density
    nice python benches/structure_inward_sources.py vote
    nice python benches/structure_inward_sources.py grow
    nice python benches/structure_inward_sources.py missions
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

from uavcov import Terrain
from uavcov.experiments import parse_seeds
from uavcov.structures import STRUCTURE_FAMILIES, _outer_surface, reconstruct_structure, reconstruction_error, sample_structure_prior
from uavcov.structures._structure_prior import _solid_faces

AIR_SAMPLES = 20000
DENSITIES = (100, 1000, 3000)


def _prior(family: str, seed: int, n: int) -> tuple[Any, Any, np.random.Generator]:
    structure = STRUCTURE_FAMILIES[family](rng=seed)
    prior_rng = np.random.default_rng(seed).spawn(3)[0]  # run_mission's prior stream
    return structure, sample_structure_prior(structure, n, rng=prior_rng), prior_rng


def _reconstruct(prior: Any, method: str, prior_rng: np.random.Generator) -> Terrain:
    depth = {"poisson_depth": 8} if method == "poisson" else {}
    # S' through the known points, before its envelope (margin=0): where the inward faces come from.
    return reconstruct_structure(prior, method=method, margin=0.0, rng=prior_rng, **depth)


def measure(structure: Any, approx: Terrain, seed: int) -> np.ndarray:
    """(inward share, air share of S''s volume, mean distance m, H(S->S') m)."""
    error = reconstruction_error(structure, approx, n_samples=4000, rng=seed)
    solid = Terrain(structure.surface.vertices, structure.surface.faces[_solid_faces(structure)])
    box = np.random.default_rng(seed).uniform(approx.bounds[0], approx.bounds[1], size=(AIR_SAMPLES, 3))
    in_approx = approx.inside(box, n_threads=1)
    air = (in_approx & ~solid.inside(box, n_threads=1)).sum() / max(int(in_approx.sum()), 1)
    return np.array([error.inward_area_share, air, error.mean_m, error.hausdorff_truth_to_approx_m])


def _row(label: str, values: dict[str, np.ndarray]) -> str:
    cells = [f"{100 * v[0]:.1f} % / {v[1]:.2f} / {v[2]:.2f} m" for v in values.values()]
    return f"| {label} | " + " | ".join(cells) + " |"


def _header(first: str) -> None:
    print(f"| {first} | " + " | ".join(STRUCTURE_FAMILIES) + " |")
    print("|---|" + "---|" * len(STRUCTURE_FAMILIES))


def density(seeds: list[int]) -> None:
    print("inward / air / mean distance, by method and known points\n")
    _header("S'")
    for method in ("oriented", "poisson"):
        for n in DENSITIES:
            values = {}
            for family in STRUCTURE_FAMILIES:
                rows = []
                for seed in seeds:
                    structure, prior, prior_rng = _prior(family, seed, n)
                    rows.append(measure(structure, _reconstruct(prior, method, prior_rng), seed))
                values[family] = np.mean(rows, axis=0)
            print(_row(f"{method}, {n} points", values), flush=True)


def winding_vote(points: np.ndarray, normals: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """1/2 minus the generalised winding number of the oriented points (negative inside)."""
    spacing, _ = cKDTree(points).query(points, k=7)
    area = np.pi * spacing[:, 6] ** 2 / 6.0  # a disc holding its six neighbours, shared
    vote = np.empty(queries.shape[0])
    for start in range(0, queries.shape[0], 1000):
        offset = points[None] - queries[start : start + 1000, None]
        distance = np.maximum(np.linalg.norm(offset, axis=2), 1e-9)
        winding = (area * np.einsum("qpi,pi->qp", offset, normals) / (4.0 * np.pi * distance**3)).sum(axis=1)
        vote[start : start + 1000] = 0.5 - winding
    return vote


def nearest_vote(points: np.ndarray, normals: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """The nearest known point's tangent plane alone (negative behind it)."""
    _, nearest = cKDTree(points).query(queries)
    return np.asarray(np.einsum("ij,ij->i", queries - points[nearest], normals[nearest]))


def vote(seeds: list[int]) -> None:
    votes: dict[str, Callable[..., np.ndarray]] = {
        "six nearest (library)": _outer_surface.normal_vote,
        "nearest": nearest_vote,
        "winding number": winding_vote,
    }
    library_vote, library_rounds = _outer_surface.normal_vote, _outer_surface._FILL_ROUNDS
    print("inward / air / mean distance, by the inside vote, with and without the fill\n")
    _header("vote")
    try:
        for n in (100, 3000):
            for name, function in votes.items():
                for rounds in (library_rounds, 0):
                    _outer_surface.normal_vote = function
                    _outer_surface._FILL_ROUNDS = rounds
                    values = {}
                    for family in STRUCTURE_FAMILIES:
                        rows = []
                        for seed in seeds:
                            structure, prior, prior_rng = _prior(family, seed, n)
                            rows.append(measure(structure, _reconstruct(prior, "oriented", prior_rng), seed))
                        values[family] = np.mean(rows, axis=0)
                    print(_row(f"{name}, {'fill' if rounds else 'no fill'}, {n} points", values), flush=True)
    finally:
        _outer_surface.normal_vote, _outer_surface._FILL_ROUNDS = library_vote, library_rounds


def grown(surface: Terrain, margin: float) -> Terrain:
    """``surface`` with each vertex moved ``margin`` metres along its area-weighted normal."""
    vertices, faces = surface.vertices, surface.faces
    weighted = surface.face_normals * surface.face_areas[:, None]
    normal = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(normal, faces[:, k], weighted)
    length = np.linalg.norm(normal, axis=1)
    normal[length > 0] /= length[length > 0, None]
    return Terrain(vertices + margin * normal, faces)


def grow(seeds: list[int]) -> None:
    print("inward / air / mean distance of the default S' (100 points) grown outward\n")
    _header("grown by")
    for margin in (0.0, 0.5, 1.0, 2.0, 3.0):
        values = {}
        for family in STRUCTURE_FAMILIES:
            rows = []
            for seed in seeds:
                structure, prior, prior_rng = _prior(family, seed, 100)
                approx = _reconstruct(prior, "oriented", prior_rng)
                rows.append(measure(structure, grown(approx, margin) if margin else approx, seed))
            values[family] = np.mean(rows, axis=0)
        print(_row(f"{margin:g} m", values), flush=True)


def missions(seeds: list[int]) -> None:
    from uavcov.mission import MissionSettings, run_mission
    from uavcov.paper import _structures as experiment_module
    from uavcov.placement import CVTSettings, StartSettings

    experiment = experiment_module.StructuresExperiment()
    print("cvt3d mission on each S': mean initial / best coverage\n")
    _header("S'")
    for method in ("oriented", "poisson"):
        for n in DENSITIES:
            cells = []
            for family in STRUCTURE_FAMILIES:
                outcome = []
                for seed in seeds:
                    structure, prior, prior_rng = _prior(family, seed, n)
                    approx = _reconstruct(prior, method, prior_rng)
                    begin = StartSettings(kind="cvt", altitude=3.0, altitude_reference="normal", climb=0.5)
                    settings = MissionSettings(
                        n_uavs=experiment.n_uavs,
                        d_max=experiment.d_max,
                        n_prior=experiment.n_prior,
                        iterations=experiment.iterations,
                        start=begin,
                        constraints=experiment_module._limits(experiment, structure),
                        cvt=CVTSettings(normal_weight=10.0),
                    )
                    settings = replace(settings, cao=replace(settings.cao, alpha0=0.5))
                    targets = structure.targets(spacing=experiment.target_spacing)
                    result = run_mission(structure, settings, known=approx, targets=targets, rng=seed, n_threads=1)
                    outcome.append((result.initial_coverage, float(result.coverage.max())))
                initial, best = np.mean(outcome, axis=0)
                cells.append(f"{initial:.3f} / {best:.3f}")
            print(f"| {method}, {n} points | " + " | ".join(cells) + " |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("density", "vote", "grow", "missions"))
    parser.add_argument("--seeds", default="1000-1003")
    args = parser.parse_args()
    {"density": density, "vote": vote, "grow": grow, "missions": missions}[args.what](list(parse_seeds(args.seeds)))


if __name__ == "__main__":
    main()
