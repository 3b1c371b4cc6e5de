"""Structure scenes and mesh files as structures (uavcov.structures), against trimesh and an
independent winding-number inside test."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from uavcov.errors import InvalidInputError, InvalidTypeError, MeshError
from uavcov.structures import STRUCTURE_SCENES, Structure, StructureTargets, girder_bridge, height_field_violation, load_structure

SCENES = sorted(STRUCTURE_SCENES)


@pytest.fixture(scope="module", params=SCENES)
def scene(request: pytest.FixtureRequest) -> Structure:
    return STRUCTURE_SCENES[request.param](rng=3)


def components(structure: Structure) -> list[np.ndarray]:
    """Solid components by union-find over shared vertices (independent of the library's)."""
    faces = structure.surface.faces
    solid = np.nonzero(structure.face_parts != structure.ground_part)[0]
    parent = np.arange(structure.surface.n_vertices)

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b, c in faces[solid]:
        for u, v in ((a, b), (b, c)):
            ru, rv = find(u), find(v)
            if ru != rv:
                parent[ru] = rv
    roots = np.array([find(int(f[0])) for f in faces[solid]])
    return [solid[roots == r] for r in np.unique(roots)]


def winding_number(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Generalised winding number of a closed mesh at each point (1 inside, 0 outside), by the
    solid angles of its triangles (Van Oosterom and Strackee)."""
    total = np.zeros(points.shape[0])
    for start in range(0, faces.shape[0], 2000):
        tri = vertices[faces[start : start + 2000]]
        a = tri[None, :, 0, :] - points[:, None, :]
        b = tri[None, :, 1, :] - points[:, None, :]
        c = tri[None, :, 2, :] - points[:, None, :]
        la, lb, lc = (np.linalg.norm(q, axis=2) for q in (a, b, c))
        det = np.einsum("pfi,pfi->pf", a, np.cross(b, c))
        den = la * lb * lc + np.einsum("pfi,pfi->pf", a, b) * lc + np.einsum("pfi,pfi->pf", b, c) * la + np.einsum("pfi,pfi->pf", c, a) * lb
        total += 2.0 * np.arctan2(det, den).sum(axis=1)
    return total / (4.0 * np.pi)


def test_scene_size_parts_and_not_a_height_field(scene: Structure) -> None:
    assert 1_000 <= scene.surface.n_faces <= 100_000
    assert scene.part_names[scene.ground_part] == "ground"
    double_hit, downward = height_field_violation(scene)
    assert double_hit > 0.02, scene.name
    assert downward > 0.005, scene.name
    assert len(set(scene.face_parts.tolist())) == len(scene.part_names)


def test_scene_solids_are_closed_outward_and_do_not_interpenetrate(scene: Structure) -> None:
    trimesh = pytest.importorskip("trimesh")
    vertices, faces = scene.surface.vertices, scene.surface.faces
    parts = components(scene)
    boxes = []
    for component in parts:
        mesh = trimesh.Trimesh(vertices, faces[component], process=True)
        assert mesh.is_watertight and mesh.is_winding_consistent, scene.name
        assert mesh.volume > 0, scene.name  # outward: positive enclosed volume
        boxes.append((vertices[faces[component]].reshape(-1, 3).min(axis=0), vertices[faces[component]].reshape(-1, 3).max(axis=0)))
    for i, a in enumerate(parts):
        # Just inside solid a, under each face's centroid: outside every other solid unless they cut into each other.
        tri = vertices[faces[a]]
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        probes = tri.mean(axis=1) - 1e-3 * normal / np.linalg.norm(normal, axis=1)[:, None]
        for j, b in enumerate(parts):
            if i == j or (boxes[i][1] < boxes[j][0]).any() or (boxes[j][1] < boxes[i][0]).any():
                continue
            assert winding_number(probes, vertices, faces[b]).max() < 0.5, (scene.name, i, j)


def test_targets_are_area_weighted_outward_and_labelled(scene: Structure) -> None:
    targets = scene.targets(spacing=1.0)
    assert isinstance(targets, StructureTargets)
    mask = scene.face_mask()
    contact = scene.surface.face_areas[scene.face_parts == scene.part_names.index("contact")].sum()
    assert 0.95 * (scene.surface.face_areas[mask].sum() - contact) <= targets.total_weight <= scene.surface.face_areas[mask].sum()
    assert np.allclose(np.linalg.norm(targets.normals, axis=1), 1.0)
    assert scene.ground_part not in targets.parts and "contact" not in [scene.part_names[p] for p in np.unique(targets.parts)]
    with_ground = scene.targets(spacing=1.0, include_ground=True)
    ground = scene.surface.face_areas[scene.face_parts == scene.ground_part].sum()
    # Pieces straddling a contact's edge go whole one way or the other: allow a few per cent.
    assert 0.95 * (ground - contact) <= with_ground.total_weight - targets.total_weight <= ground
    # Outward: a point 2 cm out along the normal is in no solid, 2 cm in is in exactly one.
    pick = np.random.default_rng(0).choice(len(targets), 150, replace=False)
    out = targets.points[pick] + 0.02 * targets.normals[pick]
    inner = targets.points[pick] - 0.02 * targets.normals[pick]
    solids = scene.surface.faces[scene.face_parts != scene.ground_part]
    assert np.all(np.abs(winding_number(out, scene.surface.vertices, solids)) < 0.1), scene.name
    assert np.all(np.abs(winding_number(inner, scene.surface.vertices, solids) - 1.0) < 0.1), scene.name


def test_scenes_are_seeded() -> None:
    for make in STRUCTURE_SCENES.values():
        a, b, c = make(rng=5), make(rng=5), make(rng=6)
        assert np.array_equal(a.surface.vertices, b.surface.vertices) and np.array_equal(a.face_parts, b.face_parts)
        assert not np.array_equal(a.surface.vertices, c.surface.vertices)


def test_girder_bridge_parts_face_their_way_and_coverage_by_part() -> None:
    bridge = girder_bridge(rng=0)
    targets = bridge.targets(spacing=1.0)
    names = bridge.part_names
    under = targets.parts == names.index("deck_underside")
    top = targets.parts == names.index("deck_top")
    assert np.allclose(targets.normals[under], [0, 0, -1]) and np.allclose(targets.normals[top], [0, 0, 1])
    assert 10.0 <= targets.points[top, 2].min() <= 11.0 + 1e-9
    shares = bridge.coverage_by_part(top, targets)
    assert shares["deck_top"] == 1.0 and shares["deck_underside"] == 0.0 and shares["piers"] == 0.0
    assert set(shares) == {names[p] for p in np.unique(targets.parts)}
    assert all(v == 1.0 for v in bridge.coverage_by_part(np.ones(len(targets), bool), targets).values())
    with pytest.raises(InvalidInputError):
        bridge.coverage_by_part(np.ones(3, bool), targets)
    with pytest.raises(InvalidTypeError):
        bridge.coverage_by_part(top, bridge.surface.default_targets())
    restored = pickle.loads(pickle.dumps(targets))
    assert isinstance(restored, StructureTargets) and np.array_equal(restored.parts, targets.parts)
    again = pickle.loads(pickle.dumps(bridge))
    assert np.array_equal(again.face_parts, bridge.face_parts) and again.part_names == names
    with pytest.raises(InvalidInputError):
        bridge.targets(spacing=1e-6)
    with pytest.raises(InvalidInputError):
        bridge.targets(spacing=float("nan"))


# --------------------------------------------------------------------------------------------
# Mesh files


def unit_box(trimesh_module):
    return trimesh_module.creation.box(extents=(4.0, 2.0, 3.0))


@pytest.mark.parametrize(
    "suffix,file_type",
    [("stl", "stl"), ("stl", "stl_ascii"), ("obj", "obj"), ("ply", "ply"), ("ply", "ply_ascii")],
)
def test_mesh_files_load_as_structures(tmp_path, suffix: str, file_type: str) -> None:
    trimesh = pytest.importorskip("trimesh")
    box = unit_box(trimesh)
    path = tmp_path / f"box.{suffix}"
    if file_type == "ply_ascii":
        path.write_bytes(trimesh.exchange.ply.export_ply(box, encoding="ascii"))
    else:
        box.export(path, file_type=file_type)
    structure = load_structure(path)
    assert set(structure.part_names) == {"ground", "structure", "contact"}
    visible = structure.surface.face_areas[structure.face_mask()].sum()
    assert visible == pytest.approx(2 * (4 * 2 + 4 * 3 + 2 * 3) - 4 * 2, rel=1e-6)  # the bottom touches the ground
    assert height_field_violation(structure) == (0.0, 0.0)  # a box on the ground is a height field
    inverted = tmp_path / f"inverted.{suffix}"
    trimesh.Trimesh(box.vertices, box.faces[:, ::-1], process=False).export(inverted, file_type="stl" if suffix == "stl" else suffix)
    flipped = load_structure(inverted)
    targets = flipped.targets(spacing=0.5)
    centre = (
        flipped.surface.vertices[flipped.surface.faces[flipped.face_parts == flipped.part_names.index("structure")]]
        .reshape(-1, 3)
        .mean(axis=0)
    )
    assert np.all(np.einsum("ij,ij->i", targets.points - centre, targets.normals) > 0)  # turned outward


def test_a_mesh_file_keeps_the_origin_it_is_given(tmp_path) -> None:
    trimesh = pytest.importorskip("trimesh")
    box = unit_box(trimesh)  # 4 m x 2 m x 3 m about its centre
    box.apply_translation([512002.0, 4180001.0, 121.5])  # UTM-like, its base at 120 m
    path = tmp_path / "block.stl"
    box.export(path)
    default = load_structure(path)  # the file's minimum corner is (0, 0, 0)
    corner = np.array([512000.0, 4180000.0, 120.0])
    np.testing.assert_array_equal(load_structure(path, origin=corner).surface.vertices, default.surface.vertices)
    site = np.array([511990.0, 4179980.0, 100.0])
    moved = load_structure(path, origin=site)  # local = file - origin: the block 10, 20, 20 m off the site
    np.testing.assert_allclose(moved.surface.vertices, default.surface.vertices + (corner - site), atol=1e-9)
    kept = load_structure(path, origin=(0.0, 0.0, 0.0))  # the file's own coordinates
    structure_faces = kept.surface.faces[kept.face_parts == kept.part_index("structure")]
    np.testing.assert_allclose(kept.surface.vertices[structure_faces].reshape(-1, 3).min(axis=0), corner)
    for origin, error, words in [
        ((float("nan"), 0.0, 0.0), InvalidInputError, "NaN"),
        ((0.0, 0.0, float("inf")), InvalidInputError, "infinite"),
        ((1.0, 2.0), InvalidInputError, "triple"),
        ([[0.0, 0.0, 0.0]], InvalidInputError, "1-dimensional"),
        ("corner", InvalidTypeError, "numeric"),
        ((1e300, 0.0, 0.0), InvalidInputError, "within 1e15 m"),
    ]:
        with pytest.raises(error, match=words):
            load_structure(path, origin=origin)


def test_broken_mesh_files_are_clear_errors(tmp_path) -> None:
    trimesh = pytest.importorskip("trimesh")
    box = unit_box(trimesh)
    corrupt = tmp_path / "corrupt.stl"
    corrupt.write_bytes(b"solid \x00\xff" + bytes(range(256)) * 3)
    empty = tmp_path / "empty.ply"
    empty.write_bytes(b"")
    nan = tmp_path / "nan.obj"
    nan.write_text("v nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n")
    open_box = tmp_path / "open.stl"
    trimesh.Trimesh(box.vertices, box.faces[:-1], process=False).export(open_box)
    nonmanifold = tmp_path / "fin.obj"
    fin = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]], dtype=float)
    trimesh.Trimesh(fin, [[0, 1, 2], [1, 0, 3], [0, 1, 4]], process=False).export(nonmanifold)
    huge = tmp_path / "huge.stl"
    trimesh.Trimesh(box.vertices * 1e7, box.faces, process=False).export(huge)
    twisted = tmp_path / "twisted.ply"
    faces = box.faces.copy()
    faces[0] = faces[0, ::-1]
    trimesh.Trimesh(box.vertices, faces, process=False).export(twisted)
    cases = {
        corrupt: "",
        empty: "empty",
        nan: "",
        open_box: "not a closed solid",
        nonmanifold: "not a closed solid",
        huge: "max_extent",
        twisted: "winding",
        tmp_path / "missing.stl": "does not exist",
        tmp_path: "directory",
    }
    for path, words in cases.items():
        with pytest.raises(MeshError, match=words or None):
            load_structure(path)
    assert load_structure(open_box, closed=False).surface.n_faces > 0
    with pytest.raises(MeshError, match="max_faces"):
        load_structure(tmp_path / "huge.stl", max_faces=5)
    with pytest.raises(InvalidTypeError):
        load_structure(3)
    with pytest.raises(InvalidTypeError):
        height_field_violation(box)


def test_cvt_runs_on_a_structure() -> None:
    from uavcov.placement import cvt

    bridge = girder_bridge(rng=1)
    result = cvt(bridge.surface, 6, rng=0, n_threads=1)
    on_surface = bridge.surface.closest_point(result.generators)
    assert np.allclose(on_surface, result.generators, atol=1e-6)


def test_a_structure_where_a_terrain_is_taken_is_refused_with_what_to_give() -> None:
    """The first mix-up of a structure's user: the Structure itself where its mesh is taken."""
    from uavcov import Visibility
    from uavcov.placement import cvt
    from uavcov.terrain import sample_prior

    bridge = girder_bridge(rng=1)
    calls = {
        "Visibility": lambda thing: Visibility(thing, d_max=10.0),
        "cvt": lambda thing: cvt(thing, 3, rng=0),
        "sample_prior": lambda thing: sample_prior(thing, 5, rng=0),
    }
    for name, call in calls.items():
        with pytest.raises(InvalidTypeError, match=r"got Structure \(a structure's mesh is its \.surface") as refused:
            call(bridge)
        assert isinstance(refused.value, TypeError), name
        for other in (bridge.surface.vertices, "bridge.stl", None):  # not a structure: no hint
            with pytest.raises(InvalidTypeError, match=r"must be a uavcov Terrain, got \w+$"):
                call(other)
    Visibility(bridge.surface, 10.0, targets=bridge.targets(spacing=2.0))  # what it says to give works
