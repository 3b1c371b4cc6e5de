"""Partial knowledge of a 3D structure and the surface S' made from it.

A :class:`StructurePrior` is either known points on the structure (:func:`sample_structure_prior`:
area-uniform, optional Gaussian noise, normals) or a coarse model (:func:`coarse_structure_prior`:
boxes around the parts, or the mesh decimated by vertex clustering).
:func:`reconstruct_structure` makes S' (a closed, outward-wound mesh) from either;
:func:`reconstruction_error` measures S' against the truth (Hausdorff both ways, mean distance,
area ratio, the share of S' facing into the structure). ``python scripts/structure_reconstruction.py``
writes the table of docs/structures.md.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import (
    MAX_COORDINATE_M,
    as_bool,
    as_count,
    as_generator,
    as_non_negative_float,
    as_points,
    as_positive_float,
    read_only,
    within_coordinate_bound,
)
from ..engine import Terrain, degenerate_faces
from ..errors import InvalidInputError, InvalidTypeError, MissingExtraError
from ._envelope import ENVELOPE_GAPS, envelope
from ._facing import facing_into
from ._outer_surface import alpha_solid, check_prior_points, is_closed, normal_vote, oriented_solid, outer_shells, separate_groups
from ._solids import box, face_normals, join, signed_volume
from ._structures import CONTACT, Structure, connected_faces

MAX_PRIOR_POINTS = 10_000_000
PRIOR_KINDS = ("points", "boxes", "decimated")
RECONSTRUCTION_METHODS = ("auto", "model", "oriented", "alpha", "hulls", "poisson", "ball_pivoting")
MIN_POINTS = 20


@dataclass(frozen=True, eq=False)
class StructurePrior:
    """What is known of a structure before flying.

    Attributes
    ----------
    points : (n, 3) float64 ndarray
        Known points (m): samples on the surface for ``kind="points"``, the model's vertices for a
        coarse model.
    normals : (n, 3) float64 ndarray or None
        Outward unit normals at ``points`` when the source gives them.
    kind : {"points", "boxes", "decimated"}
    model : Terrain or None
        The coarse model (closed solids wound outward) for ``kind != "points"``.
    noise : float
        Standard deviation of the Gaussian noise added to the points (m).
    """

    points: np.ndarray
    normals: np.ndarray | None
    kind: str
    model: Terrain | None = None
    noise: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.kind, str) or self.kind not in PRIOR_KINDS:
            raise InvalidInputError(f"kind must be one of {PRIOR_KINDS}, got {self.kind!r}")
        points = within_coordinate_bound(as_points(self.points, "points"), "points").copy()  # S' is made of them
        object.__setattr__(self, "points", read_only(points))
        if self.normals is not None:
            normals = as_points(self.normals, "normals").copy()
            if normals.shape != points.shape:
                raise InvalidInputError(f"{normals.shape[0]} normals for {points.shape[0]} points")
            object.__setattr__(self, "normals", read_only(normals))
        if self.model is not None and not isinstance(self.model, Terrain):
            raise InvalidTypeError(f"model must be a Terrain, got {type(self.model).__name__}")
        if (self.kind == "points") != (self.model is None):
            raise InvalidInputError("a 'points' prior has no model; a coarse prior needs one")
        object.__setattr__(self, "noise", as_non_negative_float(self.noise, "noise"))

    @property
    def spacing(self) -> float:
        """The known points' median distance to their nearest other known point (m).

        The scale on which they describe the surface (about 1-2 m for 100 points on the
        families of :data:`STRUCTURE_FAMILIES`); 0 when fewer than two points are distinct.
        """
        from scipy.spatial import cKDTree

        distinct = np.unique(self.points, axis=0)
        if distinct.shape[0] < 2:
            return 0.0
        nearest, _ = cKDTree(distinct).query(distinct, k=2)
        return float(np.median(nearest[:, 1]))

    def behind(self, points: Any, *, reach: float | None = None) -> np.ndarray:
        """Whether the known points' normals put each point inside the structure.

        The vote of :func:`reconstruct_structure`'s ``"oriented"`` method (the six nearest known
        points, closer ones weighing more, see it behind their tangent planes): evidence of a
        part S' may not resolve, as a girder or a balcony between known points. All ``False``
        without normals.

        Parameters
        ----------
        points : (m, 3) array_like of float
            Metres.
        reach : float, optional
            Judge only the points within ``reach`` metres of a known point; the others are not
            behind. A tangent plane speaks for the surface near its point: several spacings
            away (inside a lattice pylon's tent seen from 5 m off, under an arch) the vote
            extrapolates, and a CVT start it steered lifted 1-3 of 8 UAVs over the top on the
            development seeds (docs/structures.md).

        Returns
        -------
        (m,) bool ndarray
        """
        queries = within_coordinate_bound(as_points(points, "points", allow_empty=True), "points")  # squared distances stay finite
        reach = None if reach is None else as_non_negative_float(reach, "reach")
        if self.normals is None or not queries.shape[0]:
            return np.zeros(queries.shape[0], dtype=bool)
        unit = self.normals / np.linalg.norm(self.normals, axis=1)[:, None]
        inside = normal_vote(self.points, unit, queries) < 0.0
        if reach is not None:
            from scipy.spatial import cKDTree

            distance, _ = cKDTree(self.points).query(queries)
            inside &= distance <= reach
        return np.asarray(inside, dtype=bool)

    def __reduce__(self) -> tuple[Any, ...]:
        normals = None if self.normals is None else np.array(self.normals)
        return (StructurePrior, (np.array(self.points), normals, self.kind, self.model, self.noise))


def _check_structure(structure: Any) -> Structure:
    if not isinstance(structure, Structure):
        raise InvalidTypeError(f"expected a Structure, got {type(structure).__name__}")
    return structure


def _sample_faces(vertices: np.ndarray, faces: np.ndarray, n: int, generator: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """``n`` points uniform over the area of ``faces`` and the face each lies on."""
    _, areas = face_normals(vertices, faces)
    chosen = generator.choice(faces.shape[0], size=n, p=areas / areas.sum())
    r1, r2 = generator.random(n), generator.random(n)
    root = np.sqrt(r1)
    a, b, c = (vertices[faces[chosen, k]] for k in range(3))
    points = (1 - root)[:, None] * a + (root * (1 - r2))[:, None] * b + (root * r2)[:, None] * c
    return points, chosen


def sample_structure_prior(
    structure: Structure,
    n: int,
    *,
    noise: float = 0.0,
    normals: bool = True,
    include_ground: bool = False,
    rng: Any = None,
) -> StructurePrior:
    """``n`` known points drawn uniformly over the structure's area (contact faces left out).

    Parameters
    ----------
    structure : Structure
    n : int
        Number of points, 1 to 10^7.
    noise : float
        Standard deviation (m) of isotropic Gaussian noise added to each point.
    normals : bool
        Keep the true outward normal of the face each point was drawn on (a scanner or a
        photogrammetric model gives them); the normals carry no noise.
    include_ground : bool
        Also draw points on the ground plane.
    rng : None, int or numpy.random.Generator
    """
    structure = _check_structure(structure)
    n = as_count(n, "n", MAX_PRIOR_POINTS)
    noise = as_non_negative_float(noise, "noise")
    normals, include_ground = as_bool(normals, "normals"), as_bool(include_ground, "include_ground")
    generator = as_generator(rng)
    faces = structure.surface.faces[structure.face_mask(include_ground=include_ground)]
    points, chosen = _sample_faces(structure.surface.vertices, faces, n, generator)
    if noise > 0:
        points = points + generator.normal(scale=noise, size=points.shape)
    face_normal = face_normals(structure.surface.vertices, faces[chosen])[0] if normals else None
    return StructurePrior(points, face_normal, "points", None, noise)


def _solid_faces(structure: Structure) -> np.ndarray:
    keep = np.ones(structure.surface.n_faces, dtype=bool)
    if structure.ground_part is not None:
        keep &= structure.face_parts != structure.ground_part
    return keep


def coarse_structure_prior(structure: Structure, kind: str = "boxes", *, cell: float | None = None) -> StructurePrior:
    """A coarse model of the structure (ground left out) as the prior.

    Parameters
    ----------
    structure : Structure
    kind : {"boxes", "decimated"}
        ``"boxes"``: the axis-aligned bounding box of each connected piece of each part (what a
        plan drawing or a BIM block model gives). ``"decimated"``: the solids' mesh simplified by
        vertex clustering on a grid of ``cell`` metres (each cell's vertices merged into their
        mean; collapsed and doubled faces dropped).
    cell : float, optional
        Clustering cell for ``"decimated"`` (m); default 1/30 of the structure's largest side.

    Returns
    -------
    StructurePrior
        ``points`` are the model's vertices, ``normals`` None.
    """
    structure = _check_structure(structure)
    vertices, faces = structure.surface.vertices, structure.surface.faces
    if not isinstance(kind, str):  # before any comparison: an array's == is elementwise
        raise InvalidInputError(f"kind must be 'boxes' or 'decimated', got {kind!r}")
    cell = None if cell is None else as_positive_float(cell, "cell")  # whatever the kind: an ignored cell is a mistake too
    if kind == "boxes":
        pieces = []
        for index, name in enumerate(structure.part_names):
            if index == structure.ground_part or name == CONTACT:
                continue
            here = faces[structure.face_parts == index]
            for component in connected_faces(here, structure.surface.n_vertices):
                corners = vertices[np.unique(here[component])]
                lo, hi = corners.min(axis=0), corners.max(axis=0)
                # A flat piece (a face of a larger solid) still gets a box: 1 cm thick.
                hi = np.maximum(hi, lo + 0.01)
                pieces.append(box(tuple(lo), tuple(hi), name))
        model_vertices, model_faces, _ = join(pieces)
    elif kind == "decimated":
        solid = faces[_solid_faces(structure)]
        used = np.unique(solid)
        lo, hi = vertices[used].min(axis=0), vertices[used].max(axis=0)
        extent = float(np.max(hi - lo))
        size = extent / 30.0 if cell is None else cell
        if extent > 1e15 * size:  # the cells' integer keys would overflow; far before, every vertex has a cell of its own
            raise InvalidInputError(f"cell {size:g} m is too fine for the structure's {extent:g} m: at least {extent * 1e-15:g} m")
        keys = np.floor((vertices - lo) / size).astype(np.int64)
        _, cluster = np.unique(keys[used], axis=0, return_inverse=True)
        cluster = cluster.reshape(-1)
        label = np.full(vertices.shape[0], -1, dtype=np.int64)
        label[used] = cluster
        model_vertices = np.zeros((cluster.max() + 1, 3))
        np.add.at(model_vertices, cluster, vertices[used])
        model_vertices /= np.bincount(cluster)[:, None]
        mapped = label[solid]
        mapped = mapped[(mapped[:, 0] != mapped[:, 1]) & (mapped[:, 1] != mapped[:, 2]) & (mapped[:, 0] != mapped[:, 2])]
        # A triangle kept in both windings is a sheet of no thickness: drop both copies.
        key = np.sort(mapped, axis=1)
        _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        model_faces = mapped[counts[inverse.reshape(-1)] == 1]
        _, areas = face_normals(model_vertices, model_faces)
        model_faces = model_faces[areas > 1e-12 * size * size]
        if model_faces.shape[0] == 0:
            raise InvalidInputError(f"cell {size} m collapses the whole structure; use a smaller cell")
    else:
        raise InvalidInputError(f"kind must be 'boxes' or 'decimated', got {kind!r}")
    model = Terrain(model_vertices, model_faces)
    return StructurePrior(model.vertices, None, kind, model, 0.0)


def _cluster_hulls(points: np.ndarray, clusters: int | None, generator: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Convex hulls of k-means clusters of the points (k = n / 10 by default), each outward."""
    from scipy.cluster.vq import kmeans2
    from scipy.spatial import ConvexHull, QhullError

    k = max(1, points.shape[0] // 10) if clusters is None else as_count(clusters, "clusters", points.shape[0])
    _, label = kmeans2(points, k, minit="++", seed=generator)
    vertices, faces, offset = [], [], 0
    for q in range(k):
        member = points[label == q]
        if member.shape[0] < 4:
            continue
        try:
            hull = ConvexHull(member, qhull_options="QJ")
        except QhullError:
            continue
        tri = hull.simplices.copy()
        normal, _ = face_normals(member, tri)
        inward = np.einsum("ij,ij->i", normal, hull.equations[:, :3]) < 0
        tri[inward] = tri[inward][:, ::-1]
        vertices.append(member)
        faces.append(tri + offset)
        offset += member.shape[0]
    if not faces:
        raise InvalidInputError("no cluster of the known points has 4 points spanning a volume")
    return np.concatenate(vertices), np.concatenate(faces)


def _open3d(points: np.ndarray, normals: np.ndarray | None, method: str, depth: int) -> tuple[np.ndarray, np.ndarray]:
    try:
        import open3d
    except ImportError as exc:
        raise MissingExtraError(f"method={method!r} needs Open3D: pip install 'uavcov[reconstruct]' (or pip install open3d-cpu)") from exc
    if normals is None:
        raise InvalidInputError(f"method={method!r} needs points with normals (sample_structure_prior(..., normals=True))")
    # A repeated point is one sample: Open3D's octree and ball pivoting each mishandle copies.
    _, first = np.unique(points, axis=0, return_index=True)
    first = np.sort(first)
    unit = normals[first] / np.linalg.norm(normals[first], axis=1)[:, None]
    cloud = open3d.geometry.PointCloud(open3d.utility.Vector3dVector(np.array(points[first])))
    cloud.normals = open3d.utility.Vector3dVector(unit)
    try:
        if method == "poisson":
            mesh, _ = open3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=depth)
        else:
            spacing = np.asarray(cloud.compute_nearest_neighbor_distance())
            radius = float(np.median(spacing)) * 1.5
            mesh = open3d.geometry.TriangleMesh.create_from_point_cloud_ball_pivoting(
                cloud, open3d.utility.DoubleVector([radius, 2 * radius, 4 * radius])
            )
    except RuntimeError as exc:
        reason = re.sub(r"\x1b\[[0-9;]*m", "", str(exc)).strip()
        raise InvalidInputError(f"Open3D's {method} reconstruction failed on the known points: {reason}") from None
    vertices, faces = np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.triangles, dtype=np.int64)
    # Poisson's marching cubes leaves zero-area triangles on thin parts (arch bridge 1002 at 100
    # and 3000 points): they have no side, and the engine refuses them.
    return vertices, faces[~degenerate_faces(vertices, faces)] if faces.shape[0] else faces


