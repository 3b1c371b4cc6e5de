"""Structures no one on the project designed, built here with numpy alone, and brute-force
references to judge missions on them.

The shapes do not use the project's generators (``uavcov.structures._solids``): every mesh is
made here from its definition, closed solids wound outward by their own signed volume (except
where a kind is about bad winding, open edges, duplicates or non-manifold edges on purpose).
The references do not use the project's queries either: point-triangle distance by the
closest-point regions (Ericson, "Real-Time Collision Detection" 5.1.5), inside by the generalised
winding number (the sum of the solid angles of the faces, Van Oosterom and Strackee), segment
crossing and occlusion by Moller-Trumbore, all in numpy.

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
            for di, dj, e in ((-1, 0, (i, j, i, j + 1)), (1, 0, (i + 1, j + 1, i + 1, j)), (0, -1, (i + 1, j, i, j)), (0, 1, (i, j + 1, i + 1, j + 1))):
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
        anchor = (reach * np.cos(angle), reach * np.sin(angle), 0.0)
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
}


def make(kind: str, seed: int) -> Shape:
    build, extra = KINDS[kind]
    v, f = build(np.random.default_rng(seed))
    closed = extra.get("closed", True)
    used = np.unique(f)
    return Shape(kind, seed, np.asarray(v, float), np.asarray(f, np.int64), closed, float(v[used, 2].min()), extra.get("millimetres", False))


def as_structure(shape: Shape):
    """The shape on a ground sheet as a user would hand it to uavcov: ``Structure(...)``, faces
    resting on the ground named "contact"."""
    import uavcov
    from uavcov.structures import Structure

    v, f = shape.vertices, shape.faces
    used = v[np.unique(f)]
    lo, hi = used.min(axis=0), used.max(axis=0)
    margin = max(0.5 * float(max(hi[0] - lo[0], hi[1] - lo[1])), 10.0)
    xs = np.linspace(lo[0] - margin, hi[0] + margin, 5)
    ys = np.linspace(lo[1] - margin, hi[1] + margin, 5)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    gv = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, shape.ground_z)])
    gf = grid_quads(5, 5, False, False)
    gf = np.array([(a, b, c) for a, b, c in gf])
    # grid_quads walks the lattice (x outer, y inner): make every ground face face up
    n = np.cross(gv[gf[:, 1]] - gv[gf[:, 0]], gv[gf[:, 2]] - gv[gf[:, 0]])
    gf[n[:, 2] < 0] = gf[n[:, 2] < 0][:, ::-1]
    tri = v[f]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    resting = np.abs(tri[:, :, 2] - shape.ground_z).max(axis=1) <= 1e-9 * max(1.0, abs(shape.ground_z))
    resting &= normal[:, 2] < 0 if shape.kind != "inverted_winding" else normal[:, 2] > 0
    parts = np.concatenate([np.zeros(len(gf), np.int32), np.where(resting, 2, 1).astype(np.int32)])
    surface = uavcov.Terrain(np.vstack([gv, v]), np.vstack([gf, f + len(gv)]))
    return Structure(shape.kind, surface, parts, ("ground", "structure", "contact"), 0)


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
        for normal, t in zip(n, tri):
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
    suffix = form.split("_")[0]
    path = Path(directory) / f"{name}.{suffix}"
    if form == "obj":
        return write_obj(path, v, f)
    writer = write_stl if suffix == "stl" else write_ply
    return writer(path, v, f, form.endswith("binary"))


# ---------------------------------------------------------------------------------------------
# the independent references
# ---------------------------------------------------------------------------------------------


def point_triangle_distance(points: np.ndarray, triangles: np.ndarray, chunk: int = 256) -> np.ndarray:
    """``(P,)`` least distance of each point to any of ``triangles`` ``(F, 3, 3)``, by the
    closest-point regions of each triangle (vertex, edge, face)."""
    out = np.empty(len(points))
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    ab, ac = b - a, c - a
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
        for start, edge, t in ((a, ab, t_ab), (a, ac, t_ac), (b, c - b, t_bc)):
            t = np.nan_to_num(t, nan=0.0)
            e = start + t[..., None] * edge
            best = np.fmin(best, np.linalg.norm(p - e, axis=-1))
        out[s : s + chunk] = best.min(axis=1)
    return out


def winding_number(points: np.ndarray, triangles: np.ndarray, chunk: int = 128) -> np.ndarray:
    """``(P,)`` generalised winding number of each point with respect to ``triangles``: 1 inside
    a closed outward solid, 0 outside, 2 where two overlapping solids are both around it."""
    out = np.empty(len(points))
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
    t0, e1, e2 = triangles[None, :, 0], (triangles[:, 1] - triangles[:, 0])[None], (triangles[:, 2] - triangles[:, 0])[None]
    for s in range(0, len(a), chunk):
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


def judge(structure, result, h_min: float, d_safe: float, z_max: float, closed: bool) -> Verdict:
    """Every configuration of ``result`` (a MissionResult on ``structure``) against the references."""
    v, f = structure.surface.vertices, structure.surface.faces
    triangles = v[f]
    solid = triangles[structure.face_parts != structure.ground_part]
    ground_z = float(v[f[structure.face_parts == structure.ground_part]][..., 2].min())
    trajectory = np.asarray(result.trajectory)
    points = trajectory.reshape(-1, 3)
    unique = np.unique(points, axis=0)
    verdict = Verdict()
    scale = max(1.0, float(np.abs(v).max()))
    verdict.standoff = int((point_triangle_distance(unique, triangles) < h_min - 1e-9 * scale).sum())
    verdict.ceiling = int((unique[:, 2] > z_max + 1e-9 * scale).sum())
    verdict.below_ground = int((unique[:, 2] < ground_z).sum())
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


def run_judged(structure, start: str, iterations: int, seed: int, closed: bool, *, n_uavs: int = 8, targets_count: int = 400) -> Outcome:
    """Run one mission with the README's settings and judge it by the references."""
    import uavcov
    from uavcov import errors

    outcome = Outcome(structure.name, seed, start)
    try:
        settings = readme_settings(structure, start, iterations, n_uavs)
        targets = few_targets(structure, targets_count)
        result = uavcov.run_mission(structure, settings, targets=targets, rng=seed, n_threads=1)
    except Exception as exc:  # counted, not hidden: the table shows it
        outcome.error = f"{type(exc).__name__}: {exc}"
        outcome.clear_refusal = isinstance(exc, errors.UavcovError)
        return outcome
    z_max = result.settings.constraints.z_max
    verdict = judge(structure, result, H_MIN, D_SAFE, z_max, closed)
    best_lo, best_hi = recount(structure, targets, result.best_positions, D_MAX)
    start_lo, start_hi = recount(structure, targets, result.initial_positions, D_MAX)
    verdict.recount = (best_lo, best_hi)
    off = max(best_lo - result.best_coverage, result.best_coverage - best_hi, 0.0)
    off = max(off, start_lo - result.initial_coverage, result.initial_coverage - start_hi)
    verdict.coverage_off = off
    outcome.verdict, outcome.best, outcome.initial = verdict, result.best_coverage, result.initial_coverage
    return outcome


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


