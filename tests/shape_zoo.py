"""Structures no one on the project designed, built here with numpy alone, and brute-force
references to judge missions on them.

The shapes do not use the project's generators (``uavcov.structures._solids``): every mesh is
made here from its definition, closed solids wound outward by their own signed volume (except
where a kind is about bad winding, open edges, duplicates or non-manifold edges on purpose).
``tests/shape_checks.py`` judges missions on them by references of its own;
``tests/test_unseen_shapes.py`` asserts on small cases; ``scripts/unseen_shapes.py`` runs the
README's structure settings on every kind and prints a table.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

Mesh = tuple[np.ndarray, np.ndarray]  # (V, 3) float64 vertices, (F, 3) int64 faces

# ---------------------------------------------------------------------------------------------
# building blocks
# ---------------------------------------------------------------------------------------------


def signed_volume(v: np.ndarray, f: np.ndarray) -> float:
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def outward(mesh: Mesh) -> Mesh:
    """The closed mesh with its faces reversed if it encloses a negative volume."""
    v, f = mesh
    return (v, f) if signed_volume(v, f) > 0 else (v, f[:, ::-1].copy())


def box(lo, hi) -> Mesh:
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    faces = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.int64)
    return outward((lo + corners * (hi - lo), faces))


def grid_quads(rows: int, cols: int, wrap_cols: bool, wrap_rows: bool) -> np.ndarray:
    """Two triangles per cell of a ``rows x cols`` vertex lattice (index ``r * cols + c``)."""
    out = []
    for r in range(rows if wrap_rows else rows - 1):
        for c in range(cols if wrap_cols else cols - 1):
            a, b = r * cols + c, r * cols + (c + 1) % cols
            d, e = ((r + 1) % rows) * cols + c, ((r + 1) % rows) * cols + (c + 1) % cols
            out += [(a, b, e), (a, e, d)]
    return np.array(out, np.int64)


def revolve(profile: np.ndarray, sides: int, centre=(0.0, 0.0, 0.0)) -> Mesh:
    """A closed solid of revolution about the z axis: ``profile`` a closed loop of (r > 0, z)."""
    theta = 2 * np.pi * np.arange(sides) / sides
    r, z = profile[:, 0], profile[:, 1]
    v = np.column_stack([np.outer(r, np.cos(theta)).ravel(), np.outer(r, np.sin(theta)).ravel(), np.repeat(z, sides)])
    return outward((v + np.asarray(centre, float), grid_quads(len(profile), sides, True, True)))


def dome(radius: float, rings: int, sides: int, centre=(0.0, 0.0, 0.0)) -> Mesh:
    """A closed hemisphere standing on its flat disc (z from 0 to ``radius``)."""
    phi = np.linspace(0.0, np.pi / 2, rings + 1)[:-1]  # elevation of each ring, the equator first
    theta = 2 * np.pi * np.arange(sides) / sides
    ring = np.column_stack(
        [np.outer(np.cos(phi), np.cos(theta)).ravel(), np.outer(np.cos(phi), np.sin(theta)).ravel(), np.repeat(np.sin(phi), sides)]
    )
    v = np.vstack([radius * ring, [[0, 0, radius], [0, 0, 0]]])
    top, bottom = len(v) - 2, len(v) - 1
    f = [grid_quads(rings, sides, True, False)]
    last = (rings - 1) * sides
    f.append(np.array([(last + k, last + (k + 1) % sides, top) for k in range(sides)], np.int64))
    f.append(np.array([((k + 1) % sides, k, bottom) for k in range(sides)], np.int64))
    return outward((v + np.asarray(centre, float), np.vstack(f)))


def torus(major: float, minor: float, sides: int, rings: int) -> Mesh:
    """A torus about the z axis, centred at the origin."""
    a = 2 * np.pi * np.arange(rings) / rings
    profile = np.column_stack([major + minor * np.cos(a), minor * np.sin(a)])
    return revolve(profile, sides)


def prism(mask: np.ndarray, cell: float, height: float, z0: float = 0.0) -> Mesh:
    """The cells of a boolean ``(nx, ny)`` footprint extruded from ``z0`` to ``z0 + height``
    (cells touching only at a corner are not allowed: they would make a non-manifold edge)."""
    nx, ny = mask.shape
    index = lambda i, j, k: (k * (nx + 1) + i) * (ny + 1) + j  # noqa: E731
    faces = []
    for i in range(nx):
        for j in range(ny):
            if not mask[i, j]:
                continue
            for k in (0, 1):
                q = [index(i, j, k), index(i + 1, j, k), index(i + 1, j + 1, k), index(i, j + 1, k)]
                faces += [(q[0], q[1], q[2]), (q[0], q[2], q[3])] if k else [(q[0], q[2], q[1]), (q[0], q[3], q[2])]
            for di, dj, e in (
                (-1, 0, (i, j, i, j + 1)),
                (1, 0, (i + 1, j + 1, i + 1, j)),
                (0, -1, (i + 1, j, i, j)),
                (0, 1, (i, j + 1, i + 1, j + 1)),
            ):
                n = (i + di, j + dj)
                if 0 <= n[0] < nx and 0 <= n[1] < ny and mask[n]:
                    continue
                a, b = index(e[0], e[1], 0), index(e[2], e[3], 0)
                c, d = index(e[2], e[3], 1), index(e[0], e[1], 1)
                faces += [(a, c, b), (a, d, c)]
    k, i, j = np.meshgrid(np.arange(2), np.arange(nx + 1), np.arange(ny + 1), indexing="ij")
    v = np.column_stack([i.ravel() * cell, j.ravel() * cell, z0 + k.ravel() * height]).astype(float)
    return compact(outward((v, np.array(faces, np.int64))))


def compact(mesh: Mesh) -> Mesh:
    """The mesh without unreferenced vertices."""
    v, f = mesh
    used, inverse = np.unique(f, return_inverse=True)
    return v[used], inverse.reshape(f.shape)


def beam(a, b, width: float) -> Mesh:
    """A closed square-section bar from ``a`` to ``b`` (a guy wire, a strut)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    axis = (b - a) / np.linalg.norm(b - a)
    u = np.cross(axis, [0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(axis, u)
    square = np.array([u + w, -u + w, -u - w, u - w]) * width / 2
    v = np.vstack([a + square, b + square])
    quads = [(0, 1, 2, 3), (4, 7, 6, 5)] + [(k, 4 + k, 4 + (k + 1) % 4, (k + 1) % 4) for k in range(4)]
    return outward((v, np.array([t for p, q, r, s in quads for t in ((p, q, r), (p, r, s))], np.int64)))


def transform(mesh: Mesh, rotation=None, shift=(0.0, 0.0, 0.0)) -> Mesh:
    v, f = mesh
    v = v if rotation is None else v @ np.asarray(rotation, float).T
    return v + np.asarray(shift, float), f


def rest(mesh: Mesh) -> Mesh:
    """The mesh moved up or down to touch z = 0 with its lowest vertex."""
    v, f = mesh
    return v - [0.0, 0.0, v[:, 2].min()], f


def union(*meshes: Mesh) -> Mesh:
    """The meshes side by side in one (no welding: they may touch or overlap)."""
    vs, fs, offset = [], [], 0
    for v, f in meshes:
        vs.append(v)
        fs.append(f + offset)
        offset += len(v)
    return np.vstack(vs), np.vstack(fs)


def weld(mesh: Mesh, tolerance: float = 1e-9) -> Mesh:
    """Merge coincident vertices (as an exporter that shares vertices would)."""
    v, f = mesh
    key = np.round(v / tolerance).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return v[first], inverse.reshape(-1)[f]


# ---------------------------------------------------------------------------------------------
# the kinds
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Shape:
    """One unseen structure: its solid mesh (no ground) and what the checks may expect of it."""

    kind: str
    seed: int
    vertices: np.ndarray
    faces: np.ndarray
    closed: bool = True  # closed solids: "inside" is meaningful
    ground_z: float = 0.0
    millimetres: bool = False  # its mesh file is written in millimetres (read with scale=0.001)
    # The ground as_structure puts under it (tests/shape_zoo2.py): "sheet" a flat sheet round it,
    # "mesh" the given ``ground`` (a hillside, a valley), "none" no ground at all, "small" a
    # sheet under the middle of the structure only.
    ground: Mesh | None = None
    ground_mode: str = "sheet"


def _rotation_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]], float)


