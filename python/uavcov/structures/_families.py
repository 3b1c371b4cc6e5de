"""Randomised families of structures no one here tuned on (issue 42).

Each family is a function ``family(rng) -> Structure`` whose proportions are all drawn from
``rng`` over wide ranges, built like the five fixed scenes (closed solids wound outward on a
ground sheet, every face named after its part): a seed is one structure. The experiment
(``uavcov reproduce structures``) chooses its settings on development seeds and reports on
others, as Table 1 does.

:func:`building_family`
    A block of 3 to 8 storeys with an optional open courtyard, balconies on its long sides, a
    roof slab overhanging every wall and an entrance canopy.
:func:`girder_bridge_family`
    A deck of 30 to 70 m, 6 to 14 m up, on 2 to 4 girders and 1 to 3 piers, with abutments and
    parapets.
:func:`arch_bridge_family`
    A deck arch bridge of 30 to 60 m span and a rise of 0.12 to 0.3 of it.
:func:`tower_family`
    A tapered tower of 20 to 60 m with a nacelle-like head, and blades (a turbine) or not.
:func:`pylon_family`
    A lattice pylon: four legs, braces on its faces, a cross-arm, all of random proportions.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validate import as_generator
from ._solids import Piece, box, cells, frustum, ground, refine
from ._structures import CONTACT, Structure, _assemble, arch_pieces, pylon_pieces


def _grid(*breaks: list[float], step: float) -> tuple[np.ndarray, ...]:
    return tuple(refine(b, step) for b in breaks)


def _centres(xs: np.ndarray, ys: np.ndarray, zs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    cx, cy, cz = ((q[:-1] + q[1:]) / 2 for q in (xs, ys, zs))
    x, y, z = np.meshgrid(cx, cy, cz, indexing="ij")
    return x, y, z


def building_family(rng: Any = None, *, step: float = 1.5) -> Structure:
    """A building of random proportions with the parts a plain box lacks.

    Parts: ground, walls, roof (the overhanging slab: its underside is seen from below),
    balconies, canopy, contact. Drawn from ``rng``: footprint 12-30 m by 10-22 m, 3-8 storeys of
    3 m, a courtyard open to the sky (half the seeds, on footprints at least 18 m by 16 m), a
    roof overhang of 0.8-2 m, balconies 1-1.6 m deep on storeys 2 and up of both long sides,
    and a canopy 1.5-3 m deep over the entrance.
    """
    g = as_generator(rng)
    width, depth = float(g.uniform(12.0, 30.0)), float(g.uniform(10.0, 22.0))
    storeys = int(g.integers(3, 9))
    height = 3.0 * storeys
    overhang, slab = float(g.uniform(0.8, 2.0)), 0.5
    balcony = float(g.uniform(1.0, 1.6))
    canopy_depth = float(g.uniform(1.5, 3.0))
    courtyard = bool(g.random() < 0.5) and width >= 18.0 and depth >= 16.0
    court = (width * 0.3, width * 0.7, depth * 0.3, depth * 0.7)
    bays = max(2, int(width // 5.0))
    bay = width / bays
    door = (width / 2 - 2.0, width / 2 + 2.0)
    out = max(overhang, balcony, canopy_depth) + 0.5
    xs_b = [-overhang, 0.0, width, width + overhang, *door] + [b * bay + s for b in range(bays) for s in (0.6, bay - 0.6)]
    ys_b = [-out, -canopy_depth, -balcony, -overhang, 0.0, depth, depth + balcony, depth + overhang]
    zs_b = [0.0, 3.0, 3.3, height, height + slab] + [3.0 * s + d for s in range(2, storeys) for d in (0.0, 0.25)]
    if courtyard:
        xs_b += [court[0], court[1]]
        ys_b += [court[2], court[3]]
    xs, ys, zs = _grid(xs_b, ys_b, zs_b, step=step)
    x, y, z = _centres(xs, ys, zs)
    label = np.full(x.shape, -1, dtype=np.int64)
    inside = (x > 0) & (x < width) & (y > 0) & (y < depth)
    if courtyard:
        inside &= ~((x > court[0]) & (x < court[1]) & (y > court[2]) & (y < court[3]))
    label[inside & (z < height)] = 0
    roof = (x > -overhang) & (x < width + overhang) & (y > -overhang) & (y < depth + overhang) & (z > height) & (z < height + slab)
    if courtyard:
        roof &= ~((x > court[0]) & (x < court[1]) & (y > court[2]) & (y < court[3]))
    label[roof] = 1
    for s in range(2, storeys):
        level = (z > 3.0 * s) & (z < 3.0 * s + 0.25)
        for b in range(bays):
            along = (x > b * bay + 0.6) & (x < (b + 1) * bay - 0.6)
            label[level & along & (((y > -balcony) & (y < 0)) | ((y > depth) & (y < depth + balcony)))] = 2
    label[(x > door[0]) & (x < door[1]) & (y > -canopy_depth) & (y < 0) & (z > 3.0) & (z < 3.3)] = 3
    solid = cells(xs, ys, zs, label, ("walls", "roof", "balconies", "canopy"))
    margin = 12.0
    sheet = ground(-margin - out, width + margin + out, -margin - out, depth + margin + out, 2.0)
    return _assemble("building_family", [solid], sheet)


def girder_bridge_family(rng: Any = None, *, step: float = 1.5) -> Structure:
    """A girder bridge of random span, height, girders and piers.

    Parts: ground, deck_top, deck_underside, deck_edges, girders, piers, abutments, parapets,
    contact. Drawn from ``rng``: length 30-70 m, deck top 6-14 m up, deck 6-10 m wide, 2-4
    girders of 0.8-1.6 m depth, 1-3 piers spread along the span.
    """
    g = as_generator(rng)
    length, top = float(g.uniform(30.0, 70.0)), float(g.uniform(6.0, 14.0))
    half = float(g.uniform(3.0, 5.0))
    deck_bottom = top - 0.8
    girder_bottom = deck_bottom - float(g.uniform(0.8, 1.6))
    n_girders, n_piers = int(g.integers(2, 5)), int(g.integers(1, 4))
    girder_y = np.linspace(-half + 1.0, half - 1.0, n_girders)
    girders = [(float(c) - 0.25, float(c) + 0.25) for c in girder_y]
    piers = length * (np.arange(1, n_piers + 1) / (n_piers + 1)) + g.uniform(-1.0, 1.0, n_piers)
    names = ("deck_edges", "girders", "piers", "parapets", "abutments")
    xs, ys, zs = _grid(
        [-2.0, 0.0, length, length + 2.0] + [float(p) + s for p in piers for s in (-0.6, 0.6)],
        [-half, -half + 0.3, half - 0.3, half, -half + 0.7, half - 0.7] + [y for pair in girders for y in pair],
        [0.0, girder_bottom, deck_bottom, top, top + 1.0],
        step=step,
    )
    x, y, z = _centres(xs, ys, zs)
    label = np.full(x.shape, -1, dtype=np.int64)
    label[(x > 0) & (x < length) & (z > deck_bottom) & (z < top)] = 0
    for lo, hi in girders:
        label[(x > 0) & (x < length) & (y > lo) & (y < hi) & (z > girder_bottom) & (z < deck_bottom)] = 1
    for p in piers:
        label[(np.abs(x - p) < 0.6) & (np.abs(y) < half - 0.7) & (z < girder_bottom)] = 2
    label[(np.abs(y) > half - 0.3) & (z > top)] = 3
    label[((x < 0) | (x > length)) & (z < top)] = 4
    deck = cells(xs, ys, zs, label, names, up={0: "deck_top"}, down={0: "deck_underside"})
    return _assemble("girder_bridge_family", [deck], ground(-14.0, length + 14.0, -half - 12.0, half + 12.0, 2.0))


def arch_bridge_family(rng: Any = None, *, step: float = 1.5) -> Structure:
    """A deck arch bridge of random span and rise.

    Parts: ground, arch, columns, deck_top, deck_underside, deck, abutments, parapets, contact.
    Drawn from ``rng``: span 30-60 m, rise 0.12-0.3 of the span, 1.5-4 m from the crown's top to
    the deck.
    """
    g = as_generator(rng)
    span = float(g.uniform(30.0, 60.0))
    rise = span * float(g.uniform(0.12, 0.3))
    clearance = float(g.uniform(1.5, 4.0))
    return _assemble("arch_bridge_family", arch_pieces(span, rise, clearance, step), ground(-15.0, span + 15.0, -16.0, 16.0, 2.0))


def tower_family(rng: Any = None) -> Structure:
    """A tower of random proportions with a head, and three blades on half the seeds.

    Parts: ground, tower, head, blades (when drawn), contact. Drawn from ``rng``: height 20-60 m,
    base radius 1.2-3 m tapering to 50-80 % of it, a head 3-8 m long, blades 0.3-0.6 of the
    height at a random rotor angle.
    """
    g = as_generator(rng)
    height = float(g.uniform(20.0, 60.0))
    base = float(g.uniform(1.2, 3.0))
    radius_top = base * float(g.uniform(0.5, 0.8))
    head_length, head_height = float(g.uniform(3.0, 8.0)), float(g.uniform(2.0, 4.0))
    turbine = bool(g.random() < 0.5)
    blade = height * float(g.uniform(0.3, 0.6))
    azimuth = float(g.uniform(0.0, 2.0 * math.pi / 3.0))
    slices = max(4, int(height // 4.0))
    pieces: list[Piece] = [
        frustum(np.zeros(3), np.array([0.0, 0.0, height]), (base, radius_top), "tower", sides=20, slices=slices, caps=(None, CONTACT))
    ]
    half = radius_top + 0.5
    # The head's front clears the tower's widest section, so the blades turn in front of it.
    front = max(head_length - half, base + 1.0)
    pieces.append(box((-half, -half, height), (front, half, height + head_height), "head", step=1.5))
    if turbine:
        hub = np.array([front + 0.8, 0.0, height + head_height / 2])
        u, v = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0])
        for k in range(3):
            angle = azimuth + 2.0 * math.pi * k / 3
            direction = math.cos(angle) * u + math.sin(angle) * v
            pieces.append(
                frustum(
                    hub + 1.0 * direction,
                    blade * direction,
                    (0.5, 0.15),
                    "blades",
                    sides=10,
                    slices=8,
                    flat=(0.5, 0.3),
                    across=np.array([1.0, 0.0, 0.0]),
                )
            )
    reach = max(front, blade if turbine else 0.0) + 12.0
    return _assemble("tower_family", pieces, ground(-reach, reach, -reach, reach, 3.0))


def pylon_family(rng: Any = None) -> Structure:
    """A lattice pylon of random proportions.

    Parts: ground, legs, braces, crossarm, contact. Drawn from ``rng``: base 4-9 m, 6-12 panels of
    2.5-4 m, legs 0.4-0.7 m, a cross-arm reaching 3-8 m beyond the legs.
    """
    g = as_generator(rng)
    base, leg = float(g.uniform(4.0, 9.0)), float(g.uniform(0.4, 0.7))
    panels, panel = int(g.integers(6, 13)), float(g.uniform(2.5, 4.0))
    arm = float(g.uniform(3.0, 8.0))
    pieces = pylon_pieces(base, leg, panels, panel, arm)
    return _assemble("pylon_family", pieces, ground(-arm - 10.0, base + arm + 10.0, -12.0, base + 12.0, 1.5))


STRUCTURE_FAMILIES: dict[str, Callable[..., Structure]] = {
    "building": building_family,
    "girder_bridge": girder_bridge_family,
    "arch_bridge": arch_bridge_family,
    "tower": tower_family,
    "pylon": pylon_family,
}
