"""Mesh files and arrays as surfaces: OBJ / STL / PLY (``load_mesh``, needs ``trimesh``) or
arrays (``mesh_terrain``), welded and repaired by ``clean_mesh`` with a
:class:`MeshReport` of what was changed, in a recentred :class:`~uavcov.terrain.LocalFrame`.

Elevation grids with a coordinate reference system are :class:`~uavcov.terrain.GeoDem`'s
(:func:`~uavcov.terrain.read_dem`, :func:`~uavcov.terrain.dem_from_array`).
"""

from __future__ import annotations

import io
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from .._validate import (
    MAX_COORDINATE_M,
    as_float_array,
    as_index_array,
    as_non_negative_int,
    as_positive_float,
    existing_path,
)
from ..engine import Terrain, degenerate_faces
from ..errors import InvalidInputError, MeshError, MissingExtraError
from ._frame import LocalFrame
from ._mesh_headers import check_binary_stl_size, check_ply_counts, ply_element_counts


@dataclass(frozen=True)
class MeshReport:
    """What ``clean_mesh`` found and repaired in a mesh (all counts).

    Attributes
    ----------
    merged_vertices : int
        Vertices dropped because another vertex has exactly the same coordinates (STL files
        store every triangle's corners separately).
    unused_vertices : int
        Vertices no face refers to, dropped.
    degenerate_faces : int
        Faces with a repeated vertex or zero area, dropped.
    duplicate_faces : int
        Faces over the same three vertices as an earlier face (in any order), dropped.
    boundary_edges : int
        Edges of only one face. A terrain is an open sheet, so these are expected and kept.
    nonmanifold_edges : int
        Edges of three faces or more; kept (visibility needs no manifold), reported.
    """

    merged_vertices: int = 0
    unused_vertices: int = 0
    degenerate_faces: int = 0
    duplicate_faces: int = 0
    boundary_edges: int = 0
    nonmanifold_edges: int = 0

    def __post_init__(self) -> None:
        # Counts, so that a report read back or built by hand never says "nan faces repaired".
        for field in fields(self):
            object.__setattr__(self, field.name, as_non_negative_int(getattr(self, field.name), field.name))

    @property
    def repaired(self) -> bool:
        """True when faces were dropped (degenerate or duplicate)."""
        return self.degenerate_faces + self.duplicate_faces > 0


@dataclass(frozen=True)
class LoadedMesh:
    """A mesh read from a file or arrays, with what is needed to map results back.

    Attributes
    ----------
    terrain : Terrain
        The surface in the local metric frame (metres, Z up).
    frame : LocalFrame
        Local <-> source coordinates; ``frame.to_source(uav_positions)`` gives world positions.
    source : str
        Where the mesh came from (a path or a short description).
    mesh_report : MeshReport
        What was repaired.
    """

    terrain: Terrain
    frame: LocalFrame
    source: str
    mesh_report: MeshReport


def _within_coordinate_bound(points: np.ndarray, what: str) -> None:
    """Refuse a coordinate beyond :data:`MAX_COORDINATE_M` with the engine's own message."""
    beyond = np.abs(points) > MAX_COORDINATE_M
    if beyond.any():
        i = int(np.flatnonzero(beyond.any(axis=1))[0])
        raise MeshError(f"{what} {i} has a coordinate beyond 1e15 m in magnitude: {points[i].tolist()}")


