"""Figures of a mission, after the paper's: surfaces, CVT, coverage map, curves, Table 1, point cloud.

Every function takes library objects (a :class:`~uavcov.mission.MissionResult`, or a path to a
run saved by :func:`uavcov.records.save_mission`, a :class:`~uavcov.engine.Terrain`, a
:class:`~uavcov.placement.CVTResult`, rows of a ``runs.csv``), draws into a new figure or into the
``ax`` it is given, saves to ``out`` when asked, and returns the matplotlib ``Figure``.
:func:`plot_directory` redraws every figure of a results directory without rerunning anything.

matplotlib is the optional extra ``uavcov[plot]`` and is imported only when a figure is drawn:
importing this package does not need it. Figures are built as ``matplotlib.figure.Figure``
objects, not through ``pyplot``: they need no display and no GUI backend (they render with Agg
when saved), and nothing is kept in pyplot's global figure list, so a long loop of figures does
not leak memory.

Large surfaces are drawn decimated, never target by target: an elevation grid becomes at most
``max_polygons`` quads (each coloured by the share of its grid targets that is seen), a mesh is
clustered down to that many triangles, and top views are rasters.

The package is split by what each part owns:

- :mod:`~uavcov.plotting._figures`: one function per paper figure of one run, and ``seen_points``;
- :mod:`~uavcov.plotting._curves`: the figures of many runs (coverage curves, Table 1) and
  ``published_values``;
- :mod:`~uavcov.plotting._views`: surfaces as polygons (decimation, shading), raster top views,
  hillshade, 3D axes styling;
- :mod:`~uavcov.plotting._animation`: :func:`animate_mission`;
- :mod:`~uavcov.plotting._writers`: ``write_ply`` and the GIF / MP4 writers;
- :mod:`~uavcov.plotting._structures`: :func:`plot_structure_seen`, a structure coloured by seen
  from several sides;
- :mod:`~uavcov.plotting._directory`: :func:`plot_directory`;
- :mod:`~uavcov.plotting._view`: :func:`view`, the interactive 3D view (plotly, the extra
  ``uavcov[view]``), :func:`write_view` (one self-contained HTML file) and :func:`find_run`;
- private helpers: ``_canvas`` (colours, matplotlib on demand, axes, saving, legend entries),
  ``_inputs`` (checks of results and arguments), ``_runs`` (reading ``runs.csv`` and its cells).
"""

from __future__ import annotations

from ._animation import animate_mission
from ._cameras import footprints, plot_camera_views

# The colours and defaults of the figures stay importable from here, as before the split; like
# then they are not in __all__ (the redundant aliases mark them as re-exported).
from ._canvas import END_COLOUR as END_COLOUR
from ._canvas import INIT_COLOURS as INIT_COLOURS
from ._canvas import SEEN_COLOUR as SEEN_COLOUR
from ._canvas import START_COLOUR as START_COLOUR
from ._canvas import TRUE_SURFACE_COLOUR as TRUE_SURFACE_COLOUR
from ._canvas import UNSEEN_COLOUR as UNSEEN_COLOUR
from ._curves import plot_coverage_curves, plot_table1
from ._directory import plot_directory, report_figures
from ._figures import plot_approximation, plot_coverage_map, plot_cvt, plot_point_cloud
from ._structures import plot_structure_seen
from ._view import find_run, view, write_view
from ._views import DEFAULT_MAX_POLYGONS as DEFAULT_MAX_POLYGONS
from ._views import LIGHT as LIGHT

__all__ = [
    "animate_mission",
    "footprints",
    "plot_camera_views",
    "plot_approximation",
    "plot_coverage_curves",
    "plot_coverage_map",
    "plot_cvt",
    "plot_directory",
    "report_figures",
    "plot_point_cloud",
    "plot_table1",
    "plot_structure_seen",
    "view",
    "write_view",
    "find_run",
]
