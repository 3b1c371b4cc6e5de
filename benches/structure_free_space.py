"""Free-space carving of S' (issue 42), measured against ``oriented`` on the development seeds.

A known point ``p`` with outward normal ``n`` was seen from outside, so the segment ``p + t n``
in front of it is air until it meets another surface. Two ways to use that evidence on the
Delaunay tetrahedra of the 100 known points, each marking tetrahedra *free* (never inside, and
not grown into by the fill of ``oriented_solid``, :func:`uavcov.structures._outer_surface.oriented_labels`):

``rays``
    Each point's segment, sampled every quarter of the median nearest-neighbour spacing, marks
    the tetrahedra it crosses, until it leaves the hull or passes the tangent plane of a corner
    of its tetrahedron that lies ahead along it and faces back against it (a surface it meets).
``open``
    A tetrahedron every corner of which sees the other three on or in front of its tangent
    plane (within 0.05 of their distance), one strictly: the air in a concave corner or between
    two facing parts, by its corners alone.
``rays_blocked``
    ``rays``, but a crossed tetrahedron that ``oriented`` puts inside stays inside: the segments
    only keep the others out of the fill.
``hull``
    Not a carving: the known points' convex hull (a reference: ``oriented`` at 100 points is
    nearly it, 97-100 % of its volume, ``scripts/structure_inward.py``).
``lifted<d>``
    Not a carving either: ``oriented`` on the known points moved ``d`` metres out along their
    normals (``lifted0.5``), S' a little outside the structure's samples.

Per family, mean over the seeds: the share of S' facing into the structure
(``reconstruction_error(..., n_samples=4000, rng=seed).inward_area_share``), what S' misses
(H(S->S')), the mean distance, and the mean best coverage of the experiment's ``cvt3d`` and
``greedy3d`` missions, each run as the experiment runs it (``uavcov.paper._structures.run_task``,
the missions' own prior stream) with S' made by the variant: at the settings
``uavcov reproduce structures`` chose on these seeds for ``oriented`` (``cvt3d`` 4 m out,
``greedy3d`` 2.5 m out with points 4 m apart), or with ``--all-settings`` at every offset and
spacing it chooses from, the variant's own choice by the experiment's rule (the best mean over
the families) reported::

    nice python benches/structure_free_space.py [--seeds 1000-1003] [--variants oriented,rays,open,rays_blocked,hull]
    nice python benches/structure_free_space.py --all-settings --variants oriented,lifted0.5,lifted1,open
    nice python benches/structure_free_space.py --no-missions   # S' only: how much of the share faces in squarely
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

import uavcov.mission
from uavcov import Terrain
from uavcov.experiments import parse_seeds
from uavcov.paper import StructuresExperiment
from uavcov.paper._structures import _settings, run_task
from uavcov.structures import STRUCTURE_FAMILIES, StructurePrior, reconstruct_structure, reconstruction_error, sample_structure_prior
from uavcov.structures._facing import facing_into
from uavcov.structures._outer_surface import _boundary, oriented_labels
from uavcov.structures._structure_prior import _sample_faces, _solid_faces

Mission = tuple[str, float, float]
"""(start, offset from S' in m, greedy3d's spacing in m or 0)."""
STEP_SHARE = 0.25
OPEN_SLACK = 0.05
MISSIONS: tuple[Mission, ...] = (("cvt3d", 4.0, 0.0), ("greedy3d", 2.5, 4.0))


def ray_free(points: np.ndarray, normals: np.ndarray, triangulation: Any) -> np.ndarray:
    """Tetrahedra crossed by a known point's outward segment before it meets a surface."""
    from scipy.spatial import cKDTree

    tetra = triangulation.simplices
    spacing, _ = cKDTree(points).query(points, k=2)
    step = max(float(np.median(spacing[:, 1])) * STEP_SHARE, 1e-9)
    length = float(np.linalg.norm(np.ptp(points, axis=0)))
    t = np.arange(0.5 * step, length + step, step)
    samples = points[:, None, :] + t[None, :, None] * normals[:, None, :]
    where = triangulation.find_simplex(samples.reshape(-1, 3)).reshape(samples.shape[:2])
    corners = tetra[np.maximum(where, 0)]
    corner_points, corner_normals = points[corners], normals[corners]
    ray = np.broadcast_to(normals[:, None, None, :], corner_points.shape)
    ahead = np.einsum("nskj,nskj->nsk", corner_points - points[:, None, None, :], ray) > 0
    facing = np.einsum("nskj,nskj->nsk", corner_normals, ray) < 0
    past = np.einsum("nskj,nskj->nsk", samples[:, :, None, :] - corner_points, corner_normals) < 0
    blocked = (ahead & facing & past).any(axis=2) | (where < 0)
    stop = np.where(blocked.any(axis=1), np.argmax(blocked, axis=1), t.size)
    free = np.zeros(tetra.shape[0], dtype=bool)
    free[where[np.arange(t.size)[None, :] < stop[:, None]]] = True
    return free