def _rotation_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]], float)


def k_dome(g):
    r = g.uniform(6.0, 14.0)
    return dome(r, int(g.integers(5, 10)), int(g.integers(12, 28)))


def k_torus_flat(g):
    major, minor = g.uniform(6.0, 12.0), g.uniform(1.0, 2.5)
    return rest(torus(major, minor, int(g.integers(16, 32)), 12))


def k_torus_standing(g):
    major, minor = g.uniform(5.0, 10.0), g.uniform(0.8, 2.0)
    return rest(transform(torus(major, minor, int(g.integers(16, 32)), 12), _rotation_x(np.pi / 2)))


def k_stadium(g):
    r_in, wall, h = g.uniform(15.0, 25.0), g.uniform(4.0, 8.0), g.uniform(6.0, 12.0)
    profile = np.array([[r_in, 0.0], [r_in + wall, 0.0], [r_in + wall, h], [r_in + 0.6 * wall, h]])  # stands sloping in
    return revolve(profile, int(g.integers(24, 40)))


def _footprint(g, kind: str) -> np.ndarray:
    a, b = int(g.integers(5, 9)), int(g.integers(5, 9))
    mask = np.zeros((a, b), bool)
    arm = int(g.integers(2, 3 + min(a, b) // 3))
    if kind == "L":
        mask[:arm, :] = True
        mask[:, :arm] = True
    elif kind == "U":
        mask[:arm, :] = True
        mask[-arm:, :] = True
        mask[:, :arm] = True
    else:  # a courtyard: a ring of cells
        mask[:] = True
        mask[arm:-arm, arm:-arm] = False
        if not (~mask).any():
            mask[a // 2, b // 2] = False
    return mask


def k_l_building(g):
    return prism(_footprint(g, "L"), g.uniform(2.0, 4.0), g.uniform(6.0, 20.0))


def k_u_building(g):
    return prism(_footprint(g, "U"), g.uniform(2.0, 4.0), g.uniform(6.0, 15.0))


def k_courtyard(g):
    return prism(_footprint(g, "O"), g.uniform(2.5, 4.0), g.uniform(6.0, 15.0))


def k_thin_wall(g):
    length, h = g.uniform(10.0, 30.0), g.uniform(3.0, 8.0)
    return transform(box((0, 0, 0), (length, 0.2, h)), _rotation_z(g.uniform(0, np.pi)))


def k_sign_on_pole(g):
    h, arm = g.uniform(5.0, 9.0), g.uniform(2.0, 4.0)
    pole = box((-0.15, -0.15, 0.0), (0.15, 0.15, h))
    sign = box((0.0, -0.1, h - 1.5), (arm, 0.1, h - 0.2))  # cantilevered: overlaps the pole's half
    return union(pole, sign)


def k_chimney(g):
    r_out, wall, h = g.uniform(2.0, 6.0), g.uniform(0.3, 0.8), g.uniform(15.0, 30.0)
    profile = np.array([[r_out - wall, 0.0], [r_out, 0.0], [r_out, h], [r_out - wall, h]])
    return revolve(profile, int(g.integers(16, 32)))


def k_overlapping_boxes(g):
    a = box((0, 0, 0), (g.uniform(14, 20), g.uniform(10, 16), g.uniform(6, 12)))
    b = box((g.uniform(4, 7), g.uniform(2, 4), 0), (g.uniform(22, 28), g.uniform(18, 24), g.uniform(7, 14)))
    return union(a, b)


def k_guyed_mast(g):
    h = g.uniform(25.0, 40.0)
    parts = [box((-0.25, -0.25, 0.0), (0.25, 0.25, h))]
    for k in range(3):
        angle = 2 * np.pi * k / 3 + g.uniform(0, 0.5)
        reach = g.uniform(0.5, 0.7) * h
        anchor = (reach * np.cos(angle), reach * np.sin(angle), 0.04)  # the wire's corners just clear the ground
        parts.append(beam((0.0, 0.0, 0.8 * h), anchor, 0.06))
    return union(*parts)


def k_long_bridge(g):
    span, clearance = g.uniform(60.0, 120.0), g.uniform(1.0, 2.5)
    deck = box((0.0, -3.0, clearance), (span, 3.0, clearance + 0.8))
    left = box((-4.0, -3.0, 0.0), (0.0, 3.0, clearance + 0.8))
    right = box((span, -3.0, 0.0), (span + 4.0, 3.0, clearance + 0.8))
    return union(deck, left, right)


def k_far_from_origin(g):
    mesh = prism(_footprint(g, "L"), 3.0, g.uniform(8.0, 16.0))
    return transform(mesh, _rotation_z(g.uniform(0, 2 * np.pi)), (5e5 + g.uniform(0, 1e3), 4.18e6 + g.uniform(0, 1e3), 250.0))


def k_tiny(g):
    return box((0.0, 0.0, 0.0), (g.uniform(0.4, 1.0), g.uniform(0.4, 1.0), 1.0))


def k_inverted(g):
    v, f = box((0, 0, 0), (g.uniform(6, 12), g.uniform(4, 9), g.uniform(5, 12)))
    return v, f[:, ::-1].copy()


def k_open_box(g):
    v, f = box((0, 0, 0), (g.uniform(8, 14), g.uniform(6, 10), g.uniform(4, 8)))
    z = v[f][:, :, 2]
    top = (z > 0).all(axis=1)
    side = np.isclose(v[f][:, :, 0], v[:, 0].max()).all(axis=1)
    return v, f[~(top | side)]  # a shed open at the top and on one side


def k_duplicates(g):
    v, f = box((0, 0, 0), (g.uniform(6, 12), g.uniform(4, 9), g.uniform(5, 12)))
    junk = g.uniform(-50, 50, (int(g.integers(3, 10)), 3))
    dup = f[g.choice(len(f), 4, replace=False)]
    return np.vstack([v, junk]), np.vstack([f, dup])


def k_nonmanifold_edge(g):
    s = g.uniform(4, 8)
    a = box((0, 0, 0), (s, s, s))
    b = box((s, s, 0), (2 * s, 2 * s, s))  # touching a along its whole vertical edge
    return weld(union(a, b))


def k_below_datum(g):
    # heights in a site frame whose datum is above the ground (a polder, a quarry): z < 0
    v, f = prism(_footprint(g, "U"), g.uniform(2.0, 3.0), g.uniform(6.0, 12.0))
    return v - [0.0, 0.0, g.uniform(50.0, 150.0)], f


def k_cavity(g):
    # a hollow block: a closed inner shell wound inward, not connected to the outer one
    s, wall = g.uniform(10.0, 16.0), g.uniform(1.0, 3.0)
    inner_v, inner_f = box((wall, wall, wall), (s - wall, s - wall, s - wall))
    return union(box((0, 0, 0), (s, s, s)), (inner_v, inner_f[:, ::-1].copy()))


def k_degenerate_faces(g):
    v, f = box((0, 0, 0), (g.uniform(6, 12), g.uniform(4, 9), g.uniform(5, 12)))
    top = v[:, 2].max()
    line = np.array([[1.0, 1.0, top], [2.0, 2.0, top], [3.0, 3.0, top]])  # three points on one line
    return np.vstack([v, line]), np.vstack([f, [[8, 9, 10], [0, 0, 1]]])  # zero-area faces, as exporters leave


KINDS: dict[str, tuple[Callable, dict]] = {
    "dome": (k_dome, {}),
    "torus_flat": (k_torus_flat, {}),
    "torus_standing": (k_torus_standing, {}),
    "stadium": (k_stadium, {}),
    "l_building": (k_l_building, {}),
    "u_building": (k_u_building, {}),
    "courtyard": (k_courtyard, {}),
    "thin_wall": (k_thin_wall, {}),
    "sign_on_pole": (k_sign_on_pole, {}),
    "chimney": (k_chimney, {}),
    "overlapping_boxes": (k_overlapping_boxes, {}),
    "guyed_mast": (k_guyed_mast, {}),
    "long_bridge": (k_long_bridge, {}),
    "far_from_origin": (k_far_from_origin, {}),
    "tiny": (k_tiny, {}),
    "inverted_winding": (k_inverted, {}),
    "open_box": (k_open_box, {"closed": False}),
    "duplicates": (k_duplicates, {}),
    "nonmanifold_edge": (k_nonmanifold_edge, {}),
    "millimetres": (k_l_building, {"millimetres": True}),
    "below_datum": (k_below_datum, {}),
    "cavity": (k_cavity, {}),
    "degenerate_faces": (k_degenerate_faces, {}),
}


def make(kind: str, seed: int) -> Shape:
    build, extra = KINDS[kind]
    v, f = build(np.random.default_rng(seed))
    closed = extra.get("closed", True)
    used = np.unique(f)
    return Shape(
        kind, seed, np.asarray(v, float), np.asarray(f, np.int64), closed, float(v[used, 2].min()), extra.get("millimetres", False)
    )


def as_structure(shape: Shape):
    """The shape on a ground sheet as a user would hand it to uavcov: ``Structure(...)``, faces
    resting on the ground named "contact"."""
    import uavcov
    from uavcov.structures import Structure

    v, f = shape.vertices, shape.faces
    gv, gf = _ground_of(shape)
    tri = v[f]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    resting = np.abs(tri[:, :, 2] - shape.ground_z).max(axis=1) <= 1e-9 * max(1.0, abs(shape.ground_z))
    resting &= normal[:, 2] < 0 if shape.kind != "inverted_winding" else normal[:, 2] > 0
    if shape.ground_mode == "none":
        parts = np.where(resting, 1, 0).astype(np.int32)
        return Structure(shape.kind, uavcov.Terrain(v, f), parts, ("structure", "contact"), None)
    parts = np.concatenate([np.zeros(len(gf), np.int32), np.where(resting, 2, 1).astype(np.int32)])
    surface = uavcov.Terrain(np.vstack([gv, v]), np.vstack([gf, f + len(gv)]))
    return Structure(shape.kind, surface, parts, ("ground", "structure", "contact"), 0)


def _ground_of(shape: Shape) -> Mesh:
    """The ground ``as_structure`` puts under the shape (see ``Shape.ground_mode``), faces up."""
    if shape.ground_mode == "mesh":
        return shape.ground
    v, f = shape.vertices, shape.faces
    used = v[np.unique(f)]
    lo, hi = used.min(axis=0), used.max(axis=0)
    if shape.ground_mode == "small":  # the middle fifth of the footprint only
        centre, half = (lo + hi) / 2, (hi - lo) / 10
        lo, hi, margin = centre - half, centre + half, 0.0
    else:
        margin = max(0.5 * float(max(hi[0] - lo[0], hi[1] - lo[1])), 10.0)
    xs = np.linspace(lo[0] - margin, hi[0] + margin, 5)
    ys = np.linspace(lo[1] - margin, hi[1] + margin, 5)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    gv = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, shape.ground_z)])
    gf = grid_quads(5, 5, False, False)
    # grid_quads walks the lattice (x outer, y inner): make every ground face face up
    n = np.cross(gv[gf[:, 1]] - gv[gf[:, 0]], gv[gf[:, 2]] - gv[gf[:, 0]])
    gf[n[:, 2] < 0] = gf[n[:, 2] < 0][:, ::-1]
    return gv, gf


