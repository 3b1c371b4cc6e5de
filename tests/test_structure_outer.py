"""S' seen from outside (issue 42): the outer surface only, wound outward, degenerate priors
refused before any foreign library sees them (issue 43, class 1), starts flown out of S'."""

from __future__ import annotations

import importlib.util
import warnings

import numpy as np
import pytest
import trimesh

import uavcov
from uavcov.cover import surface_normals
from uavcov.errors import InvalidInputError
from uavcov.placement import cvt, standoff_start
from uavcov.placement._starts3d import fly_out
from uavcov.structures import (
    STRUCTURE_FAMILIES,
    Structure,
    StructurePrior,
    reconstruct_structure,
    reconstruction_error,
    sample_structure_prior,
)
from uavcov.structures._solids import signed_volume

BOX = np.array([[0, 0, 0], [12, 0, 0], [12, 9, 0], [0, 9, 0], [0, 0, 16], [12, 0, 16], [12, 9, 16], [0, 9, 16]], float)
WALLS = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
HAS_OPEN3D = importlib.util.find_spec("open3d") is not None


def issue_box() -> Structure:
    """The issue's plain box on a ground sheet, built independently of the scenes' code."""
    ground = np.array([[-20, -20, 0], [30, -20, 0], [30, 30, 0], [-20, 30, 0]], float)
    vertices = np.vstack([ground, BOX])
    faces = np.vstack([[[0, 1, 2], [0, 2, 3]], np.array(WALLS) + 4])
    return Structure("box", uavcov.Terrain(vertices, faces), np.array([0, 0, 1, 1] + [2] * 10), ("ground", "contact", "building"), 0)


def _in_box(points: np.ndarray) -> np.ndarray:
    return ((points > [0, 0, 0]) & (points < [12, 9, 16])).all(axis=1)


@pytest.mark.parametrize("seed", range(4))
def test_the_issue_box_gives_no_start_inside(seed: int) -> None:
    box = issue_box()
    surface = reconstruct_structure(sample_structure_prior(box, 100, rng=seed), rng=seed)
    anchors, normals = surface_normals(surface, cvt(surface, 8, rng=seed).generators)
    assert not _in_box(anchors + 6.0 * normals).any()  # the issue's own check: 8, 5, 6 of 8 before
    start = standoff_start(surface, 8, 6.0, rng=seed)
    assert not _in_box(start.positions).any()


@pytest.mark.parametrize("seed", range(3))
def test_the_alpha_shape_is_one_outward_shell_with_no_cavity(seed: int) -> None:
    box = issue_box()
    # The surface through the points (no envelope): the box holds it.
    surface = reconstruct_structure(sample_structure_prior(box, 100, rng=seed), margin=0.0, rng=seed)
    error = reconstruction_error(box, surface, n_samples=4000, rng=seed)
    assert error.inward_area_share < 0.01
    # Closed: every edge in two faces, once each way; the volume is the hull's order, not a shell's.
    edges = np.concatenate([surface.faces[:, [0, 1]], surface.faces[:, [1, 2]], surface.faces[:, [2, 0]]])
    assert {tuple(e) for e in edges.tolist()} == {tuple(e) for e in edges[:, ::-1].tolist()}
    volume = signed_volume(surface.vertices, surface.faces)
    assert 0.6 * 12 * 9 * 16 < volume <= 12 * 9 * 16 + 1e-6
    # Every point inside S' (ray parity) is inside the box: S' is filled, not hollow.
    centre = np.array([[6.0, 4.5, 8.0]])
    assert surface.inside(centre)[0]


def test_the_inward_share_counts_a_flipped_surface() -> None:
    # A box 1 % inside the true one: each point's closest true face is the parallel one (but
    # within 1 % of an edge), so the share is the flipped faces' area share.
    box = issue_box()
    shrunk = (BOX - [6.0, 4.5, 8.0]) * 0.99 + [6.0, 4.5, 8.0]
    walls = np.array(WALLS)
    assert reconstruction_error(box, uavcov.Terrain(shrunk, walls), n_samples=4000).inward_area_share == 0.0
    assert reconstruction_error(box, uavcov.Terrain(shrunk, walls[:, ::-1]), n_samples=4000).inward_area_share > 0.97
    # Every other triangle turned: half of every wall's area, whatever the walls' sizes.
    half = walls.copy()
    half[::2] = half[::2, ::-1]
    share = reconstruction_error(box, uavcov.Terrain(shrunk, half), n_samples=20_000, rng=1).inward_area_share
    assert abs(share - 0.5) < 0.03


