"""Missions on a structure (issue 35, point 5): run_mission on a Structure with the standoff limits.

Every configuration of every run is checked against an independent reference written here from
the definitions (trimesh's point-triangle closest point for the standoff, Moller-Trumbore in
numpy for the moves, the parity of an upward ray for "inside a solid"), not against the Rust
queries the mission itself used.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import uavcov
from uavcov import MissionSettings, run_mission
from uavcov.errors import InvalidInputError, InvalidTypeError
from uavcov.field import GeoAnchor, plan_structure, write_structure_plan
from uavcov.field._ply import read_seen_ply
from uavcov.limits import Constraints
from uavcov.placement import StartSettings, start_configuration
from uavcov.records import load_mission, save_mission
from uavcov.structures import girder_bridge
from uavcov.structures._structures import lattice_pylon
from uavcov.terrain import sample_prior

trimesh = pytest.importorskip("trimesh")

H_MIN, D_SAFE = 2.0, 1.0


@pytest.fixture(scope="module")
def bridge():
    return girder_bridge(rng=0, step=4.0)


@pytest.fixture(scope="module")
def targets(bridge):
    return bridge.targets(spacing=1.5)


def limits(structure) -> Constraints:
    top = float(structure.surface.bounds[1, 2])
    return Constraints(clearance="standoff", h_min=H_MIN, d_safe=D_SAFE, z_max=top + 8.0, check_moves=True)


def settings(structure, kind: str, n: int = 5, iterations: int = 25, reference: str = "normal") -> MissionSettings:
    return MissionSettings(
        n_uavs=n,
        d_max=15.0,
        n_prior=80,
        iterations=iterations,
        start=StartSettings(kind=kind, altitude=4.0, altitude_reference=reference, climb=0.5),
        constraints=limits(structure),
    )


# ---------------------------------------------------------------------------------------------
# the independent reference
# ---------------------------------------------------------------------------------------------


def ref_distance(structure, points: np.ndarray) -> np.ndarray:
    triangles = structure.surface.vertices[structure.surface.faces]
    out = np.empty(len(points))
    for k, p in enumerate(np.asarray(points, dtype=np.float64)):
        closest = trimesh.triangles.closest_point(triangles, np.repeat(p[None], len(triangles), axis=0))
        out[k] = np.linalg.norm(closest - p, axis=1).min()
    return out


def _ray_hits(triangles: np.ndarray, origins: np.ndarray, directions: np.ndarray, t_max: float) -> np.ndarray:
    """(S, F) bool: Moller-Trumbore of each ray ``o + t d``, ``0 <= t <= t_max``, against each triangle."""
    t0, t1, t2 = (triangles[None, :, k] for k in range(3))
    o, d = origins[:, None, :], directions[:, None, :]
    e1, e2 = t1 - t0, t2 - t0
    pvec = np.cross(d, e2)
    det = np.einsum("stk,stk->st", np.broadcast_to(e1, pvec.shape), pvec)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        tvec = o - t0
        u = np.einsum("stk,stk->st", tvec, pvec) * inv
        qvec = np.cross(tvec, e1)
        v = np.einsum("stk,stk->st", np.broadcast_to(d, qvec.shape), qvec) * inv
        t = np.einsum("stk,stk->st", np.broadcast_to(e2, qvec.shape), qvec) * inv
        eps = 1e-9
        return (np.abs(det) > 1e-14) & (u >= -eps) & (v >= -eps) & (u + v <= 1 + eps) & (t >= -eps) & (t <= t_max + eps)


def ref_moves_cross(structure, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    triangles = structure.surface.vertices[structure.surface.faces]
    out = np.zeros(len(a), dtype=bool)
    for start in range(0, len(a), 64):
        out[start : start + 64] = _ray_hits(triangles, a[start : start + 64], b[start : start + 64] - a[start : start + 64], 1.0).any(
            axis=1
        )
    return out


def ref_inside(structure, points: np.ndarray) -> np.ndarray:
    """Odd number of solid faces crossed by a slightly skewed upward ray (the ground sheet is open)."""
    solid = structure.face_parts != structure.ground_part
    triangles = structure.surface.vertices[structure.surface.faces[solid]]
    direction = np.array([0.0123, 0.0071, 1.0])
    hits = _ray_hits(triangles, np.asarray(points), np.repeat(direction[None], len(points), axis=0), 1e4)
    return hits.sum(axis=1) % 2 == 1


def check_every_configuration(structure, result) -> None:
    trajectory = np.asarray(result.trajectory)
    points = trajectory.reshape(-1, 3)
    assert (ref_distance(structure, points) >= H_MIN - 1e-6).all()
    assert not ref_inside(structure, points).any()
    assert (points[:, 2] >= 0.0).all()  # the ground sheet is z = 0
    assert (points[:, 2] <= result.settings.constraints.z_max + 1e-9).all()
    i, j = np.triu_indices(trajectory.shape[1], 1)
    gaps = np.linalg.norm(trajectory[:, i] - trajectory[:, j], axis=2)
    assert (gaps >= D_SAFE - 1e-9).all()
    a, b = trajectory[:-1].reshape(-1, 3), trajectory[1:].reshape(-1, 3)
    moved = (a != b).any(axis=1)
    assert not ref_moves_cross(structure, a[moved], b[moved]).any()


# ---------------------------------------------------------------------------------------------
# missions
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["cvt", "random", "launch_pad"])
def test_every_configuration_of_a_structure_run_keeps_the_limits(bridge, targets, kind):
    result = run_mission(bridge, settings(bridge, kind), targets=targets, rng=3, n_threads=1)
    check_every_configuration(bridge, result)
    assert result.coverage_by_part is not None and set(result.coverage_by_part) <= set(bridge.part_names)
    assert result.trace.n_feasible[1:].sum() > 0  # the optimiser moved: the check above is about real moves


def test_the_height_field_prior_start_is_made_admissible_under_the_standoff(bridge, targets):
    known = sample_prior(bridge.surface, 80, kind="random", rng=3)
    result = run_mission(bridge, settings(bridge, "cvt", reference="prior"), known=known, targets=targets, rng=3, n_threads=1)
    assert result.prior_kind == "random"
    check_every_configuration(bridge, result)


def test_a_pylon_run_keeps_the_limits_too():
    pylon = lattice_pylon(rng=1)
    result = run_mission(pylon, settings(pylon, "cvt", n=6, iterations=15), targets=pylon.targets(spacing=1.5), rng=1, n_threads=1)
    check_every_configuration(pylon, result)


def test_the_deck_underside_is_seen_from_a_3d_cvt_start(bridge, targets):
    for seed in (0, 1):
        result = run_mission(bridge, settings(bridge, "cvt", n=8), targets=targets, rng=seed, n_threads=1)
        assert result.coverage_by_part["deck_underside"] > 0.0
        # by the reference: some UAV of the start is under the deck (below its underside, over its footprint)
        underside = bridge.surface.vertices[bridge.surface.faces[bridge.face_parts == bridge.part_index("deck_underside")]]
        lowest = underside[..., 2].min()
        assert (np.asarray(result.initial_positions)[:, 2] < lowest).any()


def test_coverage_by_part_is_the_parts_share_of_the_best_configuration(bridge, targets):
    result = run_mission(bridge, settings(bridge, "cvt", iterations=5), targets=targets, rng=2, n_threads=1)
    seen = uavcov.Visibility(bridge.surface, 15.0, targets).seen(result.best_positions)
    for name, share in result.coverage_by_part.items():
        here = targets.parts == bridge.part_index(name)
        assert share == pytest.approx(targets.weights[here & seen].sum() / targets.weights[here].sum(), abs=1e-12)
    total = sum(targets.weights[targets.parts == bridge.part_index(n)].sum() * s for n, s in result.coverage_by_part.items())
    assert total / targets.weights.sum() == pytest.approx(result.best_coverage, abs=1e-9)


def test_same_seed_same_run_and_the_run_file_keeps_the_parts(bridge, targets, tmp_path):
    a = run_mission(bridge, settings(bridge, "random", iterations=8), targets=targets, rng=5, n_threads=1)
    b = run_mission(bridge, settings(bridge, "random", iterations=8), targets=targets, rng=5, n_threads=2)
    assert np.array_equal(a.trajectory, b.trajectory) and a.coverage_by_part == b.coverage_by_part
    loaded = load_mission(save_mission(a, tmp_path / "run.npz"))
    assert loaded.coverage_by_part == a.coverage_by_part
    assert loaded.settings == a.settings


def test_the_launch_pad_is_on_the_ground_at_the_corner(bridge):
    spec = StartSettings(kind="launch_pad", altitude=1.0, altitude_reference="normal", corner_spacing=2.0)
    c = limits(bridge).resolve(bridge.surface)
    positions, tessellation = start_configuration(spec, bridge.surface, bridge.surface, 4, constraints=c, rng=0)
    assert tessellation is None
    xmin, ymin, _, _ = c.flight_box
    assert np.allclose(np.sort(positions[:, 0]), xmin + np.array([1.0, 1.0, 3.0, 3.0]))
    assert np.allclose(np.sort(positions[:, 1]), ymin + np.array([1.0, 1.0, 3.0, 3.0]))
    assert np.allclose(positions[:, 2], 1.0)


def test_the_random_start_is_admissible_by_the_reference(bridge):
    spec = StartSettings(kind="random", altitude_reference="normal")
    positions, _ = start_configuration(spec, bridge.surface, bridge.surface, 12, constraints=limits(bridge), rng=4)
    assert (ref_distance(bridge, positions) >= H_MIN).all() and not ref_inside(bridge, positions).any()


# ---------------------------------------------------------------------------------------------
# the plan and its outputs
# ---------------------------------------------------------------------------------------------


def test_a_structure_plan_has_clear_routes_and_writes_the_seen_cloud(bridge, targets, tmp_path):
    mission = plan_structure(bridge, settings(bridge, "cvt", n=6, iterations=10), GeoAnchor(8.5, 47.4, 400.0), targets=targets, rng=0)
    plan = mission.flight
    for k, route in enumerate(plan.routes_local):
        path = np.vstack([plan.takeoff_local + [0, 0, 0.01], route, plan.positions_local[k]])
        assert not ref_moves_cross(bridge, path[:-1], path[1:]).any()
    written = {p.name for p in write_structure_plan(mission, tmp_path)}
    assert {"seen.ply", "parts.csv", "plan.json", "uav_01.plan"} <= written
    cloud = read_seen_ply(tmp_path / "seen.ply")
    assert np.array_equal(cloud["count"], mission.seen_count)
    seen = cloud["count"] > 0
    assert float(targets.weights[seen].sum() / targets.weights.sum()) == pytest.approx(mission.result.best_coverage, abs=1e-9)


def test_the_plan_command_for_a_structure(tmp_path, capsys):
    from uavcov.cli import main

    code = main(["plan", "--structure", "girder_bridge", "--anchor", "8.5,47.4,400", "--uavs", "4", "--d-max", "15",
                 "--iterations", "3", "--threads", "1", "--out", str(tmp_path)])  # fmt: skip
    assert code == 0
    assert (tmp_path / "seen.ply").is_file() and (tmp_path / "plan.json").is_file()
    assert json.loads((tmp_path / "plan.json").read_text())
    assert "deck_underside" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv",
    [
        ["--structure", "no_such_scene", "--anchor", "8.5,47.4,400"],
        ["--structure", "girder_bridge"],
        ["--structure", "girder_bridge", "--anchor", "8.5,147.4,400"],
        ["--structure", "girder_bridge", "--anchor", "8.5,47.4,400", "--sample"],
        ["--sample", "--anchor", "8.5,47.4,400"],
        ["--structure", "missing.stl", "--anchor", "8.5,47.4,400"],
    ],
)
def test_bad_structure_plans_exit_2_with_one_line(argv, tmp_path, capsys):
    from uavcov.cli import main

    assert main(["plan", *argv, "--uavs", "3", "--d-max", "10", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err


# ---------------------------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------------------------


def test_bad_structure_missions_raise(bridge, targets):
    vertical = settings(bridge, "cvt").with_changes(**{"constraints.clearance": "vertical", "start.altitude_reference": "prior"})
    with pytest.raises(InvalidInputError, match="standoff"):
        run_mission(bridge, vertical, targets=targets, rng=0)
    with pytest.raises(InvalidInputError, match="structure's prior"):
        run_mission(bridge, settings(bridge, "cvt").with_changes(prior="pyramid"), targets=targets, rng=0)
    with pytest.raises(InvalidTypeError):
        run_mission("girder_bridge", settings(bridge, "cvt"), rng=0)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError):
        StartSettings(kind="corner", altitude_reference="normal")
    with pytest.raises(InvalidInputError):
        StartSettings(kind="launch_pad")
    with pytest.raises(InvalidInputError, match="too sparse"):
        run_mission(bridge, settings(bridge, "cvt").with_changes(n_prior=5), targets=targets, rng=0)


def test_the_reference_agrees_with_the_terrain_on_sample_points(bridge):
    # the reference must be able to fail: points inside the deck, under it, beside a pier
    rng = np.random.default_rng(0)
    lo, hi = bridge.surface.bounds
    points = rng.uniform(lo + [0, 0, 0.1], hi + [0, 0, 3.0], size=(200, 3))
    assert np.allclose(ref_distance(bridge, points), bridge.surface.distance(points), atol=1e-9)
    inside = ref_inside(bridge, points)
    assert inside.any() and not inside.all()
    assert np.array_equal(inside, bridge.surface.inside(points))


def _boxes_on_ground(boxes) -> uavcov.Terrain:
    quads = ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5))
    vertices = [[-20.0, -20.0, 0.0], [20.0, -20.0, 0.0], [20.0, 20.0, 0.0], [-20.0, 20.0, 0.0]]
    faces = [[0, 1, 2], [0, 2, 3]]
    for lo, hi in boxes:
        base = len(vertices)
        vertices += [[(lo, hi)[k & 1][0], (lo, hi)[(k >> 1) & 1][1], (lo, hi)[(k >> 2) & 1][2]] for k in range(8)]
        for a, b, c, d in quads:
            faces += [[base + a, base + b, base + c], [base + a, base + c, base + d]]
    return uavcov.Terrain(np.array(vertices), np.array(faces))


def test_closest_admissible_gets_out_of_a_building_low_down_and_out_of_a_wedge():
    from uavcov.limits import closest_admissible
    from uavcov.limits._constraints import feasible_mask

    # a wide block on the ground: from a point inside it 1 m up, the nearest face is its base on
    # the ground, and going out through it leads under the ground (it used to oscillate for ever)
    block = _boxes_on_ground([((-8.0, -8.0, 0.0), (8.0, 8.0, 12.0))])
    c = Constraints(clearance="standoff", h_min=2.0, d_safe=1.0, z_max=30.0, check_moves=True)
    out = closest_admissible(c, block, [[0.0, 0.0, 1.0], [10.5, 0.0, 6.0]], climb=0.5)
    assert feasible_mask(c, block, out, out[None])[0]
    assert out[0, 2] == pytest.approx(12.0 + 2.5)  # over the roof
    assert np.array_equal(out[1], [10.5, 0.0, 6.0])  # an admissible UAV is left where it is
    # a slot 3 m wide between two walls: no point in it keeps 2 m from both, so the UAV goes up
    slot = _boxes_on_ground([((-8.0, -5.0, 0.0), (-1.5, 5.0, 10.0)), ((1.5, -5.0, 0.0), (8.0, 5.0, 10.0))])
    out = closest_admissible(c, slot, [[0.3, 0.0, 5.0]], climb=0.5)
    assert feasible_mask(c, slot, out, out[None])[0]
    assert out[0, 2] >= 10.0 + 2.0


def test_the_committed_structures_experiment_is_the_report_of_its_rows():
    """docs/structures.md's table is what ``uavcov reproduce structures`` makes from the committed
    rows (docs/structures_experiment/), offsets chosen on the development rows alone, and no run
    failed."""
    from pathlib import Path

    from uavcov.paper._structures import report_from_folder

    docs = Path(__file__).resolve().parent.parent / "docs"
    text = (docs / "structures.md").read_text(encoding="utf-8")
    begin, end = "<!-- structures experiment: made by uavcov reproduce structures -->", "<!-- end of structures experiment -->"
    assert begin in text and end in text
    section = text.split(begin, 1)[1].split(end, 1)[0]
    report = report_from_folder(docs / "structures_experiment")
    assert report.strip() in section
    assert "Failed runs" not in report


def test_the_families_ground_reaches_under_all_of_them() -> None:
    from uavcov.structures import STRUCTURE_FAMILIES, STRUCTURE_SCENES

    for name, make in {**STRUCTURE_FAMILIES, **STRUCTURE_SCENES}.items():
        assert make(rng=0).check_ground() is None, name
