"""A sweep on a surface of the user's own: a sweep file's ``[terrain] kind = "file"``.

The file becomes the experiment's :class:`~uavcov.Terrain`, the true surface of every seed (its
geometry's digest is in the settings hash: another file's content, other run ids). By suffix:
``.npy``, an ``(ny, nx)`` array of heights in metres, rows going north, with ``spacing``;
``.tif``/``.tiff``, a GeoTIFF DEM in its local frame (:func:`uavcov.read_dem`, extra ``geo``);
anything else, a mesh file (:func:`uavcov.terrain.load_mesh`, extra ``mesh``) with ``up`` and
``scale``.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..engine import Terrain
from ..errors import ConfigError, UavcovError
from ..terrain import load_mesh, read_dem

FILE_KEYS = ("path", "spacing", "up", "scale")
"""The keys of a ``[terrain]`` table of kind "file" (besides ``kind``)."""

MAX_GRID_SIDE = 4000
"""Nodes along a side of a ``.npy`` grid a sweep takes (the hills generator's limit too)."""


def terrain_file(table: Mapping[str, Any], source: str) -> Terrain:
    """The surface of a ``[terrain]`` table of kind "file" (``kind`` taken out).

    Parameters
    ----------
    table : mapping
        ``path`` (relative paths from the sweep file's folder; from the working folder when
        ``source`` is not a file), ``spacing`` (metres, ``.npy`` only), ``up`` and ``scale``
        (meshes only, as :func:`uavcov.terrain.load_mesh`).
    source : str
        The sweep file (or a name), for relative paths and messages.

    Raises
    ------
    ConfigError
        An unknown or missing key, a key the file's kind does not take, or a file that cannot be
        read as a surface (the reader's message, with the path).
    """
    unknown = sorted(set(table) - set(FILE_KEYS))
    if unknown:
        raise ConfigError(f'{source}: terrain.{unknown[0]}: unknown key for kind = "file"; valid keys: {", ".join(FILE_KEYS)}')
    raw = table.get("path")
    if not isinstance(raw, str) or not raw:
        raise ConfigError(f'{source}: terrain.path: kind = "file" needs the path of a .npy grid, a GeoTIFF or a mesh, got {raw!r}')
    folder = Path(source).parent if os.path.isfile(source) else Path.cwd()
    path = folder / Path(raw).expanduser()
    suffix = path.suffix.lower()
    allowed = {".npy": {"path", "spacing"}, ".tif": {"path"}, ".tiff": {"path"}}.get(suffix, {"path", "up", "scale"})
    ignored = sorted(set(table) - allowed)
    if ignored:
        raise ConfigError(f"{source}: terrain.{ignored[0]}: not read for a {suffix or 'mesh'} file (it takes {', '.join(sorted(allowed))})")
    try:
        if suffix == ".npy":
            return _grid(path, table.get("spacing"), source)
        if suffix in (".tif", ".tiff"):
            return read_dem(path).terrain
        return load_mesh(path, up=table.get("up", "z"), scale=table.get("scale", 1.0)).terrain
    except (UavcovError, OSError, ValueError) as exc:
        if isinstance(exc, ConfigError):
            raise
        raise ConfigError(f"{source}: terrain.path: {path}: {exc}") from exc


def _grid(path: Path, spacing: Any, source: str) -> Terrain:
    """A ``.npy`` of heights as a grid terrain, its size checked before it is read whole."""
    if spacing is None:
        raise ConfigError(f"{source}: terrain.spacing: a .npy grid needs its cell size in metres (spacing = 1.0, or [dx, dy])")
    if path.exists() and not path.is_file():  # a FIFO would block np.load forever
        raise ConfigError(f"{source}: terrain.path: {path} is not a regular file")
    try:
        heights = np.load(path, mmap_mode="r", allow_pickle=False)
    except ValueError as exc:  # numpy speaks of pickles for anything that is not an array file
        raise ConfigError(f"{source}: terrain.path: {path}: not a .npy array of heights ({exc})") from exc
    if heights.ndim != 2 or max(heights.shape) > MAX_GRID_SIDE:
        raise ConfigError(
            f"{source}: terrain.path: {path}: expected an (ny, nx) grid of at most {MAX_GRID_SIDE} nodes a side, got {heights.shape}"
        )
    if heights.dtype.kind not in "fiu":  # a cast would drop an imaginary part or read flags as 0 and 1 m
        raise ConfigError(f"{source}: terrain.path: {path}: heights must be real numbers, got dtype {heights.dtype}")
    return Terrain.from_grid(np.asarray(heights, dtype=np.float64), spacing=spacing)
