#!/usr/bin/env python
"""Choose reconstruct_structure's default by the mission it gives (issue 42), on development seeds.

For each family of :data:`uavcov.structures.STRUCTURE_FAMILIES` and development seed, the same 100
known points (with normals) are turned into S' by each dependency-light method, and the same
``cvt3d`` mission (the experiment's settings, S' given directly) runs on each; the table is the
mean best coverage, the mean number of start points inside the real structure before
``closest_admissible``, and the share of S' facing inward, per method::

    nice python scripts/structure_method_choice.py --seeds 1000-1003 --workers 2

``--methods`` adds the optional libraries' reconstructions (``EXTERNAL``), which need
``pip install open3d-cpu pymeshlab point-cloud-utils`` in the venv: measured here, not
dependencies of uavcov.
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

EXTERNAL = ("poisson", "ball_pivoting", "meshlab_poisson", "meshlab_ball_pivoting", "alpha_wrap_2", "alpha_wrap_5", "winding_1")
"""Reconstructions from the optional libraries (Open3D's through ``reconstruct_structure``; pymeshlab's
screened Poisson, ball pivoting and CGAL alpha wrap of alpha 2 or 5 m; point-cloud-utils' fast winding
number of the oriented points on a 1 m voxel grid), each reduced to its outer pieces, turned outward."""


def _voxel_boundary(solid: np.ndarray, origin: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """The faces between solid and empty voxels of a boolean grid, two triangles each, wound outward."""
    padded = np.pad(solid, 1)
    _, ny, nz = padded.shape

    def corner(i: np.ndarray, j: np.ndarray, k: np.ndarray) -> np.ndarray:
        return (i * (ny + 1) + j) * (nz + 1) + k

    quads = []
    for axis in range(3):
        diff = np.diff(padded.astype(np.int8), axis=axis)  # +1: empty -> solid along +axis (face looks -axis)
        for sign in (1, -1):
            idx = np.argwhere(diff == sign)
            idx[:, axis] += 1  # the face lies on the lattice plane between the two voxels
            u, v = [(axis + 1) % 3, (axis + 2) % 3]
            du, dv = np.eye(3, dtype=int)[u], np.eye(3, dtype=int)[v]
            c = [idx, idx + du, idx + du + dv, idx + dv]
            ids = np.stack([corner(*q.T) for q in c], axis=1)
            quads.append(ids[:, ::-1] if sign == 1 else ids)  # wound so the normal leaves the solid
    quads = np.concatenate(quads)
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    used, faces = np.unique(tris, return_inverse=True)
    i, rest = np.divmod(used, (ny + 1) * (nz + 1))
    j, k = np.divmod(rest, nz + 1)
    vertices = origin + step * (np.stack([i, j, k], axis=1) - 1.0)
    return vertices, faces.reshape(-1, 3)


def external(method: str, prior: object) -> object:
    from uavcov import Terrain
    from uavcov.structures._outer_surface import outer_shells

    points, normals = np.asarray(prior.points), np.asarray(prior.normals)
    if method in ("poisson", "ball_pivoting"):
        return reconstruct_structure(prior, method=method, margin=0.0)
    unit = normals / np.linalg.norm(normals, axis=1)[:, None]
    if method.startswith("winding"):
        import point_cloud_utils as pcu
        from scipy.spatial import cKDTree

        step = float(method.split("_")[1])
        spacing = cKDTree(points).query(points, k=2)[0][:, 1]
        areas = (np.pi * spacing**2)[:, None]  # each point stands for a disc to its nearest neighbour
        low, high = points.min(axis=0) - 2 * step, points.max(axis=0) + 2 * step
        axes = [np.arange(lo + step / 2, hi, step) for lo, hi in zip(low, high, strict=True)]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
        w = pcu.point_cloud_fast_winding_number(points, unit, areas, grid.reshape(-1, 3)).reshape(grid.shape[:3])
        vertices, faces = _voxel_boundary(w > 0.5, low, step)
    else:
        import pymeshlab

        ms = pymeshlab.MeshSet()
        if method.startswith("alpha_wrap"):  # its filter takes triangles (it crashed on bare points): a 5 cm one per point
            side = np.cross(unit, [0.3, 0.5, 0.8])
            side /= np.linalg.norm(side, axis=1)[:, None]
            other = np.cross(unit, side)
            tips = [points + 0.05 * (np.cos(t) * side + np.sin(t) * other) for t in (0.0, 2.0944, 4.1888)]
            m = points.shape[0]
            ms.add_mesh(pymeshlab.Mesh(vertex_matrix=np.concatenate(tips), face_matrix=np.arange(3 * m).reshape(3, m).T.copy()))
        else:
            ms.add_mesh(pymeshlab.Mesh(vertex_matrix=points, v_normals_matrix=unit))
        if method == "meshlab_poisson":
            ms.generate_surface_reconstruction_screened_poisson(depth=6, threads=1, preclean=True)
        elif method == "meshlab_ball_pivoting":
            ms.generate_surface_reconstruction_ball_pivoting()
        else:
            alpha = float(method.rsplit("_", 1)[1])
            ms.generate_alpha_wrap(alpha=pymeshlab.PureValue(alpha), offset=pymeshlab.PureValue(0.3))
        mesh = ms.current_mesh()
        vertices, faces = mesh.vertex_matrix().astype(np.float64), mesh.face_matrix().astype(np.int64)
    if faces.shape[0] == 0:
        raise UavcovError(f"{method} made no surface")
    faces = outer_shells(vertices, faces, points, normals)
    return Terrain(vertices, faces, drop_degenerate=True)


def one(task: tuple[str, int, str, float]) -> tuple[str, int, str, float, float, float]:
    family, seed, method, offset = task
    experiment = StructuresExperiment()
    structure = STRUCTURE_FAMILIES[family](rng=seed)
    prior_rng = np.random.default_rng(seed)
    try:
        prior = sample_structure_prior(structure, experiment.n_prior, rng=prior_rng)
        surface = external(method, prior) if method in EXTERNAL else reconstruct_structure(prior, method=method, margin=0.0, rng=prior_rng)
    except UavcovError:
        return family, seed, method, np.nan, np.nan, np.nan
    settings = MissionSettings(
        n_uavs=experiment.n_uavs,
        d_max=experiment.d_max,
        iterations=experiment.iterations,
        start=StartSettings(kind="cvt", altitude=offset, altitude_reference="normal", climb=0.5),
        constraints=_limits(experiment, structure),
    )
    try:
        result = run_mission(
            structure, settings, known=surface, targets=structure.targets(spacing=experiment.target_spacing), rng=seed, n_threads=1
        )
    except UavcovError as exc:
        print(f"{family} {seed} {method}: {type(exc).__name__}: {exc}", flush=True)
        return family, seed, method, np.nan, np.nan, np.nan
    inside = float(structure.surface.inside(result.start_positions, n_threads=1).sum())
    inward = reconstruction_error(structure, surface, n_samples=4000, rng=seed).inward_area_share
    return family, seed, method, result.best_coverage, inside, inward


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1000-1003")
    parser.add_argument("--offset", type=float, default=3.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--methods", default=",".join(METHODS), help=f"among {METHODS + EXTERNAL}")
    args = parser.parse_args()
    methods = tuple(args.methods.split(","))
    tasks = [(f, s, m, args.offset) for f, s, m in itertools.product(STRUCTURE_FAMILIES, parse_seeds(args.seeds), methods)]
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(one, tasks))
    print(f"| family | {' | '.join(methods)} |  (mean best; starts inside the structure per run; S' facing inward)")
    print("|---|" + "---|" * len(methods))
    for family in [*STRUCTURE_FAMILIES, "all"]:
        cells = []
        for method in methods:
            mine = [r for r in rows if r[2] == method and (family == "all" or r[0] == family)]
            best, inside, inward = (np.nanmean([r[k] for r in mine]) for k in (3, 4, 5))
            cells.append(f"{best:.3f}; {inside:.2f}; {100 * inward:.1f} %")
        print(f"| {family} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