def clean_mesh(vertices: Any, faces: Any) -> tuple[np.ndarray, np.ndarray, MeshReport]:
    """Repair a triangle mesh: merge coincident vertices, drop degenerate and duplicate faces.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        Finite coordinates (m).
    faces : array_like, shape (F, 3)
        Integer vertex indices in ``[0, V)``.

    Returns
    -------
    vertices : ndarray, shape (V', 3)
    faces : ndarray, shape (F', 3)
        Only referenced vertices, in the order they first appear, renumbered; the kept faces in
        their input order and orientation. A mesh without defects comes back unchanged.
    report : MeshReport

    Raises
    ------
    MeshError
        Indices out of range, or no face left.

    Notes
    -----
    Merging is exact (bitwise equal coordinates), which is what STL and unwelded OBJ/PLY
    exports produce. Open boundaries are kept: a terrain is an open sheet. Duplicate faces are
    dropped because a doubled triangle would double the coverage targets on it.
    """
    points = as_float_array(vertices, "vertices", nonfinite_error=MeshError)
    if points.ndim != 2 or points.shape[1] != 3:
        raise MeshError(f"vertices must have shape (V, 3), got {points.shape}")
    _within_coordinate_bound(points, "vertex")
    triangles = as_index_array(faces, "faces")
    if triangles.shape[0] == 0:
        raise MeshError("the mesh has no faces")
    if points.shape[0] == 0 or triangles.min() < 0 or triangles.max() >= points.shape[0]:
        raise MeshError(f"face indices must be in [0, {points.shape[0]}), got [{triangles.min()}, {triangles.max()}]")

    sorted_points, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    # Keep vertices in the order of their first appearance, so a clean mesh comes back as given.
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.shape[0])
    unique_points = sorted_points[order]
    inverse = rank[inverse.reshape(-1)]
    merged = points.shape[0] - unique_points.shape[0]
    triangles = inverse[triangles]

    t0, t1, t2 = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    repeated = (t0 == t1) | (t1 == t2) | (t0 == t2)
    # The zero-area rule of Terrain (relative to the bounding-box diagonal), so that nothing
    # this keeps is refused there.
    degenerate = repeated | degenerate_faces(unique_points, triangles)
    triangles = triangles[~degenerate]
    if triangles.shape[0] == 0:
        raise MeshError("every face of the mesh is degenerate (zero area)")

    keys = np.sort(triangles, axis=1)
    _, first = np.unique(keys, axis=0, return_index=True)
    keep = np.zeros(triangles.shape[0], dtype=bool)
    keep[first] = True
    duplicates = int((~keep).sum())
    triangles = triangles[keep]

    used = np.unique(triangles)
    renumber = np.full(unique_points.shape[0], -1, dtype=np.int64)
    renumber[used] = np.arange(used.shape[0])
    triangles = renumber[triangles]
    unused = unique_points.shape[0] - used.shape[0]

    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    report = MeshReport(
        merged_vertices=int(merged),
        unused_vertices=int(unused),
        degenerate_faces=int(degenerate.sum()),
        duplicate_faces=duplicates,
        boundary_edges=int((counts == 1).sum()),
        nonmanifold_edges=int((counts > 2).sum()),
    )
    return np.ascontiguousarray(unique_points[used]), np.ascontiguousarray(triangles), report


_UP_AXES = ("z", "y")


def mesh_terrain(
    vertices: Any,
    faces: Any,
    *,
    up: str = "z",
    origin: Any = None,
    scale: float = 1.0,
    on_defect: str = "repair",
    source: str = "arrays",
) -> LoadedMesh:
    """A triangle mesh (arrays in metres) as a Terrain in a local frame, repaired by ``clean_mesh``.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
    faces : array_like, shape (F, 3)
    up : {"z", "y"}
        The source's up axis. "y" (common in OBJ exports) maps source (x, y, z) to (x, -z, y).
    origin : (float, float, float), optional
        Source point that becomes the local origin; default: the minimum corner of the
        bounding box (after the up-axis change, so given in the Z-up source axes).
    scale : float
        Uniform model scale (1 = true size).
    on_defect : {"repair", "raise"}
        "repair" drops degenerate and duplicate faces and reports them in ``mesh_report``;
        "raise" raises :class:`~uavcov.errors.MeshError` when there are any.
    source : str
        Recorded in the result.
    """
    if not isinstance(up, str) or up.lower() not in _UP_AXES:
        raise InvalidInputError(f"up must be 'z' or 'y', got {up!r}")
    if not isinstance(on_defect, str) or on_defect not in ("repair", "raise"):
        raise InvalidInputError(f"on_defect must be 'repair' or 'raise', got {on_defect!r}")
    scale = as_positive_float(scale, "scale")
    points = as_float_array(vertices, "vertices", nonfinite_error=MeshError)
    if points.ndim != 2 or points.shape[1] != 3:
        raise MeshError(f"vertices must have shape (V, 3), got {points.shape}")
    if up.lower() == "y":
        points = np.column_stack([points[:, 0], -points[:, 2], points[:, 1]])
    if points.shape[0] == 0:
        raise MeshError("the mesh has no vertices")
    # Before recentring: at 1e300 a 4 m cube's corners are one float, and recentring would make
    # it a flat thing rather than an error.
    _within_coordinate_bound(points, "vertex")
    if origin is None:
        frame_origin = points.min(axis=0)
    else:
        frame_origin = as_float_array(origin, "origin", ndim=1)
        if frame_origin.shape != (3,):
            raise InvalidInputError(f"origin must be an (x, y, z) triple, got shape {frame_origin.shape}")
    frame = LocalFrame(frame_origin, np.full(3, scale))
    # Recentre before anything else so the geometry below works on small numbers.
    local = frame.to_local(points)
    clean_vertices, clean_faces, report = clean_mesh(local, faces)
    if on_defect == "raise" and report.repaired:
        raise MeshError(
            f"{source}: {report.degenerate_faces} degenerate and {report.duplicate_faces} duplicate faces "
            "(pass on_defect='repair' to drop them)"
        )
    terrain = Terrain(clean_vertices, clean_faces)
    return LoadedMesh(terrain=terrain, frame=frame, source=source, mesh_report=report)