# ---------------------------------------------------------------------------------------------
# mesh files written here (not by trimesh)
# ---------------------------------------------------------------------------------------------


def write_stl(path: Path, v: np.ndarray, f: np.ndarray, binary: bool) -> Path:
    tri = v[f]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    if binary:
        with open(path, "wb") as out:
            out.write(b"\0" * 80 + struct.pack("<I", len(f)))
            rows = np.zeros(len(f), dtype=[("n", "<f4", 3), ("t", "<f4", (3, 3)), ("attr", "<u2")])
            rows["n"], rows["t"] = n, tri
            out.write(rows.tobytes())
    else:
        lines = ["solid shape"]
        for normal, t in zip(n, tri, strict=True):
            lines.append(f"facet normal {normal[0]:.9g} {normal[1]:.9g} {normal[2]:.9g}\n outer loop")
            lines += [f"  vertex {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}" for p in t]
            lines.append(" endloop\nendfacet")
        path.write_text("\n".join(lines + ["endsolid shape", ""]))
    return path


def write_obj(path: Path, v: np.ndarray, f: np.ndarray) -> Path:
    lines = [f"v {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}" for p in v] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in f]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_ply(path: Path, v: np.ndarray, f: np.ndarray, binary: bool) -> Path:
    kind = "binary_little_endian" if binary else "ascii"
    header = (
        f"ply\nformat {kind} 1.0\nelement vertex {len(v)}\nproperty double x\nproperty double y\nproperty double z\n"
        f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    if binary:
        rows = np.zeros(len(f), dtype=[("n", "u1"), ("i", "<i4", 3)])
        rows["n"], rows["i"] = 3, f
        path.write_bytes(header.encode() + v.astype("<f8").tobytes() + rows.tobytes())
    else:
        body = [f"{p[0]:.17g} {p[1]:.17g} {p[2]:.17g}" for p in v] + [f"3 {a} {b} {c}" for a, b, c in f]
        path.write_text(header + "\n".join(body) + "\n")
    return path


FILE_FORMATS = ("stl_ascii", "stl_binary", "obj", "ply_ascii", "ply_binary")


def write_mesh(directory: Path, name: str, v: np.ndarray, f: np.ndarray, form: str) -> Path:
    suffix = form.split("_", maxsplit=1)[0]
    path = Path(directory) / f"{name}.{suffix}"
    if form == "obj":
        return write_obj(path, v, f)
    writer = write_stl if suffix == "stl" else write_ply
    return writer(path, v, f, form.endswith("binary"))


def through_file(shape: Shape, directory: Path, form: str, *, keep_coordinates: bool = False, closed: bool | None = None):
    """The shape written to a mesh file here and read back by ``load_structure``, as a user would
    (``closed`` as the shape is; ``scale=0.001`` for a file in millimetres; ``origin=(0, 0, 0)``
    to keep the file's coordinates)."""
    from uavcov.structures import load_structure

    v = shape.vertices * (1000.0 if shape.millimetres else 1.0)
    path = write_mesh(Path(directory), f"{shape.kind}_{shape.seed}", v, shape.faces, form)
    kwargs = {"closed": shape.closed if closed is None else closed, "scale": 0.001 if shape.millimetres else 1.0}
    if keep_coordinates:
        kwargs["origin"] = (0.0, 0.0, 0.0)
    return load_structure(path, **kwargs), path
