"""What every figure shares: the colours, matplotlib loaded on demand, the figure or axes a
function draws into, saving it, and the proxy artists legends are built from.

Nothing here imports matplotlib at module level: :func:`_matplotlib` does, when a figure is
drawn, so ``import uavcov.plotting`` works without the ``uavcov[plot]`` extra.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from .._io import make_parent, refuse_what_is_no_file
from .._validate import as_positive_float, checked_path_text
from ..errors import InvalidInputError, InvalidTypeError, MissingExtraError

MAX_DPI = 1200.0
"""Highest ``dpi`` of a figure: a print's; beyond, the canvas grows past what one figure needs."""
MIN_DPI = 10.0
"""Lowest ``dpi``: below it matplotlib's font engine cannot size the figures' text (dpi 5 and below
raised FreeType's "invalid ppem value"), and a subnormal dpi made matplotlib's size NaN."""

# The paper's colours where it has them: covered surface red, start black, end green.
SEEN_COLOUR = (0.84, 0.15, 0.16)
UNSEEN_COLOUR = (0.72, 0.77, 0.84)
TRUE_SURFACE_COLOUR = (0.86, 0.33, 0.28)
START_COLOUR = "black"
END_COLOUR = (0.10, 0.65, 0.15)
INIT_COLOURS = {"cvt": "#2ca02c", "random": "#1f77b4", "corner": "#d62728", "pairs": "#9467bd", "greedy": "#ff7f0e"}
FOOTPRINT_COLOUR = "#ffbf00"
"""Outlines of camera footprints: amber, visible on the seen red and the unseen grey-blue alike."""


def _matplotlib() -> Any:
    """Import matplotlib, or say which extra provides it."""
    try:
        import matplotlib as mpl
        from matplotlib.figure import Figure  # noqa: F401
    except ImportError as exc:
        raise MissingExtraError("uavcov's figures need matplotlib, the optional extra: pip install 'uavcov[plot]'") from exc
    return mpl


def _new_axes(ax: Any, *, three_d: bool, figsize: tuple[float, float]) -> tuple[Any, Any]:
    """``(figure, axes)``: the caller's axes, checked, or a new figure with one axes."""
    _matplotlib()
    from matplotlib.axes import Axes

    if ax is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=figsize)
        ax = fig.add_subplot(projection="3d" if three_d else None)
        return fig, ax
    if not isinstance(ax, Axes):
        raise InvalidTypeError(f"ax must be a matplotlib Axes, got {type(ax).__name__}")
    if three_d and getattr(ax, "name", "") != "3d":
        raise InvalidInputError("this figure is 3D: pass axes made with projection='3d'")
    if not three_d and getattr(ax, "name", "") == "3d":
        raise InvalidInputError("this figure is 2D: pass ordinary (not 3D) axes")
    return ax.figure, ax


def check_output(out: Any, dpi: Any, *, required: bool = False) -> tuple[Path | None, float]:
    """``out`` as a Path (None unless ``required``) and ``dpi`` as a float in (0, MAX_DPI]."""
    if not isinstance(out, (str, os.PathLike)) and (required or out is not None):
        raise InvalidTypeError(f"out must be {'' if required else 'None, '}a path string or os.PathLike, got {type(out).__name__}")
    dpi = as_positive_float(dpi, "dpi")
    if dpi > MAX_DPI:
        raise InvalidInputError(f"dpi must be at most {MAX_DPI:g}, got {dpi:g}")
    if dpi < MIN_DPI:
        raise InvalidInputError(f"dpi must be at least {MIN_DPI:g} (text matplotlib can draw), got {dpi:g}")
    return (None if out is None else Path(checked_path_text(os.fspath(out), "out"))), dpi  # "" would be the working directory


def _finish(fig: Any, out: Any, dpi: float) -> Any:
    """Save ``fig`` to ``out`` (parents made) when given, and return it: every figure's last step."""
    out, dpi = check_output(out, dpi)
    if out is not None:
        path = refuse_what_is_no_file(make_parent(Path(out)))
        formats = fig.canvas.get_supported_filetypes()
        if path.suffix and path.suffix[1:].lower() not in formats:  # matplotlib's ValueError, in our words
            raise InvalidInputError(f"out {path} names no picture format matplotlib writes ({', '.join(sorted(formats))})")
        fig.savefig(path, dpi=dpi, bbox_inches="tight", pad_inches=0.15)
    return fig


def _close(fig: Any) -> None:
    """Drop the figure's drawing state at once (figures here are not registered with pyplot)."""
    fig.clear()


# ---------------------------------------------------------------------------------------------
# Legend entries: proxies, since the drawn artists (3D collections, rasters) make poor handles


def _patch(colour: Any, label: str) -> Any:
    from matplotlib.patches import Patch

    return Patch(facecolor=colour, edgecolor="0.3", linewidth=0.5, label=label)


def _marker(label: str, **style: Any) -> Any:
    from matplotlib.lines import Line2D

    return Line2D([], [], linestyle="none", label=label, **style)


def _line(label: str, **style: Any) -> Any:
    from matplotlib.lines import Line2D

    return Line2D([], [], label=label, **style)
