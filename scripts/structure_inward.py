#!/usr/bin/env python
"""Where S' faces into the structure (issue 42): the inward share of S''s area, decomposed.

For each family of :data:`uavcov.structures.STRUCTURE_FAMILIES` and seed, the 100 known points
with normals and the S' that ``run_mission(..., rng=seed)`` flies on in the structures
experiment (its prior stream, ``reconstruct_structure(prior, method=...)``); the 4000
area-uniform points of S' that ``reconstruction_error(..., n_samples=4000, rng=seed)`` draws (the
experiment's ``inward_share`` column) are judged by the measure of
``reconstruction_error(...).inward_area_share`` (``structures/_facing.py``), and the inward ones
split by where they are: in the air or inside a real solid, the real part nearest them, the
size of the S' face holding them (its longest edge), its distance from the real surface, and
how far their normal is from the real
surface's tangent plane there (in the air: how far it points into the nearest part, against
the way out from it). Every figure is a share of S''s area (mean over the seeds), so the rows
of one split add up to the inward share. Besides, H(S->S') (what S' misses, from 4000 points of
the structure), the mean of the two mean distances, S''s volume over the known points' convex
hull's, the share of S''s volume in the air (outside every real solid), and what the share stands for: the share of
S' from which a start flown straight out along the normal by the experiment's offsets (2.5 m,
4 m; before ``fly_out``'s checks) lands inside a real solid::

    python scripts/structure_inward.py                      # development seeds 1000-1003
    python scripts/structure_inward.py --method alpha       # another method of reconstruct_structure
    python scripts/structure_inward.py --margin 0           # S' through the points, no envelope
"""

from __future__ import annotations

import argparse
import itertools
from collections import defaultdict

import numpy as np
from scipy.spatial import ConvexHull

from uavcov import Terrain
from uavcov.experiments import parse_seeds
from uavcov.structures import STRUCTURE_FAMILIES, reconstruct_structure, reconstruction_error, sample_structure_prior
from uavcov.structures._facing import facing_into
from uavcov.structures._solids import signed_volume
from uavcov.structures._structure_prior import _sample_faces, _solid_faces

EDGE_BINS = (0.0, 3.0, 6.0, 12.0, np.inf)
SAMPLES = 4000
# Uniform points in S''s bounding box that measure the share of its volume in the air.
AIR_SAMPLES = 20000
# The experiment's candidate offsets of the 3D starts from S' (m): 2.5 greedy3d's, 4 cvt3d's chosen.
START_OFFSETS = (2.5, 4.0)


def _edge_label(edge: float) -> str:
    for lo, hi in itertools.pairwise(EDGE_BINS):
        if lo <= edge < hi:
            return f"face: longest edge {lo:g}-{hi:g} m" if np.isfinite(hi) else f"face: longest edge over {lo:g} m"
    return "edge ?"