@dataclass
class PlanOutcome:
    returncode: int
    stderr: str
    violations: int = 0  # route segments through the structure, final positions nearer than the standoff or inside
    coverage: float = float("nan")


def plan_arguments(path: Path, out: Path, seed: int, iterations: int, n_uavs: int = 8, *, scale: float = 1.0, open_mesh: bool = False) -> list[str]:
    """The arguments of ``uavcov plan --structure FILE`` with the README's team."""
    arguments = ["plan", "--structure", str(path), "--anchor", "8.5,47.4,400", "--uavs", str(n_uavs), "--d-max", str(D_MAX)]
    arguments += ["--iterations", str(iterations), "--seed", str(seed), "--threads", "1"] + (["--scale", repr(scale)] if scale != 1.0 else [])
    return arguments + (["--open-mesh"] if open_mesh else []) + ["--out", str(out)]


def judge_plan(path: Path, out: Path, *, scale: float = 1.0, open_mesh: bool = False) -> int:
    """How many route segments of a written structure plan cross the structure (read as the
    command read it), and how many final positions are nearer than the standoff or inside it."""
    import csv
    import json

    from uavcov.structures import load_structure

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
    violations += int((winding_number(positions, solid) > 0.5).sum())
    return violations


def plan_judged(path: Path, out: Path, seed: int, iterations: int, n_uavs: int = 8, *, scale: float = 1.0, open_mesh: bool = False) -> PlanOutcome:
    """``uavcov plan --structure FILE`` in a child process, judged by :func:`judge_plan`."""
    import json
    import subprocess
    import sys

    command = [sys.executable, "-m", "uavcov"] + plan_arguments(path, out, seed, iterations, n_uavs, scale=scale, open_mesh=open_mesh)
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, env=_no_plots_env())
    outcome = PlanOutcome(done.returncode, done.stderr.strip())
    if done.returncode == 0:
        outcome.violations = judge_plan(path, out, scale=scale, open_mesh=open_mesh)
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
    expected = np.abs(winding_number(points, triangles)) > 0.5  # a solid wound inward has -1 inside
    said = np.asarray(structure.surface.inside(points), dtype=bool)
    return int((expected & ~said).sum()), int((~expected & said).sum())
