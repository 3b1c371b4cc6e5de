"""A :class:`~uavcov.field.FlightPlan` written for flight controllers and GIS, and read back.

:func:`write_plan` writes one folder:

=======================  =====================================================================
file                     what, in which frame
=======================  =====================================================================
``positions.csv``        one row per UAV: local metres; (x, y) in the DEM's CRS; longitude,
                         latitude (WGS84); altitude above the DEM's datum (AMSL), above the
                         ground under the UAV (AGL) and above the take-off point (home)
``waypoints.csv``        every item of every ``.plan``: longitude, latitude (WGS84), altitude
                         above home and AMSL
``uav_NN.plan``          QGroundControl plan per UAV: take-off at home, transit at a safe
                         altitude, descent to the position, hold (loiter for ``hold_s``);
                         altitudes relative to home (``MAV_FRAME_GLOBAL_RELATIVE_ALT``, frame 3)
``plan.geojson``         positions (Points, altitude AMSL), footprints, the area, the take-off
                         point; RFC 7946: WGS84 longitude, latitude
``plan.kml``             the same for Google Earth / QGIS; altitudes ``absolute`` (AMSL)
``coverage.tif``         GeoTIFF in the DEM's grid and CRS: band 1 seen (1) or not (0), band 2
                         how many UAVs see the cell; 65535 outside the area and over nodata
``plan.json``            the command, seed, settings, versions, CRSs and datums, the numbers
``report.md``            one page: the map, the numbers, the settings
``report.png``           the map: elevation, seen cells, area, footprints, positions, take-off
=======================  =====================================================================

Why relative-to-home altitudes in the ``.plan``: a flight controller measures altitude from its
take-off point (barometer), and the difference between two DEM heights does not depend on the
DEM's vertical datum, which is often unknown; the home altitude written as
``plannedHomePosition`` is the DEM's height at the take-off point.

Every file is rendered in memory first, then the folder is swapped in whole
(``field/_results_folder.py``): bad input or a failing renderer leaves the folder as it
was, a new plan leaves nothing of an older one, and a folder of other files is refused. Every
JSON file is strict (no NaN or Infinity), every CSV cell a finite number or empty, every longitude
in [-180, 180]. Each writer has a reader (``read_*``) that the round-trip tests use; the writers
live in one file per kind (``_qgc``, ``_plan_tables``, ``_gis_files``, ``_plan_report``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ._gis_files import _coverage_geotiff, _geojson, _kml, _quality_geotiff
from ._plan import FlightPlan
from ._plan_report import _document, _map_png, _report_md
from ._plan_tables import _positions_csv, _waypoints_csv
from ._provenance import check_provenance
from ._qgc import _check, qgc_plan
from ._results_folder import write_files
from ._strict_json import json_bytes


def render_plan(flight_plan: FlightPlan, *, command: str | None = None, runtime_s: float | None = None) -> dict[str, bytes]:
    """Every file of :func:`write_plan` as ``{name: bytes}``, nothing written."""
    fp = _check(flight_plan)
    command, runtime_s = check_provenance(command, runtime_s)
    files: dict[str, bytes] = {}
    files["positions.csv"] = _positions_csv(fp)
    files["waypoints.csv"] = _waypoints_csv(fp)
    for k in range(fp.n_uavs):
        files[f"uav_{k + 1:02d}.plan"] = json_bytes(qgc_plan(fp, k), indent=4, what=f"uav_{k + 1:02d}.plan")
    files["plan.geojson"] = _geojson(fp)
    files["plan.kml"] = _kml(fp)
    coverage = _coverage_geotiff(fp)
    if coverage is not None:
        files["coverage.tif"] = coverage
    quality = _quality_geotiff(fp)
    if quality is not None:
        files["quality.tif"] = quality
    document = _document(fp, command, runtime_s)
    files["plan.json"] = json_bytes(document, indent=2, what="plan.json")
    files["report.png"] = _map_png(fp)
    files["report.md"] = _report_md(fp, document)
    return files


def write_plan(flight_plan: FlightPlan, out: Any, *, command: str | None = None, runtime_s: float | None = None) -> list[Path]:
    """Write every file of a plan into the folder ``out`` (created if needed); see the module.

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    ResultsInUseError
        ``out`` holds files that are not a plan's: a plan replaces its folder as a whole (the
        files of an earlier plan there go), and never deletes what it did not write.
    ResultsFolderError
        ``out`` is a file, or cannot be created or written.
    """
    return write_files(render_plan(flight_plan, command=command, runtime_s=runtime_s), out)