def test_closest_face_agrees_with_a_brute_force_search() -> None:
    rng = np.random.default_rng(3)
    surface = uavcov.Terrain(BOX, np.array(WALLS))
    queries = rng.uniform(-10, 25, size=(300, 3))
    closest, face = surface.closest_face(queries)
    v, f = surface.vertices, surface.faces
    every = _every_distance(surface, queries)
    held = every[np.arange(queries.shape[0]), face]
    assert np.allclose(held, every.min(axis=1), rtol=0, atol=1e-9)
    assert np.allclose(np.linalg.norm(closest - queries, axis=1), surface.distance(queries))
    normals = surface.face_normals
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)
    centre = v[f].mean(axis=1)
    assert np.all(np.einsum("ij,ij->i", normals, centre - [6.0, 4.5, 8.0]) > 0)


def _every_distance(surface: uavcov.Terrain, queries: np.ndarray) -> np.ndarray:
    """Brute force: every query against every triangle (trimesh's point-triangle closest point)."""
    triangles = surface.vertices[surface.faces]
    n, f = queries.shape[0], triangles.shape[0]
    near = trimesh.triangles.closest_point(np.tile(triangles, (n, 1, 1)), np.repeat(queries, f, axis=0))
    distance: np.ndarray = np.linalg.norm(near - np.repeat(queries, f, axis=0), axis=1).reshape(n, f)
    return distance


def test_the_faces_at_the_closest_point_are_every_face_a_brute_force_finds_there() -> None:
    # The box's faces, edges and corners (where two to six triangles hold the closest point),
    # its faces' diagonals, and random points, against every triangle by trimesh.
    rng = np.random.default_rng(5)
    surface = uavcov.Terrain(BOX, np.array(WALLS))
    corners = BOX + rng.uniform(0.5, 3.0, size=(8, 1)) * np.sign(BOX - [6.0, 4.5, 8.0])
    edges = np.array([[6.0, -2.0, -2.0], [14.0, 4.5, 18.0], [-1.0, 10.0, 8.0], [6.0, 4.5, 17.0]])
    queries = np.vstack([corners, edges, rng.uniform(-10, 25, size=(300, 3))])
    closest, holding = surface.faces_at_closest(queries)
    assert np.allclose(closest, surface.closest_point(queries), rtol=0, atol=0)
    on_surface = _every_distance(surface, closest)
    for k, faces in enumerate(holding):
        assert faces.tolist() == np.flatnonzero(on_surface[k] <= 1e-9).tolist(), queries[k]
    normals = surface.face_normals
    planes = [len(np.unique(np.round(normals[faces], 9), axis=0)) for faces in holding[:12]]
    assert planes == [3] * 8 + [2, 2, 2, 1]  # corners, edges, one face's diagonal (two triangles)
    assert len(holding[11]) == 2
    one, by_one = surface.faces_at_closest(queries, n_threads=1)
    four, by_four = surface.faces_at_closest(queries, n_threads=4)
    assert np.array_equal(one, four) and all(np.array_equal(a, b) for a, b in zip(by_one, by_four, strict=True))
    empty_points, empty_faces = surface.faces_at_closest(np.empty((0, 3)))
    assert empty_points.shape == (0, 3) and empty_faces == []


@pytest.mark.parametrize("bad", [[[np.nan, 0.0, 0.0]], [[1e300, 0.0, 0.0]], [[0.0, 0.0]], "points"])
def test_faces_at_closest_refuses_bad_points(bad: object) -> None:
    surface = uavcov.Terrain(BOX, np.array(WALLS))
    with pytest.raises((uavcov.errors.InvalidInputError, uavcov.errors.InvalidTypeError)):
        surface.faces_at_closest(bad)


