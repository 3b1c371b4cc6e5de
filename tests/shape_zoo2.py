"""Structures no one on the project designed, round 2: kinds and inputs of another nature than
``tests/shape_zoo.py``'s, built with numpy alone from that module's building blocks.

Not axis-aligned (a block tilted over one edge, a leaning tower), on a ground that is not a flat
sheet (a house on a hillside, a bridge over a valley: a DEM-like ground mesh), several buildings
200 m apart in one scene, a 1.5 km bridge, a hyperbolic cooling tower (a thin shell open at the
top), a wind turbine with slender blades on a tilted, yawed rotor, a cable-stayed bridge with
0.1 m cables, a wall with window openings through it (genus > 0), a staircase, a cantilever, a
200k-face dome, a drum made of slivers, a block with two slivers of about zero area, a structure
handed over with no ground at all and one whose ground is smaller than its footprint. ``PRIORS`` are the inputs of another nature: known
points with noise, without normals (the ``alpha`` reconstruction), coarse boxes and a decimated
mesh. ``tests/test_unseen_shapes2.py`` asserts on small cases; ``scripts/unseen_shapes.py
--round 2`` runs the README's structure settings on every kind.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from shape_zoo import (
    Mesh,
    Shape,
    _rotation_x,
    _rotation_z,
    beam,
    box,
    dome,
    grid_quads,
    outward,
    prism,
    rest,
    revolve,
    transform,
    union,
)


def _rotation_y(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]], float)


def upright(mask: np.ndarray, cell: float, thickness: float) -> Mesh:
    """The cells of a boolean ``(nx, nz)`` elevation (x along, z up) extruded ``thickness``
    along y: a wall with openings, a staircase's side, a cantilever's section."""
    v, f = prism(mask, cell, thickness)  # x, y = z of the elevation, z = the extrusion
    v = v[:, [0, 2, 1]]  # (x, elevation, extrusion) -> (x, extrusion, elevation)
    return outward((v, f[:, ::-1].copy()))  # swapping two axes mirrors: rewind


def frustum(r_bottom: float, r_top: float, height: float, sides: int) -> Mesh:
    """A closed truncated cone on z = 0 about the z axis (a tower, a drum)."""
    theta = 2 * np.pi * np.arange(sides) / sides
    ring = np.column_stack([np.cos(theta), np.sin(theta)])
    v = np.vstack(
        [
            np.column_stack([r_bottom * ring, np.zeros(sides)]),
            np.column_stack([r_top * ring, np.full(sides, height)]),
            [[0, 0, 0], [0, 0, height]],
        ]
    )
    k = np.arange(sides)
    k1 = (k + 1) % sides
    side = np.vstack([np.column_stack([k, k1, sides + k1]), np.column_stack([k, sides + k1, sides + k])])
    caps = np.vstack(
        [np.column_stack([np.full(sides, 2 * sides), k1, k]), np.column_stack([np.full(sides, 2 * sides + 1), sides + k, sides + k1])]
    )
    return outward((v, np.vstack([side, caps]).astype(np.int64)))


def heightfield(xs: np.ndarray, ys: np.ndarray, height: Callable[[np.ndarray, np.ndarray], np.ndarray]) -> Mesh:
    """An open DEM-like ground mesh ``z = height(x, y)`` on the lattice ``xs x ys``, facing up."""
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    v = np.column_stack([gx.ravel(), gy.ravel(), height(gx, gy).ravel()])
    f = grid_quads(len(xs), len(ys), False, False)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    down = np.cross(b - a, c - a)[:, 2] < 0
    f[down] = f[down][:, ::-1]
    return v, f


def _with_ground(kind: str, seed: int, mesh: Mesh, ground: Mesh | None = None, mode: str = "sheet", closed: bool = True) -> Shape:
    v, f = mesh
    ground_z = float(v[np.unique(f), 2].min()) if ground is None else float(ground[0][:, 2].min())
    return Shape(kind, seed, np.asarray(v, float), np.asarray(f, np.int64), closed, ground_z, False, ground, mode)


# ---------------------------------------------------------------------------------------------
# the kinds: each ``build(g, kind, seed) -> Shape``
# ---------------------------------------------------------------------------------------------


def k_tilted_block(g, kind, seed):
    # a container tipped over one long edge, turned about z by any angle: no face is axis-aligned
    size = (g.uniform(8, 14), g.uniform(3, 5), g.uniform(3, 5))
    tilt = _rotation_x(g.uniform(0.2, 0.6))
    return _with_ground(kind, seed, rest(transform(box((0, 0, 0), size), _rotation_z(g.uniform(0, 2 * np.pi)) @ tilt)))


def k_leaning_tower(g, kind, seed):
    r, h = g.uniform(3.0, 6.0), g.uniform(20.0, 40.0)
    tower = frustum(r, r, h, int(g.integers(12, 24)))
    lean = _rotation_z(g.uniform(0, 2 * np.pi)) @ _rotation_y(g.uniform(0.07, 0.2))
    return _with_ground(kind, seed, rest(transform(tower, lean)))


def _hills(g, span: float) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    centres = g.uniform(-span / 2, span / 2, (4, 2))
    heights, widths = g.uniform(3.0, 9.0, 4), g.uniform(0.15, 0.35, 4) * span
    tilt = g.uniform(-0.12, 0.12, 2)  # a hillside, not a plain

    def height(x, y):
        z = tilt[0] * x + tilt[1] * y
        for (cx, cy), a, w in zip(centres, heights, widths, strict=True):
            z = z + a * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2 * w * w))
        return z

    return height


def k_hillside_house(g, kind, seed):
    span = 70.0
    height = _hills(g, span)
    xs = np.linspace(-span / 2, span / 2, int(g.integers(25, 40)))
    ys = np.linspace(-span / 2, span / 2, int(g.integers(25, 40)))
    ground = heightfield(xs, ys, height)
    w, d, h = g.uniform(8, 14), g.uniform(6, 10), g.uniform(5, 10)
    # The house's footprint sunk below the lowest ground under it (a basement), turned about z.
    house = transform(box((-w / 2, -d / 2, 0), (w / 2, d / 2, h)), _rotation_z(g.uniform(0, np.pi)))
    corners = house[0][:, :2]
    sample = np.concatenate([corners, corners.mean(axis=0, keepdims=True)])
    low, high = float(height(sample[:, 0], sample[:, 1]).min()), float(height(sample[:, 0], sample[:, 1]).max())
    v, f = house
    v = v.copy()
    v[:, 2] = np.where(v[:, 2] > 0, high + h, low - 1.5)
    return _with_ground(kind, seed, (v, f), ground, "mesh")


def k_valley_bridge(g, kind, seed):
    # a deck across a V valley on piers of different heights, the abutments sunk into the slopes
    span, depth, deck_z = g.uniform(60, 100), g.uniform(10, 20), g.uniform(2.0, 4.0)
    slope = 2 * depth / span

    def height(x, y):
        return np.maximum(depth - slope * np.abs(x), 0.0) + 0.02 * y

    xs = np.linspace(-span / 2 - 15, span / 2 + 15, int(g.integers(30, 50)))
    ys = np.linspace(-20, 20, 9)
    ground = heightfield(xs, ys, height)
    top = depth + deck_z
    parts = [box((-span / 2 - 10, -4, top), (span / 2 + 10, 4, top + 1.2))]
    for x in np.linspace(-span / 3, span / 3, int(g.integers(2, 4))):
        foot = float(height(np.array([x]), np.array([0.0]))[0]) - 2.0
        parts.append(box((x - 1.0, -2.0, foot), (x + 1.0, 2.0, top + 0.6)))  # into the deck and the ground
    return _with_ground(kind, seed, union(*parts), ground, "mesh")


def k_campus(g, kind, seed):
    # two or three buildings about 200 m apart in one scene
    count = int(g.integers(2, 4))
    parts = []
    for k in range(count):
        angle = 2 * np.pi * k / count + g.uniform(0, 0.3)
        centre = 200.0 / (2 * np.sin(np.pi / count)) * np.array([np.cos(angle), np.sin(angle), 0.0])
        w, d, h = g.uniform(10, 25), g.uniform(8, 16), g.uniform(6, 20)
        parts.append(transform(box((-w / 2, -d / 2, 0), (w / 2, d / 2, h)), _rotation_z(g.uniform(0, np.pi)), centre))
    return _with_ground(kind, seed, union(*parts))


def k_km_bridge(g, kind, seed):
    length, top = g.uniform(1400, 1600), g.uniform(12, 20)
    parts = [box((0, -6, top - 1.5), (length, 6, top))]
    # piers every 60-100 m, their tops 0.5 m into the deck's underside
    parts += [box((x - 1.5, -3, 0), (x + 1.5, 3, top - 1.0)) for x in np.arange(g.uniform(40, 80), length - 20, g.uniform(60, 100))]
    return _with_ground(kind, seed, transform(union(*parts), _rotation_z(g.uniform(0, np.pi))))


def k_cooling_tower(g, kind, seed):
    # a hyperboloid of one sheet, 0.3-0.5 m thick, open at the top (the inside can be flown into)
    h, waist, base = g.uniform(40, 70), g.uniform(12, 18), g.uniform(20, 28)
    wall = g.uniform(0.3, 0.5)
    z = np.linspace(0.0, h, 14)
    throat = 0.75 * h
    c = throat / np.sqrt((base / waist) ** 2 - 1)
    r = waist * np.sqrt(1 + ((z - throat) / c) ** 2)
    profile = np.vstack([np.column_stack([r - wall, z]), np.column_stack([r, z])[::-1]])  # up inside, down outside
    return _with_ground(kind, seed, revolve(profile, int(g.integers(24, 40))))


def k_wind_turbine(g, kind, seed):
    h, blade = g.uniform(35, 50), g.uniform(22, 32)
    tower = frustum(2.0, 1.2, h, 16)
    nacelle = box((-2.0, -1.5, h - 0.5), (5.0, 1.5, h + 2.5))
    hub = (5.5, 0.0, h + 1.0)
    parts = [tower, nacelle, box((4.5, -1.0, h), (6.5, 1.0, h + 2.0))]
    tilt, azimuth = _rotation_y(-g.uniform(0.05, 0.1)), g.uniform(0, 2 * np.pi / 3)
    for k in range(3):
        a = azimuth + 2 * np.pi * k / 3
        direction = tilt @ np.array([0.0, np.cos(a), np.sin(a)])
        parts.append(beam(np.asarray(hub) + 0.5 * direction, np.asarray(hub) + blade * direction, g.uniform(0.3, 0.5)))
    return _with_ground(kind, seed, transform(union(*parts), _rotation_z(g.uniform(0, 2 * np.pi))))


def k_cable_stayed(g, kind, seed):
    span, top, mast = g.uniform(100, 180), g.uniform(8, 12), g.uniform(35, 50)
    parts = [box((-span / 2, -5, top), (span / 2, 5, top + 1.0)), box((-1.5, -6.5, 0.0), (1.5, -5.0, mast))]
    parts.append(box((-1.5, 5.0, 0.0), (1.5, 6.5, mast)))
    parts += [box((x - 2, -5, 0), (x + 2, 5, top + 0.5)) for x in (-span / 2 + 2, span / 2 - 2)]  # abutments
    for side in (-5.7, 5.7):
        for x in np.linspace(-span / 2 + 8, span / 2 - 8, int(g.integers(4, 8))):
            if abs(x) < 6:
                continue
            parts.append(beam((0.0, side, mast - 2.0 - abs(x) / span * 8), (x, side * 0.85, top + 0.9), 0.1))  # 0.1 m cables
    return _with_ground(kind, seed, transform(union(*parts), _rotation_z(g.uniform(0, np.pi))))


def k_windowed_wall(g, kind, seed):
    nx, nz, cell = int(g.integers(9, 15)), int(g.integers(5, 9)), g.uniform(1.0, 1.6)
    mask = np.ones((nx, nz), bool)
    for i in range(1, nx - 1, 2):
        for j in range(1, nz - 1, 2):
            mask[i, j] = g.random() >= 0.8  # most become window openings through the wall: genus > 0
    wall = upright(mask, cell, g.uniform(0.3, 0.6))
    return _with_ground(kind, seed, transform(wall, _rotation_z(g.uniform(0, np.pi))))


def k_staircase(g, kind, seed):
    steps, tread = int(g.integers(8, 16)), g.uniform(0.8, 1.5)
    mask = np.tril(np.ones((steps, steps), bool))  # column i is i + 1 steps high
    stairs = upright(mask, tread, g.uniform(2.0, 4.0))
    return _with_ground(kind, seed, transform(stairs, _rotation_z(g.uniform(0, 2 * np.pi))))


def k_cantilever(g, kind, seed):
    # a core with a long arm overhanging open ground at mid height
    core, arm, storeys = int(g.integers(2, 4)), int(g.integers(4, 8)), int(g.integers(4, 7))
    mask = np.zeros((core + arm, storeys), bool)
    mask[:core, :] = True
    mask[core:, storeys - 2 :] = True
    building = upright(mask, g.uniform(2.5, 3.5), g.uniform(6, 12))
    return _with_ground(kind, seed, transform(building, _rotation_z(g.uniform(0, 2 * np.pi))))


def k_dense_dome(g, kind, seed):
    # about 200k faces: an exporter's fine tessellation of a 10-15 m dome
    return _with_ground(kind, seed, dome(g.uniform(10, 15), 200, 500))


def k_slivers(g, kind, seed):
    # a drum of 2000-4000 sides as a CAD exporter tessellates it: every face a sliver (its sides
    # 0.01 m wide and up to 12 m tall, its caps fans of 0.01 m wide triangles)
    sides = int(g.integers(2000, 4000))
    return _with_ground(kind, seed, frustum(g.uniform(4, 8), g.uniform(3, 8), g.uniform(6, 12), sides))


def k_no_ground(g, kind, seed):
    # a Structure handed over with no ground at all (ground_part None)
    return _with_ground(kind, seed, box((0, 0, 0), (g.uniform(8, 14), g.uniform(6, 10), g.uniform(6, 12))), mode="none")


def k_small_ground(g, kind, seed):
    # a ground sheet under the middle fifth of the footprint only: the rest of the scene has none
    return _with_ground(kind, seed, box((0, 0, 0), (g.uniform(16, 24), g.uniform(12, 18), g.uniform(6, 12))), mode="small")


def k_hairline_slivers(g, kind, seed):
    # a block whose top diagonal carries a vertex 1e-15 of its length off one end: two slivers of
    # about zero area, which a Structure by hand refuses (the engine does) and the repair drops
    return _with_ground(kind, seed, hairline_slivers(box((0, 0, 0), (g.uniform(20, 40), g.uniform(10, 20), g.uniform(5, 12))), 1e-15))


KINDS2: dict[str, Callable] = {
    "tilted_block": k_tilted_block,
    "leaning_tower": k_leaning_tower,
    "hillside_house": k_hillside_house,
    "valley_bridge": k_valley_bridge,
    "campus": k_campus,
    "km_bridge": k_km_bridge,
    "cooling_tower": k_cooling_tower,
    "wind_turbine": k_wind_turbine,
    "cable_stayed": k_cable_stayed,
    "windowed_wall": k_windowed_wall,
    "staircase": k_staircase,
    "cantilever": k_cantilever,
    "dense_dome": k_dense_dome,
    "slivers": k_slivers,
    "no_ground": k_no_ground,
    "small_ground": k_small_ground,
    "hairline_slivers": k_hairline_slivers,
}


def make2(kind: str, seed: int) -> Shape:
    return KINDS2[kind](np.random.default_rng(seed), kind, seed)


def file_mesh(shape: Shape) -> Mesh:
    """What a user's file of the shape holds: the structure, and its ground when it is not a
    flat sheet (a site model exported with its terrain: then an open mesh)."""
    if shape.ground_mode == "mesh":
        return union((shape.vertices, shape.faces), shape.ground)
    return shape.vertices, shape.faces


# ---------------------------------------------------------------------------------------------
# priors of another nature: (structure, seed) -> StructurePrior
# ---------------------------------------------------------------------------------------------


def _noisy(sigma: float):
    def prior(structure, seed):
        from uavcov.structures import sample_structure_prior

        return sample_structure_prior(structure, 100, noise=sigma, rng=seed)

    return prior


def _no_normals(structure, seed):
    from uavcov.structures import sample_structure_prior

    return sample_structure_prior(structure, 100, normals=False, rng=seed)


def _coarse(kind: str):
    def prior(structure, seed):
        from uavcov.structures import coarse_structure_prior

        return coarse_structure_prior(structure, kind)

    return prior


PRIORS: dict[str, Callable] = {
    "noise_0.1": _noisy(0.1),
    "noise_1": _noisy(1.0),
    "no_normals": _no_normals,
    "boxes": _coarse("boxes"),
    "decimated": _coarse("decimated"),
}


def through_file2(shape: Shape, directory, form: str, *, closed: bool | None = None):
    """The shape's file (``file_mesh``) written here and read back by ``load_structure`` as a
    user would (in the file's frame moved to its minimum corner, the default): the structure,
    the file's path, and the shape's own solid triangles in the structure's frame (the
    references' "inside", which a site model's terrain, read as structure, would confuse)."""
    from pathlib import Path

    from shape_zoo import write_mesh
    from uavcov.structures import load_structure

    v, f = file_mesh(shape)
    path = write_mesh(Path(directory), f"{shape.kind}_{shape.seed}", v, f, form)
    structure = load_structure(path, closed=shape.closed if closed is None else closed)
    corner = v[np.unique(f)].min(axis=0)
    return structure, path, shape.vertices[shape.faces] - corner


def hairline_slivers(mesh: Mesh, share: float) -> Mesh:
    """The closed mesh with the edge shared by its first two faces split at ``share`` of its
    length from one end, in both faces: two slivers (of about zero area for a tiny ``share``)
    where a CAD exporter mends a T-junction. Still closed and wound alike."""
    v, f = mesh
    b, c = (int(x) for x in f[0] if x in f[1])  # in f[0]'s order
    if list(f[0]).index(c) != (list(f[0]).index(b) + 1) % 3:
        b, c = c, b  # f[0] runs b -> c; f[1] runs c -> b
    p = len(v)
    faces = []
    for t, (x, y) in ((f[0], (b, c)), (f[1], (c, b))):
        a = next(int(k) for k in t if k not in (b, c))
        faces += [(x, p, a), (p, y, a)]  # x -> p -> y along the edge, a the third corner, as t ran
    return np.vstack([v, v[b] + share * (v[c] - v[b])]), np.vstack([np.array(faces, np.int64), f[2:]])