def load_mesh(
    path: Any,
    *,
    up: str = "z",
    origin: Any = None,
    scale: float = 1.0,
    on_defect: str = "repair",
) -> LoadedMesh:
    """Read an OBJ, STL or PLY file (anything trimesh reads) as a Terrain; needs ``trimesh``.

    Multi-part files are concatenated into one surface. Vertices are welded exactly,
    degenerate and duplicate faces dropped (or refused with ``on_defect="raise"``), open
    boundaries kept (:class:`MeshReport` counts each).

    The terrain is moved to a local frame: by default the file's minimum corner becomes
    ``(0, 0, 0)``. Positions given in the file's coordinates (your UAVs, a take-off point) go
    through ``loaded.frame.to_local`` before they meet ``loaded.terrain``, and results come back
    with ``loaded.frame.to_source``; ``origin=(0, 0, 0)`` keeps the file's own coordinates.

    Parameters
    ----------
    path : str or PathLike
        The mesh file, metres (or units that ``scale`` turns into metres).
    up : {"z", "y"}, default "z"
        The file's up axis. ``"y"`` (common in OBJ exports) maps the file's ``(x, y, z)`` to
        ``(x, -z, y)``.
    origin : (float, float, float), optional
        The point of the file, in its Z-up axes, that becomes the local origin; by default the
        minimum corner of its bounding box.
    scale : float, default 1.0
        Metres per unit of the file (e.g. 0.001 for millimetres).
    on_defect : {"repair", "raise"}, default "repair"
        ``"repair"`` drops degenerate and duplicate faces and counts them in ``mesh_report``;
        ``"raise"`` raises :class:`~uavcov.errors.MeshError` when there are any.

    Returns
    -------
    LoadedMesh
        ``terrain`` (local frame, metres, Z up), ``frame`` (local <-> file coordinates),
        ``source`` (the path) and ``mesh_report``.

    Raises
    ------
    MissingExtraError
        When trimesh is not installed (``pip install uavcov[mesh]``).
    MeshError
        When the file does not exist, does not parse, or holds no triangles.

    Examples
    --------
    A 10 m x 10 m square 300 m up, 500 km east, written as a PLY file and read back:

    >>> import pathlib, tempfile, numpy as np, trimesh, uavcov
    >>> corners = [[500000.0, 0.0, 300.0], [500010.0, 0.0, 300.0], [500010.0, 10.0, 300.0], [500000.0, 10.0, 300.0]]
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "square.ply"
    >>> _ = trimesh.Trimesh(corners, [[0, 1, 2], [0, 2, 3]], process=False).export(path)
    >>> loaded = uavcov.terrain.load_mesh(path)
    >>> loaded.terrain.bounds.tolist()  # the minimum corner is the local origin
    [[0.0, 0.0, 0.0], [10.0, 10.0, 0.0]]
    >>> uav = loaded.frame.to_local([[500005.0, 5.0, 310.0]])  # a UAV 10 m above the centre
    >>> uav.tolist(), uavcov.Visibility(loaded.terrain, d_max=20.0).coverage(uav)
    ([[5.0, 5.0, 10.0]], 1.0)
    """
    try:
        import trimesh
    except ImportError as exc:
        raise MissingExtraError("reading mesh files needs trimesh: pip install 'uavcov[mesh]' (or pip install trimesh)") from exc
    path_text = existing_path(path, "mesh", MeshError)
    source: Any = path_text
    ply_counts = ply_element_counts(path_text) if path_text.lower().endswith(".ply") else {}
    if path_text.lower().endswith(".stl"):
        check_binary_stl_size(path_text)
    if path_text.lower().endswith(".obj"):
        rewritten = obj_absolute_faces(path_text)
        if rewritten is not None:
            source = io.BytesIO(rewritten)
    try:
        # process=False: we weld and clean ourselves, with a report, rather than silently.
        loaded = trimesh.load(source, file_type="obj" if source is not path_text else None, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds (ValueError, KeyError, IndexError ...)
        raise MeshError(f"cannot parse {path_text!r} as a mesh: {exc}") from exc
    vertices = getattr(loaded, "vertices", None)
    faces = getattr(loaded, "faces", None)
    if vertices is None or faces is None or len(faces) == 0:
        raise MeshError(f"{path_text!r} holds no triangles")
    if ply_counts:
        check_ply_counts(path_text, ply_counts, len(vertices), len(faces))
    try:
        return mesh_terrain(
            np.asarray(vertices, dtype=np.float64),
            np.asarray(faces, dtype=np.int64),
            up=up,
            origin=origin,
            scale=scale,
            on_defect=on_defect,
            source=path_text,
        )
    except MeshError as exc:  # name the file in every mesh error
        if path_text in str(exc):
            raise
        raise MeshError(f"{path_text}: {exc}") from exc


_OBJ_COUNTED = {"v": 0, "vt": 1, "vn": 2}  # the lists an OBJ face's v/vt/vn references count into
_OBJ_NAMES = ("vertex", "texture coordinate", "normal")


def obj_absolute_faces(path: str) -> bytes | None:
    """Check every face of an OBJ file; return its text with relative (negative) references made
    absolute, or None when it has none.

    OBJ counts vertices from 1, and -1 is the last vertex defined *before* the face. trimesh
    misplaces faces that break the first rule (``f 0 2 3``) and counts negative references from
    the end of the file, so both are settled here, where the line is still known.

    Raises
    ------
    MeshError
        A face with fewer than 3 vertices, a reference that is not an integer, 0, or beyond
        what the file defines (the message names the line).
    """
    try:
        with open(path, "rb") as handle:
            lines = handle.read().split(b"\n")
    except OSError as exc:
        raise MeshError(f"cannot read {path!r}: {exc}") from None
    counts = [0, 0, 0]
    highest = [(0, 0), (0, 0), (0, 0)]  # per list: the largest positive reference and its line
    changed = False
    for number, raw in enumerate(lines, start=1):
        words = raw.split()
        if not words:
            continue
        key = words[0].decode("ascii", "replace")
        if key in _OBJ_COUNTED:
            counts[_OBJ_COUNTED[key]] += 1
        elif key == "f":
            if len(words) < 4:
                line = raw.strip()[:60].decode("ascii", "replace")
                raise MeshError(f"{path}: line {number}: a face needs at least 3 vertices, got {line!r}")
            absolute = [_obj_reference(ref, counts, highest, path, number) for ref in words[1:]]
            if absolute != words[1:]:
                changed = True
                lines[number - 1] = b"f " + b" ".join(absolute)
    for k, (index, number) in enumerate(highest):
        if index > counts[k]:
            raise MeshError(f"{path}: line {number}: a face references {_OBJ_NAMES[k]} {index}, but the file defines {counts[k]}")
    return b"\n".join(lines) if changed else None


def _obj_reference(ref: bytes, counts: list[int], highest: list[tuple[int, int]], path: str, number: int) -> bytes:
    """One ``v[/vt[/vn]]`` reference, checked, with relative indices made absolute."""
    text = ref.decode("ascii", "replace")[:40]
    parts = ref.split(b"/")
    if len(parts) > 3 or not parts[0]:
        raise MeshError(f"{path}: line {number}: {text!r} is not a face vertex (v, v/vt, v//vn or v/vt/vn)")
    out: list[bytes] = []
    for k, part in enumerate(parts):
        if not part:
            out.append(part)
            continue
        try:
            index = int(part)
        except ValueError:
            raise MeshError(f"{path}: line {number}: {text!r} is not a face vertex (references are integers)") from None
        if index == 0:
            raise MeshError(f"{path}: line {number}: a face references {_OBJ_NAMES[k]} 0, but OBJ counts from 1")
        if index < 0:
            if counts[k] + index < 0:
                raise MeshError(f"{path}: line {number}: the relative reference {index} reaches before the first {_OBJ_NAMES[k]}")
            index = counts[k] + index + 1
            out.append(str(index).encode())
            continue
        if index > highest[k][0]:
            highest[k] = (index, number)
        out.append(part)
    return b"/".join(out)