def _each_group(prior: StructurePrior, method: str, alpha: float | None) -> tuple[np.ndarray, np.ndarray]:
    """``"oriented"`` or ``"alpha"`` on each group of known points far from the others
    (:func:`separate_groups`), the pieces joined: the air between separate structures is no
    part of S'. A group that makes no solid alone is made with the others, as one."""

    def solid(points: np.ndarray, normals: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        return oriented_solid(points, normals) if normals is not None else alpha_solid(points, alpha)

    normals = prior.normals if method == "oriented" else None
    groups = separate_groups(prior.points, prior.spacing)
    if len(groups) > 1:
        vertices, faces, offset = [], [], 0
        try:
            for group in groups:
                piece_vertices, piece_faces = solid(prior.points[group], None if normals is None else normals[group])
                vertices.append(piece_vertices)
                faces.append(piece_faces + offset)
                offset += piece_vertices.shape[0]
            return np.concatenate(vertices), np.concatenate(faces)
        except InvalidInputError:
            pass
    return solid(prior.points, normals)


DEFAULT_METHOD = "oriented"


def reconstruct_structure(
    prior: StructurePrior,
    *,
    method: str = "auto",
    alpha: float | None = None,
    clusters: int | None = None,
    poisson_depth: int = 6,
    min_points: int = MIN_POINTS,
    margin: float | None = None,
    rng: Any = None,
) -> Terrain:
    """S', the surface the team is placed on, from a prior.

    Every argument is checked whatever the method, those it does not use too.

    Parameters
    ----------
    prior : StructurePrior
    method : {"auto", "model", "oriented", "alpha", "hulls", "poisson", "ball_pivoting"}
        ``"auto"``: the coarse model when the prior has one, else ``"oriented"`` for points with
        normals and ``"alpha"`` without (chosen by the missions they give, docs/structures.md).
        ``"oriented"``: the Delaunay tetrahedra the known normals put inside, their boundary
        (the outer surface only, wound outward). ``"alpha"``: the alpha shape of the points'
        Delaunay tetrahedra with its cavities filled (scipy). ``"hulls"``: convex hulls of
        k-means clusters of the points. ``"poisson"``, ``"ball_pivoting"``: Open3D's (optional
        extra, need normals), keeping the pieces no other encloses, each turned outward. Every
        method first refuses degenerate points (too few distinct, non-finite or beyond 1e15 m,
        on a line or a plane, zero normals).
    alpha : float, optional
        Circumradius limit of ``"alpha"`` (m); default the least that leaves no point out.
    clusters : int, optional
        Number of clusters of ``"hulls"``; default n / 10.
    poisson_depth : int
        Octree depth of ``"poisson"``.
    min_points : int
        Fewer known points than this is too sparse (default 20).
    margin : float, optional
        Metres by which a surface made from points is grown outward into an envelope of the
        structure (the boundary of the points within ``margin`` of its solid, docs/structures.md):
        the structure bulges out of any surface through its known points between them, and
        there S' would face into it. Default 0.75 (``ENVELOPE_GAPS``) times the mean gap between
        the known points on S' (``sqrt(area / n)``; 2-3.5 m for 100 points on the families of
        :data:`STRUCTURE_FAMILIES`); 0 returns the surface through the points. A coarse model
        (``"model"``) and an open surface (Open3D's sheets) are returned as they are.
    rng : None, int or numpy.random.Generator
        For ``"hulls"``' clustering.

    Returns
    -------
    Terrain
        S' with outward normals: a closed mesh of positive volume (the envelope, or with
        ``margin=0`` the surface of ``"oriented"``, ``"alpha"`` and ``"hulls"``, or the model);
        Open3D's surfaces with ``margin=0`` are turned to agree with the points' normals.

    Raises
    ------
    InvalidInputError
        Too few points, points spanning no volume, an unknown method, or a result that is empty
        or has no outward orientation.
    MissingExtraError
        An Open3D method without Open3D.
    """
    if not isinstance(prior, StructurePrior):
        raise InvalidTypeError(f"expected a StructurePrior, got {type(prior).__name__}")
    if not isinstance(method, str) or method not in RECONSTRUCTION_METHODS:
        raise InvalidInputError(f"method must be one of {RECONSTRUCTION_METHODS}, got {method!r}")
    # Every setting is checked whatever the method: one the method ignores is still a mistake.
    alpha = None if alpha is None else as_positive_float(alpha, "alpha")
    clusters = None if clusters is None else as_count(clusters, "clusters", MAX_PRIOR_POINTS)
    poisson_depth = as_count(poisson_depth, "poisson_depth", 12)
    min_points = as_count(min_points, "min_points", MAX_PRIOR_POINTS, minimum=4)
    margin = None if margin is None else as_non_negative_float(margin, "margin")
    if margin is not None and margin > MAX_COORDINATE_M:  # the envelope's grid would lie beyond the engine's bound
        raise InvalidInputError(f"margin must be at most {MAX_COORDINATE_M:g} m, got {margin:g}")
    generator = as_generator(rng)
    if method == "model" or (method == "auto" and prior.model is not None):
        if prior.model is None:
            raise InvalidInputError("method='model' needs a coarse prior (coarse_structure_prior)")
        return prior.model
    if method == "auto":
        method = DEFAULT_METHOD if prior.normals is not None else "alpha"
    points = prior.points
    if points.shape[0] < min_points:
        raise InvalidInputError(f"{points.shape[0]} known points are too sparse to reconstruct a structure (at least {min_points})")
    # Every method gets the same checked cloud: nothing degenerate reaches scipy or Open3D.
    check_prior_points(points, prior.normals, min_points)
    if method in ("oriented", "alpha"):
        if method == "oriented" and prior.normals is None:
            raise InvalidInputError("method='oriented' needs points with normals (sample_structure_prior(..., normals=True))")
        vertices, faces = _each_group(prior, method, alpha)
    elif method == "hulls":
        vertices, faces = _cluster_hulls(points, clusters, generator)
    else:
        vertices, faces = _open3d(points, prior.normals, method, poisson_depth)
        if faces.shape[0]:
            faces = outer_shells(vertices, faces, points, prior.normals)
    if faces.shape[0] == 0:
        raise InvalidInputError(f"method={method!r} made no surface from {points.shape[0]} points")
    if method in ("oriented", "alpha", "hulls") and not signed_volume(vertices, faces) > 0:
        raise InvalidInputError(f"method={method!r} made a surface with no outward orientation")
    surface = Terrain(vertices, faces, drop_degenerate=True)
    if margin is None:
        margin = ENVELOPE_GAPS * float(np.sqrt(surface.area / points.shape[0]))
    # Open3D's open sheets have no inside to grow from: they are returned as they are.
    return envelope(surface, margin) if margin > 0 and is_closed(surface.faces) else surface


@dataclass(frozen=True)
class ReconstructionError:
    """Distances between S' and the true structure (ground and contact faces left out).

    Attributes
    ----------
    hausdorff_m : float
        Symmetric Hausdorff distance (m): the larger of the two below.
    hausdorff_truth_to_approx_m : float
        Farthest a point of the structure is from S' (m): what S' misses.
    hausdorff_approx_to_truth_m : float
        Farthest a point of S' is from the structure (m): what S' invents.
    mean_m : float
        Mean of the two mean distances (m).
    mean_truth_to_approx_m, mean_approx_to_truth_m : float
    area_ratio : float
        Area of S' over the structure's area.
    n_samples : int
        Points drawn on each surface.
    inward_area_share : float
        Share of S''s area facing into the structure: the sampled points of S' whose outward
        normal points into a real solid (the faces a start would fly out along into the
        structure). Outside the solids, judged against the outward normal of the nearest real
        face (of those holding the nearest point, the one agreeing best); inside one, by the way
        out along the normal's own line (``n`` faces in when the solid reaches farther along
        ``n`` than against it), so that a face of S' lying a little inside a wall with the wall's
        normal does not count: orientation, not position (``structures/_facing.py``).
    """

    hausdorff_m: float
    hausdorff_truth_to_approx_m: float
    hausdorff_approx_to_truth_m: float
    mean_m: float
    mean_truth_to_approx_m: float
    mean_approx_to_truth_m: float
    area_ratio: float
    n_samples: int
    inward_area_share: float


def reconstruction_error(truth: Structure, approx: Terrain, *, n_samples: int = 20_000, rng: Any = 0) -> ReconstructionError:
    """Compare S' with the structure by ``n_samples`` area-uniform points on each surface.

    Distances are from each point to the closest point of the other surface
    (:meth:`Terrain.closest_point`); the sample maxima approach the Hausdorff distances from
    below as ``n_samples`` grows.
    """
    truth = _check_structure(truth)
    if not isinstance(approx, Terrain):
        raise InvalidTypeError(f"approx must be a Terrain, got {type(approx).__name__}")
    n_samples = as_count(n_samples, "n_samples", MAX_PRIOR_POINTS)
    generator = as_generator(rng)
    true_faces = truth.surface.faces[truth.face_mask(include_ground=False)]
    true_surface = Terrain(truth.surface.vertices, true_faces)
    on_truth, _ = _sample_faces(truth.surface.vertices, true_faces, n_samples, generator)
    on_approx, approx_face = _sample_faces(approx.vertices, approx.faces, n_samples, generator)
    to_approx = np.linalg.norm(approx.closest_point(on_truth) - on_truth, axis=1)
    to_truth = np.linalg.norm(true_surface.closest_point(on_approx) - on_approx, axis=1)
    # Which way the solid faces, contact faces included: S''s bottom faces the ground as the
    # structure's contact faces do, and must not be judged against the nearest wall.
    solid = Terrain(truth.surface.vertices, truth.surface.faces[_solid_faces(truth)])
    into = facing_into(solid, on_approx, approx.face_normals[approx_face])
    return ReconstructionError(
        hausdorff_m=float(max(to_approx.max(), to_truth.max())),
        hausdorff_truth_to_approx_m=float(to_approx.max()),
        hausdorff_approx_to_truth_m=float(to_truth.max()),
        mean_m=float(0.5 * (to_approx.mean() + to_truth.mean())),
        mean_truth_to_approx_m=float(to_approx.mean()),
        mean_approx_to_truth_m=float(to_truth.mean()),
        area_ratio=float(approx.area / true_surface.area),
        n_samples=n_samples,
        inward_area_share=float(np.mean(into)),
    )
