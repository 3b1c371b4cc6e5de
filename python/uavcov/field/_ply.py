"""The seen point cloud of a structure as a PLY file (binary little-endian), and its reader.

One vertex per target: ``x y z`` (float64, metres), ``nx ny nz`` (float32, the unit normal; 0
where the targets have none), ``seen`` (uint8, 1 if some UAV sees it) and ``count`` (int32, how
many UAVs see it). CloudCompare, MeshLab, Open3D and trimesh read it; ``read_seen_ply``
reads back exactly what ``write_seen_ply`` writes (and refuses anything else clearly).
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from .._io import atomic_write
from .._validate import MAX_SAMPLES, as_float_array, as_points
from ..engine import Targets
from ..errors import InvalidInputError, InvalidTypeError, ResultsFolderError

_PROPERTIES = (
    ("x", "<f8", "double"),
    ("y", "<f8", "double"),
    ("z", "<f8", "double"),
    ("nx", "<f4", "float"),
    ("ny", "<f4", "float"),
    ("nz", "<f4", "float"),
    ("seen", "u1", "uchar"),
    ("count", "<i4", "int"),
)
_DTYPE = np.dtype([(name, code) for name, code, _ in _PROPERTIES])
_MAX_HEADER = 4096


def seen_cloud_bytes(targets: Targets, seen_count: Any) -> bytes:
    """The PLY file of ``write_seen_ply``, in memory."""
    if not isinstance(targets, Targets):
        raise InvalidTypeError(f"targets must be a uavcov.Targets, got {type(targets).__name__}")
    count = as_float_array(seen_count, "seen_count", ndim=1)
    if count.shape[0] != len(targets):
        raise InvalidInputError(f"{count.shape[0]} seen counts for {len(targets)} targets")
    if (count < 0).any() or (count != np.round(count)).any() or (count > np.iinfo(np.int32).max).any():
        raise InvalidInputError("seen_count must hold non-negative whole numbers of UAVs")
    rows = np.zeros(len(targets), dtype=_DTYPE)
    for k, axis in enumerate("xyz"):
        rows[axis] = targets.points[:, k]
        if targets.normals is not None:
            rows["n" + axis] = targets.normals[:, k]
    rows["seen"] = count > 0
    rows["count"] = count
    header = [
        "ply",
        "format binary_little_endian 1.0",
        "comment uavcov seen point cloud: metres; seen = 1 if some UAV sees the point, count = how many",
        f"element vertex {len(targets)}",
        *(f"property {kind} {name}" for name, _, kind in _PROPERTIES),
        "end_header",
    ]
    return ("\n".join(header) + "\n").encode("ascii") + rows.tobytes()


def write_seen_ply(path: Any, targets: Targets, seen_count: Any) -> None:
    """Write the targets, their normals and how many UAVs see each, as a binary PLY (atomically).

    Parameters
    ----------
    path : str or PathLike
    targets : Targets
        Points (and normals, written as 0 when absent).
    seen_count : (T,) array_like of int
        UAVs seeing each target (>= 0); ``seen`` is ``count > 0``.

    Raises
    ------
    ResultsFolderError
        The file cannot be written.
    """
    data = seen_cloud_bytes(targets, seen_count)
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidTypeError(f"path must be a path, got {type(path).__name__}")
    try:
        atomic_write(path, data)
    except OSError as exc:
        raise ResultsFolderError(f"cannot write {path}: {exc}") from None


def read_seen_ply(path: Any) -> dict[str, np.ndarray]:
    """A file of ``write_seen_ply`` -> ``{"points", "normals", "seen", "count"}``.

    Raises
    ------
    InvalidInputError
        Unreadable, not such a PLY, or truncated.
    """
    try:
        with open(os.fspath(path), "rb") as handle:
            head = handle.read(_MAX_HEADER)
            end = head.find(b"end_header\n")
            if end < 0:
                raise InvalidInputError(f"{path}: not a PLY of uavcov (no end_header in its first {_MAX_HEADER} bytes)")
            lines = head[:end].decode("ascii", errors="replace").splitlines()
            handle.seek(end + len(b"end_header\n"))
            body = handle.read()
    except OSError as exc:
        raise InvalidInputError(f"cannot read {path}: {exc}") from None
    expected = ["ply", "format binary_little_endian 1.0"]
    properties = [line for line in lines if line.startswith("property ")]
    vertex = [line for line in lines if line.startswith("element vertex ")]
    wanted = [f"property {kind} {name}" for name, _, kind in _PROPERTIES]
    if lines[:2] != expected or properties != wanted or len(vertex) != 1:
        raise InvalidInputError(f"{path}: not a seen point cloud of uavcov (header {lines[:2]}, properties {properties})")
    try:
        n = int(vertex[0].split()[2])
    except ValueError:
        raise InvalidInputError(f"{path}: bad vertex count {vertex[0]!r}") from None
    if not 0 <= n <= MAX_SAMPLES or len(body) != n * _DTYPE.itemsize:
        raise InvalidInputError(f"{path}: {len(body)} bytes of data for {n} vertices of {_DTYPE.itemsize} bytes")
    rows = np.frombuffer(body, dtype=_DTYPE, count=n)
    points = as_points(np.column_stack([rows["x"], rows["y"], rows["z"]]), "PLY points", allow_empty=True)
    return {
        "points": points,
        "normals": np.column_stack([rows["nx"], rows["ny"], rows["nz"]]).astype(np.float64),
        "seen": rows["seen"].astype(bool),
        "count": rows["count"].astype(np.int64),
    }
