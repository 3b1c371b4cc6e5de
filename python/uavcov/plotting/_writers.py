"""Writers of files that are not matplotlib figures: PLY point clouds, GIF and MP4 animations.

``write_ply`` is public; the animation writers take frames already rendered to RGB arrays
(by :func:`uavcov.plotting.animate_mission`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .._io import make_parent, refuse_what_is_no_file
from .._validate import as_path
from ..errors import InvalidInputError
from ._inputs import _points


def write_ply(points: Any, path: Any, colors: Any = None) -> Path:
    """Write points (and optional 8-bit RGB colours) as an ASCII PLY file.

    Parameters
    ----------
    points : (n, 3) array_like of float
        Metres.
    path : path
        The file to write.
    colors : (n, 3) array_like, optional
        RGB as integers 0-255, or floats in [0, 1].

    Returns
    -------
    Path
    """
    pts = _points(points, "points")
    rgb = None
    if colors is not None:
        rgb = np.asarray(colors)
        if rgb.shape != (pts.shape[0], 3):
            raise InvalidInputError(f"colors must have shape ({pts.shape[0]}, 3), got {rgb.shape}")
        if np.issubdtype(rgb.dtype, np.floating):
            if not np.isfinite(rgb).all() or rgb.min() < 0 or rgb.max() > 1:
                raise InvalidInputError("float colors must lie in [0, 1]")
            rgb = np.rint(rgb * 255)
        elif not np.issubdtype(rgb.dtype, np.integer) or rgb.min(initial=0) < 0 or rgb.max(initial=0) > 255:
            raise InvalidInputError("integer colors must lie in 0..255")
        rgb = rgb.astype(np.int64)
    path = refuse_what_is_no_file(make_parent(as_path(path, "path")))
    header = [
        "ply",
        "format ascii 1.0",
        "comment uavcov: surface points seen by the team, metres",
        f"element vertex {pts.shape[0]}",
        "property double x",
        "property double y",
        "property double z",
    ]
    if rgb is not None:
        header += ["property uchar red", "property uchar green", "property uchar blue"]
    header.append("end_header")
    with path.open("w", encoding="ascii", newline="\n") as handle:
        handle.write("\n".join(header) + "\n")
        if pts.shape[0]:
            if rgb is None:
                np.savetxt(handle, pts, fmt="%.6f")
            else:
                table = np.concatenate([pts, rgb.astype(np.float64)], axis=1)
                np.savetxt(handle, table, fmt=["%.6f"] * 3 + ["%d"] * 3)
    return Path(path)


def _write_gif(images: list[np.ndarray], out: Path, fps: float) -> None:
    """Write ``(H, W, 3)`` uint8 frames as a looping GIF, ``fps`` frames per second, with Pillow."""
    try:
        from PIL import Image
    except ImportError as exc:
        raise ImportError("GIF animations need Pillow, part of the extra: pip install 'uavcov[plot]'") from exc
    # One palette for all frames keeps colours steady and the file small.
    first = Image.fromarray(images[0]).quantize(colors=128, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    frames = [first] + [Image.fromarray(a).quantize(palette=first, dither=Image.Dither.NONE) for a in images[1:]]
    duration = round(1000.0 / fps)
    durations = [duration] * (len(frames) - 1) + [max(duration, 1500)]  # linger on the result
    frames[0].save(out, save_all=True, append_images=frames[1:], duration=durations, loop=0, optimize=True)


def _write_mp4(images: list[np.ndarray], out: Path, fps: float) -> None:
    """Write ``(H, W, 3)`` uint8 frames as H.264 MP4 by piping them to ``ffmpeg``."""
    import subprocess

    h, w = images[0].shape[:2]
    # yuv420p wants even sizes; pad by one pixel where needed.
    command = [
        "ffmpeg",
        "-y",
        "-loglevel",
        "error",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgb24",
        "-s",
        f"{w}x{h}",
        "-r",
        f"{fps:g}",
        "-i",
        "-",
        "-vf",
        "pad=ceil(iw/2)*2:ceil(ih/2)*2",
        "-pix_fmt",
        "yuv420p",
        "-vcodec",
        "libx264",
        str(out),
    ]
    with subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE) as proc:
        assert proc.stdin is not None
        try:
            for a in images:
                proc.stdin.write(np.ascontiguousarray(a).tobytes())
        except BrokenPipeError:
            pass
        proc.stdin.close()
        err = proc.stderr.read().decode(errors="replace") if proc.stderr else ""
        if proc.wait() != 0:
            raise InvalidInputError(f"ffmpeg could not write {out}: {err.strip()}")
