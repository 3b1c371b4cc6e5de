"""Structures, not height fields: bridges, a wind turbine, a facade and a lattice pylon on a
ground plane, each face named after the part it belongs to, and mesh files read as structures.

A :class:`Structure` is one triangle mesh (:class:`~uavcov.engine.Terrain`) made of closed solids
wound outward that may touch but never interpenetrate, plus an open ground sheet. Its
:meth:`Structure.targets` are area-weighted points with outward normals on every part but the
ground (optional) and the ``"contact"`` faces (solid faces pressed against another solid or the
ground, which no camera can see). :func:`height_field_violation` (``_height_field.py``) measures
how far a scene is from ``z = f(x, y)``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import (
    as_bool,
    as_bool_array,
    as_generator,
    as_positive_float,
    as_positive_int,
    existing_path,
    is_int,
    read_only,
)
from ..engine import Targets, Terrain
from ..errors import InvalidInputError, InvalidTypeError, MeshError
from ..terrain import load_mesh
from ._cracks import zero_width_cracks
from ._solids import Piece, box, cells, face_normals, frustum, ground, join, loft, refine, signed_volume, wound_inward

GROUND = "ground"
CONTACT = "contact"
MAX_TARGETS = 20_000_000


def _names(value: Any) -> tuple[str, ...]:
    """Part names: a sequence of strings (kept as a tuple)."""
    if isinstance(value, (str, bytes)) or not isinstance(value, (tuple, list)) or not all(isinstance(n, str) for n in value):
        raise InvalidTypeError(f"part_names must be a tuple of strings, got {value!r}")
    return tuple(value)


def _part_labels(value: Any, name: str, count: int, n_names: int) -> np.ndarray:
    """``(count,)`` int32 indices into ``n_names`` part names; floats are refused, not truncated."""
    try:
        labels = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise InvalidInputError(f"{name} cannot be read as an array: {exc}") from exc
    if labels.size == 0 and labels.dtype == np.float64:
        labels = labels.astype(np.int64)  # np.asarray([]) is float64; an empty list is not a float
    if not np.issubdtype(labels.dtype, np.integer):
        raise InvalidTypeError(f"{name} must hold integers, got dtype {labels.dtype}")
    if labels.shape != (count,) or (labels.size and (labels.min() < 0 or labels.max() >= n_names)):
        raise InvalidInputError(f"{name} must be {count} indices into {n_names} part names")
    return labels.astype(np.int32)


class StructureTargets(Targets):
    """:class:`~uavcov.engine.Targets` on a structure that also know the part of each point.

    Attributes
    ----------
    parts : (T,) int32 ndarray
        Index of each target's part in ``part_names``.
    part_names : tuple of str
    """

    parts: np.ndarray
    part_names: tuple[str, ...]

    def __init__(self, points: Any, weights: Any, normals: Any, parts: Any, part_names: tuple[str, ...]) -> None:
        super().__init__(points, weights, normals)
        part_names = _names(part_names)
        labels = _part_labels(parts, "parts", len(self), len(part_names))
        labels.setflags(write=False)
        object.__setattr__(self, "parts", labels)
        object.__setattr__(self, "part_names", tuple(part_names))

    def __reduce__(self) -> tuple[Any, ...]:
        normals = None if self.normals is None else np.array(self.normals)
        return (StructureTargets, (np.array(self.points), np.array(self.weights), normals, np.array(self.parts), self.part_names))


@dataclass(frozen=True, eq=False)
class Structure:
    """A 3D structure on a ground plane, with a part name for every face.

    Attributes
    ----------
    name : str
    surface : Terrain
        The whole scene as one mesh (ground included): closed solids wound counter-clockwise
        seen from outside (outward right-hand normals) that may touch but do not interpenetrate,
        and the ground sheet facing up.
    face_parts : (F,) int32 ndarray, read-only
        Index into ``part_names`` of each face of ``surface``.
    part_names : tuple of str
        E.g. ``("ground", "deck_top", "deck_underside", ...)``; ``"contact"`` names solid faces
        pressed against the ground or another solid (never targets).
    ground_part : int or None
        Index of ``"ground"`` in ``part_names``, None without a ground plane.
    """

    name: str
    surface: Terrain
    face_parts: np.ndarray
    part_names: tuple[str, ...]
    ground_part: int | None

    def __post_init__(self) -> None:
        if not isinstance(self.surface, Terrain):
            raise InvalidTypeError(f"surface must be a Terrain, got {type(self.surface).__name__}")
        if not isinstance(self.name, str):
            raise InvalidTypeError(f"name must be a string, got {type(self.name).__name__}")
        names = _names(self.part_names)
        parts = _part_labels(self.face_parts, "face_parts", self.surface.n_faces, len(names))
        if self.ground_part is not None and not (is_int(self.ground_part) and 0 <= self.ground_part < len(names)):
            raise InvalidInputError(f"ground_part must be None or an index into the {len(names)} part names, got {self.ground_part!r}")
        object.__setattr__(self, "face_parts", read_only(parts))
        object.__setattr__(self, "part_names", tuple(str(n) for n in self.part_names))
        if wound_inward(self.surface.vertices, self.surface.faces[parts != (-1 if self.ground_part is None else self.ground_part)]):
            raise InvalidInputError(
                f"the solids of {self.name!r} are wound inward (they enclose a negative volume): wind every face "
                "counter-clockwise seen from outside (reverse them: faces[:, ::-1]), or read the file with load_structure, "
                "which turns them"
            )

    def __reduce__(self) -> tuple[Any, ...]:
        return (Structure, (self.name, self.surface, np.array(self.face_parts), self.part_names, self.ground_part))

    def part_index(self, name: str) -> int:
        """Index of the part called ``name``."""
        if not isinstance(name, str) or name not in self.part_names:
            raise InvalidInputError(f"{self.name} has no part {name!r}; its parts are {self.part_names}")
        return self.part_names.index(name)

    def face_mask(self, *, include_ground: bool = False) -> np.ndarray:
        """``(F,)`` bool: the faces that carry targets (every part but contact, ground optional)."""
        include_ground = as_bool(include_ground, "include_ground")
        mask = np.ones(self.surface.n_faces, dtype=bool)
        if CONTACT in self.part_names:
            mask &= self.face_parts != self.part_names.index(CONTACT)
        if self.ground_part is not None and not include_ground:
            mask &= self.face_parts != self.ground_part
        return mask

    def targets(self, spacing: float = 0.5, *, include_ground: bool = False) -> StructureTargets:
        """Area-weighted target points with outward unit normals, deterministic.

        Each chosen face is cut into ``m^2`` congruent triangles, ``m = ceil(sqrt(area) / spacing)``,
        with a target at each piece's centroid weighted by its area (the rule of
        :meth:`Terrain.default_targets`); pieces whose centroid lies on a contact face (where
        another solid or the ground presses on the face) are left out, so weights sum to the
        visible area of the chosen faces.

        Parameters
        ----------
        spacing : float
            About the distance between neighbouring targets (m).
        include_ground : bool
            Also put targets on the ground plane.

        Returns
        -------
        StructureTargets
            With the part of each target in ``.parts``.
        """
        spacing = as_positive_float(spacing, "spacing")
        faces = np.nonzero(self.face_mask(include_ground=include_ground))[0]
        if faces.size == 0:
            raise InvalidInputError(f"{self.name} has no face to put targets on")
        vertices = self.surface.vertices
        triangles = self.surface.faces[faces]
        normals, areas = face_normals(vertices, triangles)
        with np.errstate(over="ignore"):
            m = np.ceil(np.sqrt(areas) / spacing)
        total = float((m * m).sum())
        if not math.isfinite(total) or total > MAX_TARGETS:
            raise InvalidInputError(f"spacing {spacing} m gives about {total:.3g} targets, more than {MAX_TARGETS}; use a larger spacing")
        m = np.maximum(m, 1).astype(np.int64)
        points, weights, point_normals, parts = [], [], [], []
        for size in np.unique(m):
            chosen = np.nonzero(m == size)[0]
            bary = _subdivision_centroids(int(size))
            a, b, c = (vertices[triangles[chosen, k]] for k in range(3))
            p = a[:, None, :] + bary[None, :, 0:1] * (b - a)[:, None, :] + bary[None, :, 1:2] * (c - a)[:, None, :]
            points.append(p.reshape(-1, 3))
            weights.append(np.repeat(areas[chosen] / (size * size), bary.shape[0]))
            point_normals.append(np.repeat(normals[chosen], bary.shape[0], axis=0))
            parts.append(np.repeat(self.face_parts[faces[chosen]], bary.shape[0]))
        # Back into face order, so the result does not depend on how faces group by size.
        face_of = np.concatenate([np.repeat(np.nonzero(m == size)[0], size * size) for size in np.unique(m)])
        order = np.argsort(face_of, kind="stable")
        p, w, n, q = (np.concatenate(values)[order] for values in (points, weights, point_normals, parts))
        hidden = self._pressed(p)
        return StructureTargets(p[~hidden], w[~hidden], n[~hidden], q[~hidden], self.part_names)

    def _pressed(self, points: np.ndarray) -> np.ndarray:
        """``(n,)`` bool: points lying on a contact face, where a solid presses on a larger face
        (a nacelle on a tower's top, a deck on a column): no camera sees them."""
        pressing = self.face_parts == self.part_names.index(CONTACT) if CONTACT in self.part_names else np.zeros(0, dtype=bool)
        if not pressing.any():  # no contact part, or one named but with no face (nothing rests on another)
            return np.zeros(points.shape[0], dtype=bool)
        contact = Terrain(self.surface.vertices, self.surface.faces[pressing])
        bounds = self.surface.bounds
        tolerance = 1e-7 * float(np.max(bounds[1] - bounds[0]))
        pressed: np.ndarray = np.linalg.norm(contact.closest_point(points) - points, axis=1) <= tolerance
        return pressed

    def check_ground(self) -> None:
        """Refuse a structure whose ground does not reach under all of it.

        The standoff limits keep every UAV over some surface (a ray straight down must meet one),
        so with no ground, or one that stops short of the structure, no UAV may stand beside it
        where the ground is missing: only over its top, and the mission would report that as the
        coverage the team can reach. :func:`uavcov.run_mission` checks it first; ``load_structure``
        adds a ground reaching beyond the structure.

        Raises
        ------
        InvalidInputError
            No ground part, or a ground whose x-y extent stops short of the structure's.
        """
        faces = self.surface.faces
        ground = np.zeros(faces.shape[0], dtype=bool) if self.ground_part is None else self.face_parts == self.ground_part
        if not ground.any():
            raise InvalidInputError(
                f"the structure {self.name!r} has no ground: the standoff limits keep every UAV over some surface, so none "
                "could fly beside it; give it a ground sheet reaching beyond it (load_structure adds one)"
            )
        vertices = self.surface.vertices
        under, solid = vertices[np.unique(faces[ground])], vertices[np.unique(faces[~ground])]
        if not solid.shape[0]:
            return
        (g_lo, g_hi), (s_lo, s_hi) = ((p[:, :2].min(axis=0), p[:, :2].max(axis=0)) for p in (under, solid))
        slack = 1e-9 * max(1.0, float(np.abs(self.surface.bounds).max()))
        if (g_lo > s_lo + slack).any() or (g_hi < s_hi - slack).any():
            raise InvalidInputError(
                f"the ground of {self.name!r} covers x {g_lo[0]:.6g} to {g_hi[0]:.6g} m, y {g_lo[1]:.6g} to {g_hi[1]:.6g} m, but the "
                f"structure reaches x {s_lo[0]:.6g} to {s_hi[0]:.6g} m, y {s_lo[1]:.6g} to {s_hi[1]:.6g} m: a UAV beside it there would "
                "stand over no surface (the standoff limits need one below every UAV); extend the ground beyond the structure"
            )

    def coverage_by_part(self, seen: Any, targets: StructureTargets) -> dict[str, float]:
        """Weighted share of each part's targets that is seen.

        Parameters
        ----------
        seen : (T,) array_like of bool
            Which of ``targets`` are seen.
        targets : StructureTargets
            From :meth:`targets` of this structure.

        Returns
        -------
        dict
            Part name -> share in [0, 1], for every part that has targets.
        """
        if not isinstance(targets, StructureTargets):
            raise InvalidTypeError(f"targets must be StructureTargets (from Structure.targets), got {type(targets).__name__}")
        if targets.part_names != self.part_names:
            raise InvalidInputError("targets come from a structure with other parts")
        flags = as_bool_array(seen, "seen", len(targets))
        result = {}
        for index, name in enumerate(self.part_names):
            here = targets.parts == index
            total = float(targets.weights[here].sum())
            if total > 0:
                result[name] = float(targets.weights[here & flags].sum()) / total
        return result


def _subdivision_centroids(m: int) -> np.ndarray:
    """Barycentric ``(u, v)`` of the centroids of the ``m^2`` congruent pieces of a triangle."""
    i, j = np.meshgrid(np.arange(m), np.arange(m), indexing="ij")
    up = (i + j) <= m - 1
    down = (i + j) <= m - 2
    first = np.column_stack([(i[up] + 1 / 3) / m, (j[up] + 1 / 3) / m])
    second = np.column_stack([(i[down] + 2 / 3) / m, (j[down] + 2 / 3) / m])
    return np.concatenate([first, second])


def _assemble(name: str, pieces: list[Piece], sheet: Piece | None) -> Structure:
    """One Structure from solids and a ground sheet: down faces lying on the ground become contact."""
    vertices, faces, labels = join(pieces + ([sheet] if sheet is not None else []))
    normals, _ = face_normals(vertices, faces)
    n_solid = faces.shape[0] - (sheet.faces.shape[0] if sheet is not None else 0)
    z = vertices[faces[:, :3], 2]
    ground_z = 0.0 if sheet is None else float(sheet.vertices[0, 2])
    on_ground = (np.abs(z - ground_z).max(axis=1) <= 1e-9) & (normals[:, 2] < -0.5)
    for f in np.nonzero(on_ground[:n_solid])[0]:
        labels[f] = CONTACT
    names = ([GROUND] if sheet is not None else []) + sorted({label for label in labels if label != GROUND})
    lookup = {n: k for k, n in enumerate(names)}
    parts = np.array([lookup[label] for label in labels], dtype=np.int32)
    return Structure(name, Terrain(vertices, faces), parts, tuple(names), 0 if sheet is not None else None)


def _jitter(generator: np.random.Generator, value: float, relative: float) -> float:
    return float(value * (1.0 + generator.uniform(-relative, relative)))


def girder_bridge(*, rng: Any = None, step: float = 1.0) -> Structure:
    """A girder bridge of about 40 m: a deck 10-11 m up on three girders, two piers, abutments
    at both ends and parapets, over a ground plane.

    Parts: ground, deck_top, deck_underside, deck_edges, girders, piers, abutments, parapets,
    contact. Seeded by ``rng`` (span, deck height and pier places vary by a few per cent);
    ``step`` bounds the mesh's edge length along the cuts (m).
    """
    g = as_generator(rng)
    length = _jitter(g, 40.0, 0.05)
    top = float(g.uniform(10.5, 11.0))
    deck_bottom = top - 0.8
    girder_bottom = deck_bottom - 1.2
    piers = sorted(length * np.array([1 / 3, 2 / 3]) + g.uniform(-1.0, 1.0, 2))
    names = ("deck_edges", "girders", "piers", "parapets", "abutments")
    girder_ys = [(-2.75, -2.25), (-0.25, 0.25), (2.25, 2.75)]
    xs = refine([-2.0, 0.0, length, length + 2.0] + [p + s for p in piers for s in (-0.6, 0.6)], step)
    ys = refine([-4.0, -3.7, -3.0, 3.0, 3.7, 4.0] + [y for pair in girder_ys for y in pair], step)
    zs = refine([0.0, girder_bottom, deck_bottom, top, top + 1.0], step)
    cx, cy, cz = ((q[:-1] + q[1:]) / 2 for q in (xs, ys, zs))
    x, y, z = np.meshgrid(cx, cy, cz, indexing="ij")
    label = np.full(x.shape, -1, dtype=np.int64)
    label[(x > 0) & (x < length) & (z > deck_bottom) & (z < top)] = 0
    for lo, hi in girder_ys:
        label[(x > 0) & (x < length) & (y > lo) & (y < hi) & (z > girder_bottom) & (z < deck_bottom)] = 1
    for p in piers:
        label[(np.abs(x - p) < 0.6) & (np.abs(y) < 3.0) & (z < girder_bottom)] = 2
    label[(np.abs(y) > 3.7) & (z > top)] = 3
    label[((x < 0) | (x > length)) & (z < top)] = 4
    deck = cells(xs, ys, zs, label, names, up={0: "deck_top"}, down={0: "deck_underside"})
    return _assemble("girder_bridge", [deck], ground(-14.0, length + 14.0, -16.0, 16.0, 2.0))


def arch_bridge(*, rng: Any = None, step: float = 1.0) -> Structure:
    """A deck arch bridge of about 40 m: two parabolic arch ribs springing from the ground,
    spandrel columns standing on them, a deck about 10 m up, abutments; open span between the
    arch and the deck.

    Parts: ground, arch, columns, deck_top, deck_underside, deck, abutments, parapets, contact.
    """
    g = as_generator(rng)
    span = _jitter(g, 40.0, 0.05)
    rise = float(g.uniform(6.5, 7.5))
    return _assemble("arch_bridge", arch_pieces(span, rise, 1.8, step), ground(-15.0, span + 15.0, -16.0, 16.0, 2.0))


def arch_pieces(span: float, rise: float, clearance: float, step: float) -> list[Piece]:
    """An arch bridge's solids: two parabolic ribs of ``span`` and ``rise``, four columns on
    each, a deck ``clearance`` above the crown's top, parapets and abutments (m)."""
    thickness = 0.9
    deck_bottom = rise + thickness + clearance
    top = deck_bottom + 0.7
    column_xs = span * np.array([0.15, 0.3, 0.7, 0.85])
    half_width = 0.3
    edges = sorted({0.0, span, *(column_xs - half_width), *(column_xs + half_width)})
    ring_x = refine(edges, step)

    def crown(x: np.ndarray) -> np.ndarray:
        return rise * (1.0 - (2.0 * x / span - 1.0) ** 2)

    pieces = []
    for y0, y1 in ((-3.5, -2.5), (2.5, 3.5)):
        zb = crown(ring_x)
        rings = np.stack(
            [
                np.column_stack([ring_x, np.full_like(ring_x, y0), zb]),
                np.column_stack([ring_x, np.full_like(ring_x, y1), zb]),
                np.column_stack([ring_x, np.full_like(ring_x, y1), zb + thickness]),
                np.column_stack([ring_x, np.full_like(ring_x, y0), zb + thickness]),
            ],
            axis=1,
        )
        pieces.append(loft(rings, "arch", caps=(CONTACT, CONTACT)))
        for xc in column_xs:
            x0, x1 = xc - half_width, xc + half_width
            # The column's foot is the arch's top between two of its rings: a plane, so the
            # column sits on the rib exactly (touching, not cutting into it).
            z0, z1 = crown(np.array([x0, x1])) + thickness
            foot = np.array([[x0, y0, z0], [x1, y0, z1], [x1, y1, z1], [x0, y1, z0]])
            head = foot.copy()
            head[:, 2] = deck_bottom
            pieces.append(loft(np.stack([foot, head]), "columns", caps=(CONTACT, CONTACT)))
    pieces.append(box((-3.0, -4.0, deck_bottom), (span + 3.0, 4.0, top), "deck", up="deck_top", down="deck_underside", step=step))
    for y0, y1 in ((-4.0, -3.7), (3.7, 4.0)):
        pieces.append(box((-3.0, y0, top), (span + 3.0, y1, top + 1.0), "parapets", down=CONTACT, step=step))
    for x0, x1 in ((-3.0, 0.0), (span, span + 3.0)):
        pieces.append(box((x0, -4.0, 0.0), (x1, 4.0, deck_bottom), "abutments", up=CONTACT, step=step))
    return pieces


def wind_turbine(*, rng: Any = None) -> Structure:
    """A wind turbine: a tapered tower about 40 m high, a nacelle, a hexagonal hub and three thin
    tapered blades of about 22 m at a random rotor angle.

    Parts: ground, tower, nacelle, hub, blades, contact.
    """
    g = as_generator(rng)
    height = _jitter(g, 40.0, 0.05)
    blade = _jitter(g, 22.0, 0.05)
    azimuth = float(g.uniform(0.0, 2.0 * np.pi / 3.0))
    pieces = [frustum(np.zeros(3), np.array([0.0, 0.0, height]), (2.0, 1.2), "tower", sides=24, slices=12, caps=(None, CONTACT))]
    pieces.append(box((-2.5, -1.5, height), (4.0, 1.5, height + 3.0), "nacelle", step=1.0))
    apothem, hub_length = 1.0, 1.6
    hub_centre = np.array([4.0, 0.0, height + 1.5])
    u, v = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
    hub = frustum(
        hub_centre,
        np.array([hub_length, 0.0, 0.0]),
        (apothem / math.cos(math.pi / 6),) * 2,
        "hub",
        sides=6,
        phase=azimuth,
        across=u,
        caps=(CONTACT, None),
    )
    pieces.append(hub)
    for k in range(3):
        # Blades leave through every other face of the hexagon, from the face's middle.
        angle = azimuth + math.pi / 6 + 2.0 * math.pi * k / 3
        direction = math.cos(angle) * u + math.sin(angle) * v
        root = hub_centre + np.array([hub_length / 2, 0.0, 0.0]) + apothem * direction
        pieces.append(
            frustum(
                root,
                blade * direction,
                (0.7, 0.2),
                "blades",
                sides=12,
                slices=10,
                flat=(0.5, 0.25),
                across=np.array([1.0, 0.0, 0.0]),
                caps=(CONTACT, None),
            )
        )
    # The tower's axis is x = y = 0 by construction of the hub; the rotor plane is x ~ 4.8 m.
    return _assemble("wind_turbine", pieces, ground(-30.0, 30.0, -30.0, 30.0, 3.0))


def facade(*, rng: Any = None, step: float = 1.0) -> Structure:
    """A five-storey building front with recessed windows and balconies with railings.

    Parts: ground, wall, windows (the glass at the back of each recess), balconies, railings,
    contact. Seeded by ``rng`` (width, and which windows have a balcony).
    """
    g = as_generator(rng)
    columns, floors, storey = 5, 5, 3.0
    bay = _jitter(g, 4.8, 0.05)
    width, depth, height = columns * bay, 10.0, floors * storey
    recess, window_w, sill, window_h = 0.3, 1.6, 0.9, 1.6
    balcony_depth = 1.2
    has_balcony = g.random((floors, columns)) < 0.5
    has_balcony[0] = False
    window_x = [(c + 0.5) * bay + s * window_w / 2 for c in range(columns) for s in (-1, 1)]
    balcony_x = [(c + 0.5) * bay + s * (window_w / 2 + 0.4) for c in range(columns) for s in (-1, 1)]
    rail_x = [x + s * 0.1 for x in balcony_x for s in (-1, 1)]
    floor_z = [f * storey for f in range(floors)]
    window_z = [z + d for z in floor_z for d in (sill, sill + window_h)]
    balcony_z = [z + d for z in floor_z for d in (0.2, 1.2)]
    xs = refine([0.0, width] + window_x + balcony_x + rail_x, step)
    ys = refine([-balcony_depth, -balcony_depth + 0.1, 0.0, recess, recess + 0.2, depth], step)
    zs = refine([0.0, height] + floor_z + window_z + balcony_z, step)
    cx, cy, cz = ((q[:-1] + q[1:]) / 2 for q in (xs, ys, zs))
    x, y, z = np.meshgrid(cx, cy, cz, indexing="ij")
    label = np.full(x.shape, -1, dtype=np.int64)
    label[(y > 0) & (x < width) & (z < height)] = 0
    for f in range(floors):
        for c in range(columns):
            centre, base = (c + 0.5) * bay, floor_z[f]
            opening = (np.abs(x - centre) < window_w / 2) & (z > base + sill) & (z < base + sill + window_h)
            label[opening & (y < recess)] = -1
            label[opening & (y > recess) & (y < recess + 0.2)] = 1
            if has_balcony[f, c]:
                along = np.abs(x - centre) < window_w / 2 + 0.4
                label[along & (y < 0) & (z > base) & (z < base + 0.2)] = 2
                front = along & (y < -balcony_depth + 0.1)
                sides = (np.abs(np.abs(x - centre) - (window_w / 2 + 0.3)) < 0.1) & (y < 0)
                label[(front | sides) & (z > base + 0.2) & (z < base + 1.2)] = 3
    solid = cells(xs, ys, zs, label, ("wall", "windows", "balconies", "railings"))
    return _assemble("facade", [solid], ground(-10.0, width + 10.0, -15.0, depth + 5.0, 2.0))


def lattice_pylon(*, rng: Any = None) -> Structure:
    """A lattice pylon about 30 m high: four square legs, zigzag braces on its four faces (each
    brace touches the next only at a point) and a cross-arm on top.

    Parts: ground, legs, braces, crossarm, contact.
    """
    g = as_generator(rng)
    base = _jitter(g, 6.0, 0.05)
    panel = _jitter(g, 3.0, 0.05)
    pieces = pylon_pieces(base, 0.5, 10, panel, 6.0)
    return _assemble("lattice_pylon", pieces, ground(-15.0, base + 15.0, -12.0, base + 12.0, 1.5))


def pylon_pieces(base: float, leg: float, panels: int, panel: float, arm: float) -> list[Piece]:
    """A pylon's solids: four square ``leg``-wide legs on a ``base`` square, ``panels`` zigzag
    braces of ``panel`` metres on each face, a cross-arm reaching ``arm`` beyond the legs (m)."""
    height = panels * panel
    corners = (0.0, base - leg)
    pieces = [box((x0, y0, 0.0), (x0 + leg, y0 + leg, height), "legs", up=CONTACT, step=1.5) for x0 in corners for y0 in corners]
    depth, rise = 0.3, 0.35
    for axis in (0, 1):
        for outer in (0.0, base - depth):
            for k in range(panels):
                z_start, z_end = k * panel, (k + 1) * panel - rise
                if k % 2:
                    z_start, z_end = z_end, z_start
                rings = []
                for along, z in ((leg, z_start), (base - leg, z_end)):
                    square = [(along, outer, z), (along, outer + depth, z), (along, outer + depth, z + rise), (along, outer, z + rise)]
                    rings.append([(p[0], p[1], p[2]) if axis == 0 else (p[1], p[0], p[2]) for p in square])
                pieces.append(loft(np.asarray(rings, dtype=np.float64), "braces", caps=(CONTACT, CONTACT)))
    pieces.append(box((-arm, 0.0, height), (base + arm, base, height + 1.0), "crossarm", step=1.0))
    return pieces


STRUCTURE_SCENES: dict[str, Callable[..., Structure]] = {
    "girder_bridge": girder_bridge,
    "arch_bridge": arch_bridge,
    "wind_turbine": wind_turbine,
    "facade": facade,
    "lattice_pylon": lattice_pylon,
}


def connected_faces(faces: np.ndarray, n_vertices: int) -> list[np.ndarray]:
    """Indices into ``faces`` of each group of faces connected through shared vertices."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    if faces.shape[0] == 0:
        return []
    rows = np.repeat(np.arange(faces.shape[0]), 3)
    incidence = coo_matrix((np.ones(rows.size), (rows, faces.ravel())), shape=(faces.shape[0], n_vertices)).tocsr()
    _, label = connected_components(incidence @ incidence.T, directed=False)
    return [np.nonzero(label == k)[0] for k in range(label.max() + 1)]


def solid_components(structure: Structure) -> list[np.ndarray]:
    """The face indices of each connected solid (faces sharing a vertex), ground left out."""
    solid = np.nonzero(structure.face_parts != (-1 if structure.ground_part is None else structure.ground_part))[0]
    return [solid[group] for group in connected_faces(structure.surface.faces[solid], structure.surface.n_vertices)]


MAX_MESH_BYTES = 512 * 1024 * 1024
MIN_GROUND_MARGIN = 10.0  # m: the least reach of the ground load_structure adds beyond the model


def load_structure(
    path: Any,
    *,
    up: str = "z",
    scale: float = 1.0,
    closed: bool = True,
    add_ground: bool = True,
    max_faces: int = 2_000_000,
    max_extent: float = 1e5,
    origin: Any = None,
) -> Structure:
    """Read an STL, OBJ or PLY file (binary or ASCII; needs ``trimesh``) as a :class:`Structure`.

    The mesh is welded and cleaned like :func:`~uavcov.terrain.load_mesh`, in its local frame:
    ``local = (file - origin) * scale``, the origin by default the file's minimum corner. A UAV
    position in the file's coordinates ``p`` is ``(p - origin) * scale`` on the structure; give
    ``origin`` to know it (``origin=(0, 0, 0)`` keeps the file's coordinates). With
    ``closed=True`` the mesh must be a set of closed solids: every edge shared by exactly two
    faces, wound consistently; solids wound inward are turned outward. A ground plane at the
    model's lowest z is added (``add_ground``), reaching half the model's size beyond it (at
    least ``MIN_GROUND_MARGIN``, 10 m, so a UAV can stand off beside a small model); the
    model's faces become the part ``"structure"``.

    Parameters
    ----------
    path : str or PathLike
        The mesh file.
    up : {"z", "y"}, default "z"
        The file's up axis (as :func:`~uavcov.terrain.load_mesh`).
    scale : float, default 1.0
        Metres per unit of the file.
    closed : bool, default True
        Require closed solids (two solids that share a face make non-manifold edges: merge them
        into one solid, or pass ``closed=False`` to read an open surface).
    add_ground : bool, default True
        Add the ground plane (its faces are the part ``"ground"``). A mission needs one:
        :func:`uavcov.run_mission` refuses a structure with no ground under it.
    max_faces : int, default 2 000 000
        The most faces read.
    max_extent : float, default 1e5
        The largest size of the model, metres (a guard against a file in the wrong units).
    origin : (float, float, float), optional
        The point of the file (in its Z-up axes) that becomes ``(0, 0, 0)``; by default the
        minimum corner of its bounding box.

    Raises
    ------
    MeshError
        Missing, empty or corrupt file, no triangles, NaN or infinite coordinates, more than
        ``max_faces`` faces, a model larger than ``max_extent`` metres, or (``closed=True``) open
        or non-manifold edges or inconsistent winding.
    MissingExtraError
        trimesh is not installed.

    Examples
    --------
    A 4 m x 2 m x 3 m block whose file stands in UTM coordinates, read in a frame of your site:

    >>> import pathlib, tempfile, numpy as np, trimesh
    >>> block = trimesh.creation.box(extents=(4.0, 2.0, 3.0))
    >>> _ = block.apply_translation([512002.0, 4180001.0, 121.5])  # its base at 120 m
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "block.stl"
    >>> _ = block.export(path)
    >>> site = np.array([512000.0, 4180000.0, 100.0])
    >>> structure = load_structure(path, origin=site)  # local = file - site
    >>> structure.part_names, structure.surface.bounds.tolist()  # the ground plane reaches 10 m beyond
    (('ground', 'contact', 'structure'), [[-10.0, -10.0, 20.0], [14.0, 12.0, 23.0]])
    """
    text = existing_path(path, "mesh", MeshError)
    size = os.path.getsize(text)
    if size == 0:
        raise MeshError(f"{text!r} is empty")
    if size > MAX_MESH_BYTES:
        raise MeshError(f"{text!r} is {size} bytes, more than the {MAX_MESH_BYTES} a structure may have")
    closed, add_ground = as_bool(closed, "closed"), as_bool(add_ground, "add_ground")
    max_faces = as_positive_int(max_faces, "max_faces")
    max_extent = as_positive_float(max_extent, "max_extent")
    loaded = load_mesh(text, up=up, scale=scale, origin=origin)
    vertices, faces = loaded.terrain.vertices, np.array(loaded.terrain.faces)
    if faces.shape[0] > max_faces:
        raise MeshError(f"{text}: {faces.shape[0]} faces, more than max_faces={max_faces}")
    extent = float(np.max(vertices.max(axis=0) - vertices.min(axis=0)))
    if not extent <= max_extent:
        raise MeshError(f"{text}: the model is {extent:.3g} m across, more than max_extent={max_extent:g} m (wrong units?)")
    report = loaded.mesh_report
    if closed:
        cracks = report.degenerate_faces and not report.nonmanifold_edges and zero_width_cracks(vertices, faces)  # of dropped slivers
        if (report.boundary_edges or report.nonmanifold_edges) and not cracks:
            raise MeshError(
                f"{text}: not a closed solid ({report.boundary_edges} open and {report.nonmanifold_edges} non-manifold edges); "
                "pass closed=False (uavcov plan: --open-mesh) to read it as an open surface"
            )
        directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
        if np.unique(directed, axis=0).shape[0] != directed.shape[0]:
            raise MeshError(f"{text}: inconsistent winding (an edge runs the same way in both its faces)")
    if closed:
        for component in connected_faces(faces, vertices.shape[0]):
            if signed_volume(vertices, faces[component]) < 0:
                faces[component] = faces[component][:, ::-1]
    name = os.path.splitext(os.path.basename(text))[0]
    sheet = None
    if add_ground:
        lo, hi = vertices.min(axis=0), vertices.max(axis=0)
        # Half the model's size, and at least room to stand off beside a small model (a 1 m part,
        # a sign): a ground of half a 1 m model leaves a flight box narrower than a 2 m standoff.
        margin = max(0.5 * float(max(hi[0] - lo[0], hi[1] - lo[1])), MIN_GROUND_MARGIN)
        sheet = ground(lo[0] - margin, hi[0] + margin, lo[1] - margin, hi[1] + margin, max(2.0 * margin / 20.0, 1e-3), z=float(lo[2]))
    return _assemble(name, [Piece(vertices, faces, ("structure",) * faces.shape[0])], sheet)
