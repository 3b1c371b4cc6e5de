"""What a mesh file's header announces (a PLY's element counts, a binary STL's triangle count),
checked against the file and against what was read.

A PLY header states how many vertices and faces follow (``element vertex 3``). trimesh reads an
ASCII file that stops short of them without a word (the faces it found), and a header may
announce more elements than its file could ever hold; a binary STL states its triangle count,
and its size must be 84 + 50 bytes a triangle. All are corrupt files, refused here with the
counts, before and after trimesh reads the file.
"""

from __future__ import annotations

import os
import struct

from ..errors import MeshError

_MAX_HEADER_BYTES = 65_536  # a header names a few elements and properties: far below this


def ply_element_counts(path: str) -> dict[str, int]:
    """The element counts of the header of the PLY file at ``path`` (``{"vertex": 3, "face": 1}``).

    An empty dict when the file has no readable PLY header (trimesh then says what is wrong).

    Raises
    ------
    MeshError
        The header announces more elements than the file has bytes (each takes one at least).
    """
    try:
        with open(path, "rb") as handle:
            head = handle.read(_MAX_HEADER_BYTES)
    except OSError:
        return {}
    end = head.find(b"end_header")
    if not head.startswith(b"ply") or end < 0:
        return {}
    counts: dict[str, int] = {}
    for line in head[:end].splitlines():
        words = line.split()
        if len(words) == 3 and words[0] == b"element" and words[2].isdigit():
            counts[words[1].decode("ascii", "replace")] = int(words[2])
    size = os.path.getsize(path) - end
    for name, count in counts.items():
        if count > size:
            raise MeshError(f"{path}: the PLY header announces {count:,} {name} elements, more than the file's {size:,} bytes can hold")
    return counts


def check_ply_counts(path: str, counts: dict[str, int], n_vertices: int, n_faces: int) -> None:
    """Refuse a PLY file whose data stops short of what its header announced.

    trimesh keeps every vertex (``process=False``) and splits a polygon into triangles, so a
    whole file gives exactly the announced vertices and at least the announced faces.
    """
    announced_vertices = counts.get("vertex")
    announced_faces = counts.get("face")
    if announced_vertices is not None and n_vertices != announced_vertices:
        raise MeshError(
            f"{path}: the PLY header announces {announced_vertices:,} vertices, the file holds {n_vertices:,} (a truncated file?)"
        )
    if announced_faces is not None and n_faces < announced_faces:
        raise MeshError(
            f"{path}: the PLY header announces {announced_faces:,} faces, {n_faces:,} triangles were read "
            "(a truncated file, or faces of fewer than 3 vertices)"
        )


def check_binary_stl_size(path: str) -> None:
    """Refuse a binary STL whose size is not what its triangle count says (84 + 50 bytes each).

    A file that starts with ``solid`` may be ASCII (or a binary one whose header says so, whose
    size then matches): trimesh decides; any other is binary, and a count that disagrees with the
    size is a truncated or padded file (trimesh said only "no triangles").

    Raises
    ------
    MeshError
        The size disagrees with the count.
    """
    try:
        with open(path, "rb") as handle:
            head = handle.read(84)
    except OSError:
        return
    if len(head) < 84 or head[:5].lower() == b"solid":
        return
    (count,) = struct.unpack("<I", head[80:84])
    size, expected = os.path.getsize(path), 84 + 50 * count
    if size != expected:
        raise MeshError(
            f"{path}: the binary STL announces {count:,} triangles ({expected:,} bytes), the file has {size:,} bytes (truncated or padded)"
        )