def open_free(points: np.ndarray, normals: np.ndarray, tetra: np.ndarray) -> np.ndarray:
    """Tetrahedra every corner of which sees the others on or in front of its tangent plane."""
    p, m = points[tetra], normals[tetra]
    offset = p[:, None, :, :] - p[:, :, None, :]
    height = np.einsum("tijk,tik->tij", offset, m)
    length = np.linalg.norm(offset, axis=3)
    free: np.ndarray = (height >= -OPEN_SLACK * length).all(axis=(1, 2)) & (height > OPEN_SLACK * length).any(axis=(1, 2))
    return free


def carved(prior: StructurePrior, variant: str) -> Terrain:
    """S' of ``oriented`` with the variant's free tetrahedra carved out."""
    from scipy.spatial import Delaunay

    assert prior.normals is not None
    points, first = np.unique(prior.points, axis=0, return_index=True)
    normals = prior.normals[first] / np.linalg.norm(prior.normals[first], axis=1)[:, None]
    triangulation = Delaunay(points)
    tetra, neighbours = triangulation.simplices, triangulation.neighbors
    free = open_free(points, normals, tetra) if variant == "open" else ray_free(points, normals, triangulation)
    if variant == "rays_blocked":
        solid = oriented_labels(points, normals, tetra, neighbours, free)
        vote_only = oriented_labels(points, normals, tetra, neighbours)
        solid |= vote_only & free
    else:
        solid = oriented_labels(points, normals, tetra, neighbours, free)
    return Terrain(points, _boundary(points, tetra, neighbours, solid), drop_degenerate=True)


def convex_hull(prior: StructurePrior) -> Terrain:
    """The known points' convex hull, wound outward: no concavity, so no face of it in the air can
    point into a real part the points span (the supporting plane has them behind it)."""
    from scipy.spatial import ConvexHull

    points = np.unique(prior.points, axis=0)
    hull = ConvexHull(points)
    faces = hull.simplices.copy()
    normal = np.cross(points[faces[:, 1]] - points[faces[:, 0]], points[faces[:, 2]] - points[faces[:, 0]])
    inward = np.einsum("ij,ij->i", normal, hull.equations[:, :3]) < 0
    faces[inward] = faces[inward][:, ::-1]
    return Terrain(points, faces, drop_degenerate=True)


def surface_maker(variant: str) -> Any:
    def make(prior: StructurePrior, **kwargs: Any) -> Terrain:
        if variant == "hull":
            return convex_hull(prior)
        if variant.startswith("lifted"):
            # Each known point moved out along its normal before the reconstruction.
            assert prior.normals is not None
            unit = prior.normals / np.linalg.norm(prior.normals, axis=1)[:, None]
            lifted = StructurePrior(prior.points + float(variant[len("lifted") :]) * unit, prior.normals, "points")
            return reconstruct_structure(lifted, method="oriented", margin=0.0)
        # S' through the known points, before its envelope (margin=0): what the carving changes.
        return reconstruct_structure(prior, margin=0.0, **kwargs) if variant == "oriented" else carved(prior, variant)

    return make


def measure(variant: str, family: str, seed: int, experiment: StructuresExperiment, missions: list[Mission]) -> dict[str, float]:
    structure = STRUCTURE_FAMILIES[family](rng=seed)
    prior_rng = np.random.default_rng(seed).spawn(3)[0]  # the mission's prior stream (run_mission)
    surface = surface_maker(variant)(sample_structure_prior(structure, experiment.n_prior, rng=prior_rng), rng=prior_rng)
    error = reconstruction_error(structure, surface, n_samples=4000, rng=seed)
    row = {"inward": error.inward_area_share, "miss": error.hausdorff_truth_to_approx_m, "mean": error.mean_m}
    row["squarely"] = _squarely_inward(structure, surface, seed)
    # The mission makes S' by the name mission.py imported: the variant stands in for it.
    uavcov.mission.reconstruct_structure = surface_maker(variant)  # type: ignore[attr-defined]
    try:
        for start, offset, spacing in missions:
            result = run_task(experiment, (family, start, seed, offset, spacing))
            row[f"{start}@{offset:g},{spacing:g}"] = result["best"] if not result["error"] else np.nan
    finally:
        uavcov.mission.reconstruct_structure = reconstruct_structure  # type: ignore[attr-defined]
    return row