def test_the_inward_share_is_orientation_not_position() -> None:
    # The true surface and copies of it shrunk into it or grown around it, each as is (0) and
    # inverted (1): a face of S' a little inside a wall with the wall's normal does not face in.
    box = issue_box()
    walls = np.array(WALLS)
    centre = np.array([6.0, 4.5, 8.0])
    for scale in (1.0, 0.9, 0.5, 1.1):
        copy = (BOX - centre) * scale + centre
        assert reconstruction_error(box, uavcov.Terrain(copy, walls), n_samples=4000).inward_area_share == 0.0, scale
        assert reconstruction_error(box, uavcov.Terrain(copy, walls[:, ::-1]), n_samples=4000).inward_area_share == 1.0, scale
    # A 0.8 m slab (a deck) and a thinner slab of S' inside it, 0.2 m in from the deck's top and
    # underside: each face of S' is judged by its normal's way out along its line (0.2 m ahead,
    # 0.6 m behind), not by the nearest real face alone.
    deck = np.array([[0, 0, 10], [40, 0, 10], [40, 8, 10], [0, 8, 10], [0, 0, 10.8], [40, 0, 10.8], [40, 8, 10.8], [0, 8, 10.8]], float)
    ground = np.array([[-20, -20, 0], [60, -20, 0], [60, 30, 0], [-20, 30, 0]], float)
    bridge = Structure(
        "deck",
        uavcov.Terrain(np.vstack([ground, deck]), np.vstack([[[0, 1, 2], [0, 2, 3]], walls + 4])),
        np.array([0, 0] + [1] * 12),
        ("ground", "deck"),
        0,
    )
    inner = np.array([[x, y, z] for z in (10.2, 10.6) for x, y in ((1, 1), (39, 1), (39, 7), (1, 7))], float)
    assert reconstruction_error(bridge, uavcov.Terrain(inner, walls), n_samples=4000).inward_area_share == 0.0
    assert reconstruction_error(bridge, uavcov.Terrain(inner, walls[:, ::-1]), n_samples=4000).inward_area_share == 1.0


DEGENERATE = {
    "identical": np.ones((50, 3)),
    "collinear": np.outer(np.arange(50.0), [1.0, 1.0, 1.0]),
    "coplanar": np.column_stack([np.random.default_rng(0).random((50, 2)) * 10, np.zeros(50)]),
    "tilted plane": np.random.default_rng(1).random((60, 2)) @ np.array([[1.0, 2.0, 3.0], [-2.0, 1.0, 0.5]]),
    "too few": np.random.default_rng(2).random((5, 3)),
    "few distinct": np.repeat(np.random.default_rng(3).random((6, 3)), 10, axis=0),
    "huge": np.random.default_rng(4).random((50, 3)) * 1e300,
}


@pytest.mark.parametrize("method", ["alpha", "hulls", "poisson", "ball_pivoting"])
@pytest.mark.parametrize("name", sorted(DEGENERATE))
def test_every_method_refuses_a_degenerate_prior_before_reconstructing(method: str, name: str) -> None:
    points = DEGENERATE[name]
    # Refused by the shared check, so with or without Open3D installed: never a crash or a
    # foreign exception (Open3D's Poisson segfaulted on the identical points); points beyond
    # the engine's bound already by the prior itself.
    normals = np.tile([0.0, 0.0, 1.0], (points.shape[0], 1))
    with pytest.raises(InvalidInputError, match=r"known points|too sparse|must lie within 1e15 m"):
        reconstruct_structure(StructurePrior(points, normals, "points"), method=method)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_points_or_normals_are_refused(bad: float) -> None:
    points = np.random.default_rng(0).random((50, 3))
    points[7, 1] = bad
    with pytest.raises(InvalidInputError):
        reconstruct_structure(StructurePrior(points, None, "points"))
    normals = np.tile([0.0, 0.0, 1.0], (50, 1))
    normals[3] = [0.0, 0.0, 0.0]
    with pytest.raises(InvalidInputError, match="normals"):
        reconstruct_structure(StructurePrior(np.random.default_rng(0).random((50, 3)), normals, "points"))


