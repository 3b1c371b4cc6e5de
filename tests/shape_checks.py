"""Brute-force references that judge missions on the unseen shapes of ``tests/shape_zoo.py``.

They do not use the project's queries: point-triangle distance by the closest-point regions
(Ericson, "Real-Time Collision Detection" 5.1.5), inside by the generalised winding number (the
sum of the solid angles of the faces, Van Oosterom and Strackee), segment crossing and occlusion
by Moller-Trumbore, all in numpy; then one mission with the README's structure settings, or one
``uavcov plan --structure FILE``, judged by them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shape_zoo import Shape

# ---------------------------------------------------------------------------------------------
# the independent references
# ---------------------------------------------------------------------------------------------


_CELLS = 2_000_000  # (point, triangle) pairs held at once: a 200k-face mesh stays in memory


def _rows(chunk: int, n_triangles: int) -> int:
    """At most ``chunk`` points (or segments) at a time, fewer against many triangles."""
    return max(1, min(chunk, _CELLS // max(1, n_triangles)))


def point_triangle_distance(points: np.ndarray, triangles: np.ndarray, chunk: int = 256) -> np.ndarray:
    """``(P,)`` least distance of each point to any of ``triangles`` ``(F, 3, 3)``, by the
    closest-point regions of each triangle (vertex, edge, face)."""
    out = np.empty(len(points))
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    ab, ac = b - a, c - a
    chunk = _rows(chunk, len(triangles))
    for s in range(0, len(points), chunk):
        p = points[s : s + chunk, None, :]
        ap, bp, cp = p - a, p - b, p - c
        d1, d2 = (ap * ab).sum(-1), (ap * ac).sum(-1)
        d3, d4 = (bp * ab).sum(-1), (bp * ac).sum(-1)
        d5, d6 = (cp * ab).sum(-1), (cp * ac).sum(-1)
        va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
        with np.errstate(divide="ignore", invalid="ignore"):
            denom = 1.0 / (va + vb + vc)
            v_face, w_face = vb * denom, vc * denom
            q = a + v_face[..., None] * ab + w_face[..., None] * ac
            # edges: ab, ac, bc
            t_ab = np.clip(d1 / (d1 - d3), 0, 1)
            t_ac = np.clip(d2 / (d2 - d6), 0, 1)
            t_bc = np.clip((d4 - d3) / ((d4 - d3) + (d5 - d6)), 0, 1)
        q = np.where(((va >= 0) & (vb >= 0) & (vc >= 0) & np.isfinite(denom))[..., None], q, np.nan)
        best = np.linalg.norm(p - q, axis=-1)
        for start, edge, share in ((a, ab, t_ab), (a, ac, t_ac), (b, c - b, t_bc)):
            e = start + np.nan_to_num(share, nan=0.0)[..., None] * edge
            best = np.fmin(best, np.linalg.norm(p - e, axis=-1))
        out[s : s + chunk] = best.min(axis=1)
    return out


def winding_number(points: np.ndarray, triangles: np.ndarray, chunk: int = 128) -> np.ndarray:
    """``(P,)`` generalised winding number of each point with respect to ``triangles``: 1 inside
    a closed outward solid, 0 outside, 2 where two overlapping solids are both around it."""
    out = np.empty(len(points))
    chunk = _rows(chunk, len(triangles))
    for s in range(0, len(points), chunk):
        a = triangles[None, :, 0] - points[s : s + chunk, None]
        b = triangles[None, :, 1] - points[s : s + chunk, None]
        c = triangles[None, :, 2] - points[s : s + chunk, None]
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        det = np.einsum("pfk,pfk->pf", a, np.cross(b, c))
        den = la * lb * lc + (a * b).sum(-1) * lc + (b * c).sum(-1) * la + (c * a).sum(-1) * lb
        out[s : s + chunk] = 2.0 * np.arctan2(det, den).sum(axis=1) / (4.0 * np.pi)
    return out


def segment_hits(triangles: np.ndarray, a: np.ndarray, b: np.ndarray, eps: float, chunk: int = 64) -> np.ndarray:
    """``(S,)`` bool: the segment ``a[k] -> b[k]`` meets some triangle (Moller-Trumbore);
    ``eps > 0`` widens each triangle and the segment by that share, ``eps < 0`` shrinks them."""
    out = np.zeros(len(a), dtype=bool)
    # Each chunk meets only the triangles whose boxes overlap its own (a dense mesh's many
    # triangles far from a short segment cannot be crossed): the same answer, less work.
    t_lo, t_hi = triangles.min(axis=1), triangles.max(axis=1)
    pad = 1e-6 * max(1.0, float(np.abs(triangles).max()) if len(triangles) else 1.0)
    for s in range(0, len(a), chunk):
        ends = np.concatenate([a[s : s + chunk], b[s : s + chunk]])
        near = ((t_hi >= ends.min(axis=0) - pad) & (t_lo <= ends.max(axis=0) + pad)).all(axis=1)
        if not near.any():
            continue
        here = triangles[near]
        if len(here) * chunk > _CELLS:  # a dense mesh near the chunk: fewer segments at a time
            out[s : s + chunk] = segment_hits(here, a[s : s + chunk], b[s : s + chunk], eps, _rows(chunk, len(here)))
            continue
        t0, e1, e2 = here[None, :, 0], (here[:, 1] - here[:, 0])[None], (here[:, 2] - here[:, 0])[None]
        o, d = a[s : s + chunk, None], (b - a)[s : s + chunk, None]
        pvec = np.cross(d, e2)
        det = (e1 * pvec).sum(-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            tvec = o - t0
            u = (tvec * pvec).sum(-1) * inv
            qvec = np.cross(tvec, e1)
            v = (d * qvec).sum(-1) * inv
            t = (e2 * qvec).sum(-1) * inv
            hit = (det != 0) & (u >= -eps) & (v >= -eps) & (u + v <= 1 + eps) & (t >= -eps) & (t <= 1 + eps)
        out[s : s + chunk] = hit.any(axis=1)
    return out


def seen_bounds(triangles: np.ndarray, uavs: np.ndarray, targets: np.ndarray, d_max: float) -> tuple[np.ndarray, np.ndarray]:
    """``(T,)`` bool twice: each target surely seen, and possibly seen, by some UAV, under the
    visibility model (within ``d_max``, and the segment from the UAV to 0.1 % short of the
    target crosses no triangle), with the triangles shrunk, then widened, by 1e-9."""
    surely, maybe = np.zeros(len(targets), bool), np.zeros(len(targets), bool)
    for p in uavs:
        near = np.linalg.norm(targets - p, axis=1) <= d_max
        idx = np.nonzero(near)[0]
        if idx.size == 0:
            continue
        a = np.repeat(p[None], idx.size, axis=0)
        b = p + 0.999 * (targets[idx] - p)
        maybe[idx] |= ~segment_hits(triangles, a, b, -1e-9)
        surely[idx] |= ~segment_hits(triangles, a, b, 1e-9)
    return surely, maybe


@dataclass
class Verdict:
    """What the references found wrong with one mission (counts of positions or moves)."""

    standoff: int = 0
    separation: int = 0
    ceiling: int = 0
    below_ground: int = 0
    inside: int = 0
    raw_start_inside: int = 0
    moves_crossing: int = 0
    coverage_off: float = 0.0  # how far the reported best coverage is outside the recount's bounds
    recount: tuple[float, float] = (0.0, 0.0)

    @property
    def safety(self) -> int:
        return self.standoff + self.separation + self.ceiling + self.below_ground + self.inside + self.moves_crossing


def judge(structure, result, h_min: float, d_safe: float, z_max: float, closed: bool, *, solid: np.ndarray | None = None) -> Verdict:
    """Every configuration of ``result`` (a MissionResult on ``structure``) against the references.

    ``solid`` ``(F, 3, 3)``: the triangles of the closed solids a UAV must stay out of, when the
    structure's non-ground faces hold more (a site model read with its terrain as one open mesh);
    by default the faces of every part but the ground. Below the ground is under its lowest
    point, or under a face of it (a ray straight up meets it: a hillside); with no ground part,
    nothing is.
    """
    v, f = structure.surface.vertices, structure.surface.faces
    triangles = v[f]
    on_ground = structure.face_parts == (-1 if structure.ground_part is None else structure.ground_part)
    solid = triangles[~on_ground] if solid is None else solid
    trajectory = np.asarray(result.trajectory)
    points = trajectory.reshape(-1, 3)
    unique = np.unique(points, axis=0)
    verdict = Verdict()
    scale = max(1.0, float(np.abs(v).max()))
    verdict.standoff = int((point_triangle_distance(unique, triangles) < h_min - 1e-9 * scale).sum())
    verdict.ceiling = int((unique[:, 2] > z_max + 1e-9 * scale).sum())
    verdict.below_ground = int(below_ground(unique, triangles[on_ground]).sum())
    if closed:
        verdict.inside = int((winding_number(unique, solid) > 0.5).sum())
        raw = np.asarray(result.start_positions)
        verdict.raw_start_inside = int((winding_number(raw, solid) > 0.5).sum())
    i, j = np.triu_indices(trajectory.shape[1], 1)
    gaps = np.linalg.norm(trajectory[:, i] - trajectory[:, j], axis=2)
    verdict.separation = int((gaps < d_safe - 1e-9 * scale).sum())
    a, b = trajectory[:-1].reshape(-1, 3), trajectory[1:].reshape(-1, 3)
    moved = (a != b).any(axis=1)
    verdict.moves_crossing = int(segment_hits(triangles, a[moved], b[moved], 1e-9).sum())
    return verdict


def below_ground(points: np.ndarray, ground: np.ndarray) -> np.ndarray:
    """``(P,)`` bool: under the ground triangles ``(G, 3, 3)`` (facing up): below their lowest
    point, or with one of them straight above (a ray up meets it, widened by 1e-9)."""
    if ground.shape[0] == 0:
        return np.zeros(len(points), dtype=bool)
    low = points[:, 2] < ground[..., 2].min()
    above = points + [0.0, 0.0, float(np.ptp(ground[..., 2])) + float(np.abs(ground[..., 2]).max()) + 1.0]
    return low | segment_hits(ground, points, above, -1e-9)


def recount(structure, targets, positions: np.ndarray, d_max: float) -> tuple[float, float]:
    """The weighted share of ``targets`` seen from ``positions``: (surely, possibly)."""
    triangles = structure.surface.vertices[structure.surface.faces]
    surely, maybe = seen_bounds(triangles, np.asarray(positions, float), np.asarray(targets.points), d_max)
    w = np.asarray(targets.weights)
    return float(w[surely].sum() / w.sum()), float(w[maybe].sum() / w.sum())


# ---------------------------------------------------------------------------------------------
# one mission, judged
# ---------------------------------------------------------------------------------------------


def few_targets(structure, count: int = 400):
    """About ``count`` of the structure's own targets (every k-th of a spacing fitted to its area)."""
    from uavcov.structures import StructureTargets

    v, f = structure.surface.vertices, structure.surface.faces
    tri = v[f[structure.face_mask()]]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1).sum()
    targets = structure.targets(spacing=float(np.sqrt(area / count)))
    step = max(1, len(targets) // count)
    if step == 1:
        return targets
    pick = np.arange(0, len(targets), step)
    return StructureTargets(
        np.asarray(targets.points)[pick],
        np.asarray(targets.weights)[pick],
        np.asarray(targets.normals)[pick],
        np.asarray(targets.parts)[pick],
        targets.part_names,
    )


H_MIN, D_SAFE, D_MAX = 2.0, 1.0, 15.0


def readme_settings(structure, start: str, iterations: int, n_uavs: int = 8, n_prior: int = 100):
    """The README's structure settings (8 UAVs, d_max 15 m, 100 known points, 2 m standoff, every
    move checked), the ceiling 10 m over the structure's top (22 m for a short one)."""
    import uavcov
    from uavcov.cover import GreedySettings
    from uavcov.limits import Constraints
    from uavcov.placement import StartSettings

    v, f = structure.surface.vertices, structure.surface.faces
    ground_z = float(v[f][..., 2].min())
    z_max = max(ground_z + 22.0, float(v[f][..., 2].max()) + 10.0)
    if start == "greedy":
        spec = StartSettings(kind="greedy", altitude=4.0, altitude_reference="normal", greedy=GreedySettings(spacing=4.0))
    else:
        spec = StartSettings(kind=start, altitude=6.0, altitude_reference="normal", climb=0.5)
    limits = Constraints(clearance="standoff", h_min=H_MIN, d_safe=D_SAFE, z_max=z_max, check_moves=True)
    return uavcov.MissionSettings(n_uavs=n_uavs, d_max=D_MAX, n_prior=n_prior, iterations=iterations, start=spec, constraints=limits)


@dataclass
class Outcome:
    kind: str
    seed: int
    start: str
    error: str | None = None  # the exception's class and message, if the run raised
    clear_refusal: bool = False  # the exception came from uavcov.errors
    verdict: Verdict | None = None
    best: float = float("nan")
    initial: float = float("nan")


def run_judged(
    structure,
    start: str,
    iterations: int,
    seed: int,
    closed: bool,
    *,
    n_uavs: int = 8,
    targets_count: int = 400,
    solid: np.ndarray | None = None,
    prior=None,
) -> Outcome:
    """Run one mission with the README's settings and judge it by the references (``solid`` as
    :func:`judge`; ``prior(structure, seed) -> StructurePrior`` instead of the README's 100 known
    points with normals)."""
    import uavcov
    from uavcov import errors

    outcome = Outcome(structure.name, seed, start)
    try:
        settings = readme_settings(structure, start, iterations, n_uavs)
        targets = few_targets(structure, targets_count)
        known = None if prior is None else prior(structure, seed)
        result = uavcov.run_mission(structure, settings, known=known, targets=targets, rng=seed, n_threads=1)
    except Exception as exc:  # noqa: BLE001 -- any failure is counted (a crash or a clear refusal), not hidden
        outcome.error = f"{type(exc).__name__}: {exc}"
        outcome.clear_refusal = isinstance(exc, errors.UavcovError)
        return outcome
    z_max = result.settings.constraints.z_max
    verdict = judge(structure, result, H_MIN, D_SAFE, z_max, closed, solid=solid)
    best_lo, best_hi = recount(structure, targets, result.best_positions, D_MAX)
    start_lo, start_hi = recount(structure, targets, result.initial_positions, D_MAX)
    verdict.recount = (best_lo, best_hi)
    off = max(best_lo - result.best_coverage, result.best_coverage - best_hi, 0.0)
    off = max(off, start_lo - result.initial_coverage, result.initial_coverage - start_hi)
    verdict.coverage_off = off
    outcome.verdict, outcome.best, outcome.initial = verdict, result.best_coverage, result.initial_coverage
    return outcome


def assert_kept(outcome: Outcome) -> None:
    """Assert that the judged mission ran and kept every promise: no crash, no safety violation,
    the reported coverage within the recount's bounds (and those unambiguous), best >= start."""
    assert outcome.error is None, outcome.error
    verdict = outcome.verdict
    assert (verdict.standoff, verdict.separation, verdict.ceiling, verdict.below_ground) == (0, 0, 0, 0)
    assert verdict.inside == 0 and verdict.moves_crossing == 0
    assert verdict.coverage_off <= 1e-12
    assert verdict.recount[1] - verdict.recount[0] <= 1e-12
    assert 0.0 < outcome.best <= 1.0 and outcome.best >= outcome.initial


@dataclass
class PlanOutcome:
    returncode: int
    stderr: str
    violations: int = 0  # route segments through the structure, final positions nearer than the standoff or inside
    coverage: float = float("nan")


def plan_arguments(
    path: Path, out: Path, seed: int, iterations: int, n_uavs: int = 8, *, scale: float = 1.0, open_mesh: bool = False
) -> list[str]:
    """The arguments of ``uavcov plan --structure FILE`` with the README's team."""
    arguments = ["plan", "--structure", str(path), "--anchor", "8.5,47.4,400", "--uavs", str(n_uavs), "--d-max", str(D_MAX)]
    arguments += ["--iterations", str(iterations), "--seed", str(seed), "--threads", "1"] + (
        ["--scale", repr(scale)] if scale != 1.0 else []
    )
    return arguments + (["--open-mesh"] if open_mesh else []) + ["--out", str(out)]


def judge_plan(path: Path, out: Path, *, scale: float = 1.0, open_mesh: bool = False, solid: np.ndarray | None = None) -> int:
    """How many route segments of a written structure plan cross the structure (read as the
    command read it), and how many final positions are nearer than the standoff or inside it
    (inside ``solid``'s triangles when given, as :func:`judge`)."""
    import csv
    import json

    from uavcov.structures import load_structure

    inside = solid
    structure = load_structure(path, scale=scale, closed=not open_mesh)
    v, f = structure.surface.vertices, structure.surface.faces
    solid = v[f[structure.face_parts != structure.ground_part]]
    plan = json.loads((out / "plan.json").read_text())
    with open(out / "waypoints.csv") as table:
        rows = list(csv.DictReader(table))
    pad = np.asarray(plan["takeoff_local"], float)
    violations = 0
    for uav in sorted({r["uav"] for r in rows}):
        route = np.array([[float(r["east_m"]), float(r["north_m"]), float(r["up_m"])] for r in rows if r["uav"] == uav])
        route = np.vstack([pad, route])  # from the pad on the ground, up to the first waypoint
        violations += int(segment_hits(solid, route[:-1], route[1:], 1e-9).sum())
    positions = np.asarray(plan["positions_local"], float)
    violations += int((point_triangle_distance(positions, v[f]) < H_MIN - 1e-9).sum())
    violations += int((winding_number(positions, solid if inside is None else inside) > 0.5).sum())
    return violations


def plan_judged(
    path: Path, out: Path, seed: int, iterations: int, n_uavs: int = 8, *, scale: float = 1.0, open_mesh: bool = False, solid=None
) -> PlanOutcome:
    """``uavcov plan --structure FILE`` in a child process, judged by :func:`judge_plan`."""
    import json
    import subprocess
    import sys

    command = [sys.executable, "-m", "uavcov"] + plan_arguments(path, out, seed, iterations, n_uavs, scale=scale, open_mesh=open_mesh)
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, check=False, env=_no_plots_env())
    outcome = PlanOutcome(done.returncode, done.stderr.strip())
    if done.returncode == 0:
        outcome.violations = judge_plan(path, out, scale=scale, open_mesh=open_mesh, solid=solid)
        outcome.coverage = float(json.loads((out / "plan.json").read_text())["results"]["coverage"])
    return outcome