def _squarely_inward(structure: Any, surface: Terrain, seed: int) -> float:
    """The share of S' in the air facing into the nearest part by over 30 degrees (the points of
    ``reconstruction_error(..., n_samples=4000, rng=seed)``'s sample), not a grazing tilt."""
    generator = np.random.default_rng(seed)
    _sample_faces(structure.surface.vertices, structure.surface.faces[structure.face_mask()], 4000, generator)
    points, face = _sample_faces(surface.vertices, surface.faces, 4000, generator)
    normals = surface.face_normals[face]
    solid = Terrain(structure.surface.vertices, structure.surface.faces[_solid_faces(structure)])
    into = facing_into(solid, points, normals)
    away = points - solid.closest_point(points, n_threads=1)
    cosine = np.einsum("ij,ij->i", normals, away) / np.maximum(np.linalg.norm(away, axis=1), 1e-300)
    return float(np.mean(into & ~solid.inside(points, n_threads=1) & (cosine < -0.5)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1000-1003")
    parser.add_argument("--variants", default="oriented,rays,open,rays_blocked,hull")
    parser.add_argument("--all-settings", action="store_true", help="every offset (and spacing) the experiment chooses from")
    parser.add_argument("--no-missions", action="store_true", help="S' only: the inward share and its squarely inward part")
    args = parser.parse_args()
    experiment = StructuresExperiment()
    seeds = parse_seeds(args.seeds)
    variants = args.variants.split(",")
    if args.no_missions:
        _print_geometry(experiment, seeds, variants)
        return
    if args.all_settings:
        missions = [(start, *setting) for start in ("cvt3d", "greedy3d") for setting in _settings(experiment, start)]
    else:
        missions = list(MISSIONS)
    rows = {(v, f): [measure(v, f, seed, experiment, missions) for seed in seeds] for v in variants for f in experiment.families}
    chosen = {v: {start: _choose(v, start, rows, missions, experiment) for start in ("cvt3d", "greedy3d")} for v in variants}
    print(f"seeds {args.seeds}; per cell: inward % / H(S->S') m / mean m / cvt3d best / greedy3d best\n")
    print("| family | " + " | ".join(f"{v} ({chosen[v]['cvt3d']}; {chosen[v]['greedy3d']})" for v in variants) + " |")
    print("|---|" + "---|" * len(variants))
    for family in [*experiment.families, "all"]:
        cells = []
        for v in variants:
            mine = [r for f in experiment.families if family in (f, "all") for r in rows[(v, f)]]
            cells.append(_cell(mine, chosen[v]))
        print(f"| {family} | " + " | ".join(cells) + " |")


def _print_geometry(experiment: StructuresExperiment, seeds: list[int], variants: list[str]) -> None:
    rows = {(v, f): [measure(v, f, seed, experiment, []) for seed in seeds] for v in variants for f in experiment.families}
    print("per cell: S' facing inward / of it in the air and into the nearest part by over 30 degrees\n")
    print("| family | " + " | ".join(variants) + " |")
    print("|---|" + "---|" * len(variants))
    for family in [*experiment.families, "all"]:
        cells = []
        for v in variants:
            mine = [r for f in experiment.families if family in (f, "all") for r in rows[(v, f)]]
            cells.append(f"{100 * np.mean([r['inward'] for r in mine]):.1f} % / {100 * np.mean([r['squarely'] for r in mine]):.1f} %")
        print(f"| {family} | " + " | ".join(cells) + " |")


def _choose(
    variant: str, start: str, rows: dict[tuple[str, str], list[dict[str, float]]], missions: list[Mission], experiment: StructuresExperiment
) -> str:
    """The setting with the best mean best coverage over every family (the experiment's rule)."""
    keys = [(f"{s}@{o:g},{p:g}", o, p) for s, o, p in missions if s == start]

    def score(key: tuple[str, float, float]) -> tuple[float, float, float]:
        mean = float(np.mean([np.nanmean([r[key[0]] for r in rows[(variant, f)]]) for f in experiment.families]))
        return (mean, -key[1], key[2])

    return max(keys, key=score)[0]


def _cell(rows: list[dict[str, float]], chosen: dict[str, str]) -> str:
    mean = {c: float(np.nanmean([r[c] for r in rows])) for c in ("inward", "miss", "mean", chosen["cvt3d"], chosen["greedy3d"])}
    return (
        f"{100 * mean['inward']:.1f} % / {mean['miss']:.2f} / {mean['mean']:.2f} / "
        f"{mean[chosen['cvt3d']]:.3f} / {mean[chosen['greedy3d']]:.3f}"
    )


if __name__ == "__main__":
    main()