@pytest.mark.skipif(not HAS_OPEN3D, reason="Open3D (the reconstruct extra) is not installed")
@pytest.mark.parametrize("method", ["poisson", "ball_pivoting"])
def test_open3d_surfaces_keep_the_outer_shell_wound_outward(method: str) -> None:
    box = issue_box()
    surface = reconstruct_structure(sample_structure_prior(box, 2000, rng=0), method=method)
    error = reconstruction_error(box, surface, n_samples=4000)
    assert error.inward_area_share < 0.05


def test_fly_out_keeps_every_start_outside_and_at_the_standoff() -> None:
    surface = uavcov.Terrain(BOX, np.array(WALLS))
    anchors = np.array([[6.0, 0.0, 8.0], [6.0, 0.0, 8.0], [6.0, 0.0, 8.0]])
    # Outward; into the box with room to come out of its far side; into it with none.
    normals = np.array([[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    # 5 m: out of the far side at 15 m; 2.5 m: no step reaches the standoff, the first outside
    # (10 m, 1 m from the wall) is kept; 1 m: no step leaves the box, lifted over its top.
    for standoff, expected, lift in ((5.0, [6.0, 15.0, 8.0], False), (2.5, [6.0, 10.0, 8.0], False), (1.0, [6.0, 0.0, 17.0], True)):
        positions, lifted = fly_out(surface, anchors[:2], normals[:2], standoff)
        assert np.allclose(positions, [[6.0, -standoff, 8.0], expected])
        assert lifted.tolist() == [False, lift]
        assert not surface.inside(positions).any()
        assert surface.distance(positions[:1])[0] >= standoff - 1e-9
    with pytest.raises(InvalidInputError):
        fly_out(surface, anchors, normals[:2], 1.0)


@pytest.mark.parametrize("family", sorted(STRUCTURE_FAMILIES))
@pytest.mark.parametrize("seed", [0, 1])
def test_families_are_closed_outward_solids_seeded_by_rng(family: str, seed: int) -> None:
    make = STRUCTURE_FAMILIES[family]
    a, b = make(rng=seed), make(rng=seed)
    assert np.array_equal(a.surface.vertices, b.surface.vertices) and np.array_equal(a.surface.faces, b.surface.faces)
    assert not np.array_equal(make(rng=seed + 7).surface.vertices.shape, (0, 3))
    solid = a.surface.faces[a.face_parts != a.ground_part]
    edges = np.concatenate([solid[:, [0, 1]], solid[:, [1, 2]], solid[:, [2, 0]]])
    assert {tuple(e) for e in edges.tolist()} == {tuple(e) for e in edges[:, ::-1].tolist()}
    assert signed_volume(a.surface.vertices, solid) > 0
    # A point well above everything is outside; the targets have outward normals and weights.
    targets = a.targets(spacing=2.0)
    assert len(targets) > 100 and np.all(targets.weights > 0)


def test_a_family_written_to_a_mesh_file_goes_through_the_same_pipeline(tmp_path) -> None:
    trimesh = pytest.importorskip("trimesh")
    building = STRUCTURE_FAMILIES["building"](rng=3)
    solid = building.surface.faces[building.face_parts != building.ground_part]
    path = tmp_path / "building.stl"
    trimesh.Trimesh(building.surface.vertices, solid, process=False).export(path)
    loaded = uavcov.structures.load_structure(path)
    surface = reconstruct_structure(sample_structure_prior(loaded, 100, rng=0), rng=0)
    start = standoff_start(surface, 8, 3.0, rng=0)
    assert not surface.inside(start.positions).any()
    # fly_out's contract: the first step along the normal outside S' at the standoff, else the
    # first outside S' (S''s bottom: flown down, no step gets 3 m from the ground-level faces).
    steps = np.array([1.0, 1.5, 2.0, 3.0, 4.0])[:, None, None]
    trials = start.anchors[None] + steps * 3.0 * start.normals[None]
    outside = ~surface.inside(trials.reshape(-1, 3)).reshape(5, 8)
    clear = outside & (surface.distance(trials.reshape(-1, 3)).reshape(5, 8) >= 3.0 - 1e-9)
    pick = np.where(clear.any(axis=0), clear.argmax(axis=0), outside.argmax(axis=0))
    assert np.allclose(start.positions, trials[pick, np.arange(8)])
    assert "structure" in loaded.part_names and loaded.surface.n_faces > solid.shape[0]


def test_fly_out_stays_over_the_ground_and_out_of_what_the_known_points_put_inside() -> None:
    # A box S' standing on the ground at z = 0: a generator on its bottom is flown down; with the
    # floor it is raised to the standoff over the ground instead (and, under the box, is inside
    # S' there, so it is flown on or lifted); keep_out marks a slab beside the box as solid.
    surface = uavcov.Terrain(BOX, np.array(WALLS))
    anchors = np.array([[11.9, 4.5, 0.0], [12.0, 4.5, 8.0], [6.0, 9.0, 8.0]])
    normals = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    free, _ = fly_out(surface, anchors, normals, 2.0)
    assert free[0, 2] < 0.0  # without the floor: under the ground
    positions, _ = fly_out(surface, anchors, normals, 2.0, floor=0.0)
    assert (positions[:, 2] >= 2.0 - 1e-12).all() and not surface.inside(positions).any()
    assert np.allclose(positions[1:], [[14.0, 4.5, 8.0], [6.0, 11.0, 8.0]])

    def slab(points: np.ndarray) -> np.ndarray:
        return np.asarray((points[:, 0] > 12.5) & (points[:, 0] < 15.5), dtype=bool)

    kept, _ = fly_out(surface, anchors, normals, 2.0, floor=0.0, keep_out=slab)
    assert not slab(kept).any() and np.allclose(kept[1], [16.0, 4.5, 8.0])  # 2 standoffs out: past the slab
    with pytest.raises(InvalidInputError, match="keep_out"):
        fly_out(surface, anchors, normals, 2.0, keep_out=lambda p: np.zeros(len(p)))  # not bool
    with pytest.raises(InvalidInputError):
        fly_out(surface, anchors, normals, 2.0, floor=float("nan"))


def test_the_known_points_vote_inside_the_box_and_not_outside() -> None:
    prior = sample_structure_prior(issue_box(), 100, rng=0)
    inside = prior.behind([[6.0, 4.5, 8.0], [1.0, 1.0, 1.0], [11.0, 8.0, 15.0]])
    outside = prior.behind([[6.0, 4.5, 20.0], [-3.0, 4.5, 8.0], [6.0, 12.0, 8.0], [15.0, 12.0, 18.0]])
    assert inside.all() and not outside.any()
    assert prior.behind(np.empty((0, 3))).shape == (0,)
    bare = StructurePrior(prior.points, None, "points")
    assert not bare.behind([[6.0, 4.5, 8.0]]).any()  # no normals, no evidence
    with pytest.raises(InvalidInputError):
        prior.behind([[np.nan, 0.0, 0.0]])


def test_the_vote_within_a_reach_judges_only_points_near_the_known_ones() -> None:
    prior = sample_structure_prior(issue_box(), 100, rng=0)
    centre, near_wall = [6.0, 4.5, 8.0], prior.points[0] - 0.3 * prior.normals[0]
    distance = np.linalg.norm(prior.points - centre, axis=1).min()
    assert distance > 2.0  # the box's middle is metres from every known point
    assert prior.behind([centre, near_wall]).tolist() == [True, True]
    assert prior.behind([centre, near_wall], reach=distance - 0.1).tolist() == [False, True]
    assert prior.behind([centre, near_wall], reach=distance + 0.1).tolist() == [True, True]
    assert prior.behind([centre], reach=0.0).tolist() == [False]
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(InvalidInputError, match="reach"):
            prior.behind([centre], reach=bad)


def test_spacing_is_the_median_distance_to_the_nearest_other_known_point() -> None:
    grid = np.array([[2.0 * i, 3.0 * j, 0.0] for i in range(4) for j in range(3)])  # nearest: 2 m
    assert StructurePrior(grid, None, "points").spacing == pytest.approx(2.0)
    lonely = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [10.0, 0.0, 0.0]])  # 1, 1, 9
    assert StructurePrior(lonely, None, "points").spacing == pytest.approx(1.0)
    assert StructurePrior(np.zeros((5, 3)), None, "points").spacing == 0.0  # one distinct point


def test_the_cvt_start_takes_the_vote_near_the_known_points_and_greedy_everywhere(monkeypatch) -> None:
    import uavcov.mission
    from uavcov.mission import _keep_out

    # One spacing, so that the box's middle is out of reach (the library's reach holds it).
    spacings = 1.0
    monkeypatch.setattr(uavcov.mission, "CVT_KEEP_OUT_SPACINGS", spacings)
    prior = sample_structure_prior(issue_box(), 100, rng=0)
    queries = np.random.default_rng(1).uniform([-5.0, -5.0, 0.0], [17.0, 14.0, 20.0], (2000, 3))
    greedy, cvt_start = _keep_out(prior, "greedy"), _keep_out(prior, "cvt")
    assert greedy is not None and cvt_start is not None
    near = np.linalg.norm(queries[:, None] - prior.points[None], axis=2).min(axis=1) <= spacings * prior.spacing
    assert np.array_equal(greedy(queries), prior.behind(queries))
    assert np.array_equal(cvt_start(queries), prior.behind(queries) & near)
    assert (greedy(queries) & ~near).any()  # the reach matters on these queries
    assert _keep_out(StructurePrior(prior.points, None, "points"), "cvt") is None  # no normals, no vote
    assert _keep_out(None, "cvt") is None


@pytest.mark.parametrize("family", sorted(STRUCTURE_FAMILIES))
def test_the_3d_start_stays_out_of_the_real_structure_on_development_seeds(family: str) -> None:
    # The mission's own start (CVT on S', flown out with the floor and the known points' vote),
    # on development seeds only, judged against the real structure it does not know.
    from uavcov.limits import Constraints
    from uavcov.mission import _keep_out
    from uavcov.placement import StartSettings, start_configuration

    for seed in (1000, 1001):
        structure = STRUCTURE_FAMILIES[family](rng=seed)
        prior = sample_structure_prior(structure, 100, rng=seed)
        surface = reconstruct_structure(prior, rng=seed)
        spec = StartSettings(kind="cvt", altitude=3.0, altitude_reference="normal")
        limits = Constraints(clearance="standoff", h_min=2.0, check_moves=True)
        keep_out = _keep_out(prior, "cvt")  # the mission's
        positions, _ = start_configuration(spec, surface, structure.surface, 8, rng=seed, constraints=limits, keep_out=keep_out)
        assert not structure.surface.inside(positions).any(), (family, seed)
        assert (positions[:, 2] >= structure.surface.bounds[0, 2] + 3.0 - 1e-9).all()


def _two_boxes_with_a_gap(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Points with outward normals on two 10 m cubes 4 m apart along x (8 on each face)."""
    generator = np.random.default_rng(seed)
    points, normals = [], []
    for lo, hi in (((0.0, 0.0, 0.0), (10.0, 10.0, 10.0)), ((14.0, 0.0, 0.0), (24.0, 10.0, 10.0))):
        for axis in range(3):
            for side, level in ((-1.0, lo[axis]), (1.0, hi[axis])):
                face = generator.uniform(lo, hi, (8, 3))
                face[:, axis] = level
                normal = np.zeros((8, 3))
                normal[:, axis] = side
                points.append(face)
                normals.append(normal)
    return np.concatenate(points), np.concatenate(normals)


@pytest.mark.parametrize("seed", range(3))
def test_tetrahedra_marked_free_stay_outside_and_the_boundary_stays_closed_and_outward(seed: int) -> None:
    from scipy.spatial import Delaunay

    from uavcov.structures._outer_surface import _boundary, oriented_labels, oriented_solid

    points, normals = _two_boxes_with_a_gap(seed)
    points, first = np.unique(points, axis=0, return_index=True)  # oriented_solid's own order
    normals = normals[first]
    triangulation = Delaunay(points)
    tetra, neighbours = triangulation.simplices, triangulation.neighbors
    gap = np.array([[12.0, y, z] for y in np.linspace(1, 9, 5) for z in np.linspace(1, 9, 5)])
    # Without a mask, the labels are oriented_solid's; the vote and its fill bridge the 4 m gap
    # (issue 42: S' spanning the air between two parts).
    plain = oriented_labels(points, normals, tetra, neighbours)
    vertices, faces = oriented_solid(points, normals)
    assert np.array_equal(
        np.sort(np.sort(faces, axis=1), axis=0), np.sort(np.sort(_boundary(points, tetra, neighbours, plain), axis=1), axis=0)
    )
    assert uavcov.Terrain(vertices, faces, drop_degenerate=True).inside(gap).all()
    # The tetrahedra between the facing walls (corners on both, none elsewhere) marked free: none
    # is inside, the fill does not grow into them, and the boundary is closed and outward.
    on_wall = np.isin(points[:, 0], (10.0, 14.0))
    x = points[tetra, 0]
    free = on_wall[tetra].all(axis=1) & (x == 10.0).any(axis=1) & (x == 14.0).any(axis=1)
    assert free.any()
    solid = oriented_labels(points, normals, tetra, neighbours, free)
    assert not solid[free].any()
    carved = _boundary(points, tetra, neighbours, solid)
    edges = np.concatenate([carved[:, [0, 1]], carved[:, [1, 2]], carved[:, [2, 0]]])
    assert {tuple(e) for e in edges.tolist()} == {tuple(e) for e in edges[:, ::-1].tolist()}
    assert signed_volume(points, carved) > 0.5 * 2 * 10**3
    surface = uavcov.Terrain(points, carved, drop_degenerate=True)
    assert not surface.inside(points[tetra[free]].mean(axis=1)).any()
    assert surface.inside(gap).sum() < gap.shape[0]


def _box_points(lo, hi, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` points with outward normals on each face of the box ``lo``-``hi``."""
    generator = np.random.default_rng(seed)
    points, normals = [], []
    for axis in range(3):
        for side, level in ((-1.0, lo[axis]), (1.0, hi[axis])):
            face = generator.uniform(lo, hi, (n, 3))
            face[:, axis] = level
            normal = np.zeros((n, 3))
            normal[:, axis] = side
            points.append(face)
            normals.append(normal)
    return np.concatenate(points), np.concatenate(normals)


@pytest.mark.parametrize("gap, groups", [(300.0, 2), (4.0, 1)])
def test_structures_far_apart_are_reconstructed_apart(gap: float, groups: int) -> None:
    from uavcov.structures._outer_surface import separate_groups

    a, na = _box_points((0.0, 0.0, 0.0), (10.0, 10.0, 10.0), 8, 0)
    b, nb = _box_points((10.0 + gap, 0.0, 0.0), (20.0 + gap, 10.0, 10.0), 8, 1)
    prior = StructurePrior(np.vstack([a, b]), np.vstack([na, nb]), "points")
    assert len(separate_groups(prior.points, prior.spacing)) == groups
    surface = reconstruct_structure(prior, margin=0.0)
    # Apart, S' is the two boxes (1000 m^3 each, up to their sampled corners); together, one
    # solid spanning the gap.
    volume = signed_volume(surface.vertices, surface.faces)
    assert (volume < 2000.0 + 1e-6) if groups == 2 else (volume > 2000.0)
    lonely = StructurePrior(np.vstack([a, b[:5]]), np.vstack([na, nb[:5]]), "points")  # 5 points: too few alone
    assert len(separate_groups(lonely.points, lonely.spacing)) == 1


def test_groups_of_points_spread_beyond_any_grid_are_kept_together() -> None:
    from uavcov.structures._outer_surface import separate_groups

    # Pairs 1e-9 m apart at coordinates up to 1e14 m: 15 spacings is a cell of 1.5e-8 m, whose
    # keys would overflow; such points are not split (no warning, no error).
    base = np.random.default_rng(0).uniform(-1e14, 1e14, (30, 3))
    points = np.vstack([base, base + 1e-9])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(separate_groups(points, 1e-9)) == 1