def decompose(family: str, seed: int, method: str, margin: float | None = None) -> dict[str, float]:
    """Shares of S''s area (inward ones split several ways) for one structure and prior."""
    structure = STRUCTURE_FAMILIES[family](rng=seed)
    # The S' a mission with rng=seed flies on: run_mission draws its prior from the first of
    # three streams spawned from the seed.
    prior_rng = np.random.default_rng(seed).spawn(3)[0]
    prior = sample_structure_prior(structure, 100, rng=prior_rng)
    approx = reconstruct_structure(prior, method=method, margin=margin, rng=prior_rng)
    keep = _solid_faces(structure)
    solid = Terrain(structure.surface.vertices, structure.surface.faces[keep])
    solid_parts = np.asarray(structure.face_parts)[keep]
    # reconstruction_error's own sample of S' (it draws the structure's points first).
    generator = np.random.default_rng(seed)
    _sample_faces(structure.surface.vertices, structure.surface.faces[structure.face_mask()], SAMPLES, generator)
    points, face = _sample_faces(approx.vertices, approx.faces, SAMPLES, generator)
    normals = approx.face_normals[face]
    into = facing_into(solid, points, normals)
    inside = solid.inside(points, n_threads=1)
    closest, nearest_face = solid.closest_face(points, n_threads=1)
    corners = approx.vertices[approx.faces[face]]
    edge = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).max(axis=1)
    away = points - closest
    distance = np.linalg.norm(away, axis=1)
    # The cosine between S''s normal and the way out (from the nearest real point): in the air
    # a face of S' faces in when it is negative; near zero the face grazes the real part.
    cosine = np.einsum("ij,ij->i", normals, away) / np.maximum(distance, 1e-300)
    error = reconstruction_error(structure, approx, n_samples=SAMPLES, rng=seed)
    out: dict[str, float] = defaultdict(float)
    out["inward"] = float(into.mean())
    out["H(S->S') m"] = error.hausdorff_truth_to_approx_m
    out["mean m"] = error.mean_m
    out["faces"] = float(approx.n_faces)
    out["volume S' / known points' hull"] = signed_volume(approx.vertices, approx.faces) / ConvexHull(prior.points).volume
    # How much of S''s volume is air (outside every real solid): S' filling the space between
    # parts (under a deck, between a pylon's legs) is where its faces span the air.
    box = np.random.default_rng(seed).uniform(approx.bounds[0], approx.bounds[1], size=(AIR_SAMPLES, 3))
    in_approx = approx.inside(box, n_threads=1)
    out["volume S' in the air / S'"] = float((in_approx & ~solid.inside(box, n_threads=1)).sum() / max(int(in_approx.sum()), 1))
    for offset in START_OFFSETS:
        # What the inward share is a proxy for: a start flown out along S''s normal lands in a solid.
        out[f"start: {offset:g} m out along n inside a solid (all S')"] = float(solid.inside(points + offset * normals, n_threads=1).mean())
    share = 1.0 / SAMPLES
    for k in np.flatnonzero(into):
        out["where: inside a solid" if inside[k] else "where: in the air"] += share
        out["part: " + structure.part_names[solid_parts[nearest_face[k]]]] += share
        out[_edge_label(float(edge[k]))] += share
        if not inside[k]:
            tilt = np.degrees(np.arcsin(min(1.0, -float(cosine[k]))))
            label = "into the part by under 5 deg" if tilt < 5 else "by 5-30 deg" if tilt < 30 else "by over 30 deg"
            out["angle: in the air, " + label] += share
        label = "under 1 m" if distance[k] < 1.0 else "1-3 m" if distance[k] < 3.0 else "over 3 m"
        out["distance: " + label] += share
    return dict(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1000-1003")
    parser.add_argument("--method", default="oriented")
    parser.add_argument("--margin", default="default", help="metres S' is grown by (default: reconstruct_structure's)")
    parser.add_argument("--families", default=",".join(STRUCTURE_FAMILIES))
    args = parser.parse_args()
    seeds = parse_seeds(args.seeds)
    families = args.families.split(",")
    margin = None if args.margin == "default" else float(args.margin)
    results = {f: [decompose(f, s, args.method, margin) for s in seeds] for f in families}
    keys = sorted({k for rows in results.values() for r in rows for k in r}, key=_order)
    print(f"method {args.method!r}, margin {args.margin}, seeds {args.seeds}: shares of S''s area, mean over the seeds\n")
    print("| | " + " | ".join(families) + " |")
    print("|---|" + "---|" * len(families))
    for key in keys:
        cells = []
        for family in families:
            value = float(np.mean([r.get(key, 0.0) for r in results[family]]))
            cells.append(_format(key, value))
        print(f"| {key} | " + " | ".join(cells) + " |")


def _format(key: str, value: float) -> str:
    if key in ("H(S->S') m", "mean m", "volume S' / known points' hull", "volume S' in the air / S'"):
        return f"{value:.2f}"
    return f"{value:.0f}" if key == "faces" else f"{100 * value:.1f} %"


def _order(key: str) -> tuple[int, str]:
    head = ("inward", "H(S->S') m", "mean m", "faces", "volume S' / known points' hull", "volume S' in the air / S'")
    return (head.index(key), key) if key in head else (len(head), key)


if __name__ == "__main__":
    main()