def _no_plots_env() -> dict:
    import os

    env = dict(os.environ)
    env["MPLBACKEND"] = "Agg"
    return env


def inside_disagreements(structure, shape: Shape, count: int = 400, seed: int = 1) -> tuple[int, int]:
    """``Terrain.inside`` against the winding number of the shape's faces (each face once) on
    ``count`` random points around it, off the surface: (points inside it calls outside, points
    outside it calls inside). The first is unsafe; the second only refuses a free point."""
    v = shape.vertices
    once = np.sort(np.unique(np.sort(shape.faces, axis=1), axis=0, return_index=True)[1])
    triangles = v[shape.faces[once]]
    used = v[np.unique(shape.faces)]
    lo, hi = used.min(axis=0) - 1.0, used.max(axis=0) + 1.0
    lo[2] = shape.ground_z  # above the ground sheet: under it, any ray up meets the sheet
    points = np.random.default_rng(seed).uniform(lo, hi, (count, 3))
    points = points[point_triangle_distance(points, triangles) > 1e-3 * max(1.0, float(np.ptp(used, axis=0).max()))]
    if shape.ground is not None:  # a hillside: not under it either
        points = points[~below_ground(points, shape.ground[0][shape.ground[1]])]
    expected = np.abs(winding_number(points, triangles)) > 0.5  # a solid wound inward has -1 inside
    said = np.asarray(structure.surface.inside(points), dtype=bool)
    return int((expected & ~said).sum()), int((~expected & said).sum())
