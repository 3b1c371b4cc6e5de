"""A plan's record of what made it: ``plan.json`` (settings, seed, versions, numbers), ``report.md`` and its map."""

from __future__ import annotations

import io
import math
from typing import Any

import numpy as np

from ..errors import MissingExtraError
from ._plan import FlightPlan
from ._provenance import json_safe, versions, versions_line
from ._qgc import _ALTITUDE_FRAME


def _sensor_record(sensor: Any) -> dict[str, Any]:
    """One UAV's sensor for plan.json: its range, limits and camera (QGroundControl's fields)."""
    return {
        "d_max_m": sensor.d_max,
        "d_min_m": sensor.d_min,
        "camera": None if sensor.camera is None else vars(sensor.camera),
        "max_gsd_m": sensor.max_gsd_m,
        "max_incidence_deg": sensor.max_incidence_deg,
        "good_gsd_m": sensor.good_gsd_m,
    }


def _sensors_line(sensors: list[dict[str, Any]] | None, attitude: list[float]) -> str:
    """The report's words for the team's sensors (nothing for the omnidirectional one)."""
    if not sensors:
        return ""
    kinds = sorted({"omnidirectional" if r["camera"] is None else "camera" for r in sensors})
    cameras = [r["camera"] for r in sensors if r["camera"] is not None]
    words = f", sensors: {' and '.join(kinds)} ({len(cameras)} of {len(sensors)} with a camera)"
    return words + (f", first camera {cameras[0]}, attitude {attitude}" if cameras else "")


def _document(fp: FlightPlan, command: str | None, runtime_s: float | None) -> dict[str, Any]:
    settings = fp.settings
    return {
        "format": "uavcov.plan/1",
        "command": command,
        "runtime_s": runtime_s,
        "dem": {
            "source": fp.dem.source,
            "crs": fp.dem.crs_name,
            "crs_wkt": fp.dem.crs,
            "vertical_datum": fp.dem.vertical_datum,
            "nodata_cells": fp.dem.nodata_cells,
        },
        "area": fp.area.source if fp.area is not None else "the whole DEM",
        "altitudes": {
            "amsl": f"above the DEM's datum: {fp.dem.vertical_datum}",
            "agl": "above the DEM's ground under the UAV",
            "home": "above the take-off point's DEM ground (the .plan files' frame)",
        },
        "settings": {
            "n_uavs": settings.n_uavs,
            "d_max_m": settings.d_max,
            "h_min_m": settings.h_min,
            "h_max_m": settings.h_max,
            "separation_m": settings.d_safe,
            "prior": settings.prior,
            "iterations": settings.iterations,
            "sensors": None if settings.sensor is None else [_sensor_record(s) for s in settings.team_sensors() or []],
            "attitude_deg": list(settings.attitude),
            "cao_alpha0_m": fp.mission.settings.cao.alpha0,
            "hold_s": settings.hold_s,
            "seed": fp.seed,
        },
        "mission_settings": json_safe(fp.mission.settings.as_dict()),
        "versions": versions(),
        "results": {
            "coverage": fp.coverage,
            "initial_coverage": fp.initial_coverage,
            "area_m2": fp.area_m2,
            "targets": len(fp.targets),
            "seen_targets": int(fp.seen.sum()),
            "best_iteration": fp.mission.best_iteration,
            "takeoff": {"longitude": float(fp.takeoff_wgs84[0]), "latitude": float(fp.takeoff_wgs84[1]), "ground_amsl_m": fp.home_amsl},
        },
    }


_UNSEEN_WASH = (0.55, 0.1, 0.65)
"""The plan map's wash over unseen cells: purple, a hue the ``terrain`` colormap has nowhere."""


def _map_png(fp: FlightPlan) -> bytes:
    try:
        import matplotlib as mpl

        mpl.use("Agg", force=False)
        from matplotlib.figure import Figure
    except ImportError as exc:
        raise MissingExtraError("the report's map needs matplotlib: pip install 'uavcov[plot]'") from exc
    dem = fp.dem
    figure = Figure(figsize=(11.0, 5.0), dpi=100, layout="constrained")
    axes, curve = figure.subplots(1, 2, width_ratios=[1.6, 1.0])
    grid, raster = dem.terrain.grid, dem.raster
    if grid is not None and raster is not None:
        a, _, c, _, e, f = raster.transform
        rows, cols = raster.shape
        image = grid.z / dem.frame.factors[2] + dem.frame.origin[2]  # NaN (nodata) stays NaN
        image = image[::-1] if e < 0 else image
        extent = (c, c + cols * a, f + rows * e, f) if e < 0 else (c, c + cols * a, f, f + rows * e)
        shown = axes.imshow(image, extent=extent, cmap="terrain", origin="upper" if e < 0 else "lower", interpolation="nearest")
        seen = np.zeros((rows, cols))
        seen[:] = np.nan
        assert fp.target_pixels is not None
        seen[fp.target_pixels[:, 0], fp.target_pixels[:, 1]] = fp.seen
        # The unseen cells of the area in a colour the terrain colormap never uses (its greys and
        # browns are high ground), named in the legend.
        overlay = np.ma.masked_where(~(seen == 0), seen)
        unseen = mpl.colors.ListedColormap([_UNSEEN_WASH])
        axes.imshow(overlay, extent=extent, cmap=unseen, alpha=0.6, origin="upper" if e < 0 else "lower", interpolation="nearest")
    else:
        points = dem.to_crs(fp.targets.points)
        shown = axes.scatter(points[:, 0], points[:, 1], c=points[:, 2], s=2, cmap="terrain")
    figure.colorbar(shown, ax=axes, label="DEM height (m)", shrink=0.8)

    def crs_xy(local_xy: np.ndarray, z: float = 0.0) -> np.ndarray:
        return dem.to_crs(np.column_stack([local_xy, np.full(local_xy.shape[0], z)]))[:, :2]

    if fp.area is not None:
        for ring in fp.area.local_rings(dem):
            outline = crs_xy(np.vstack([ring, ring[:1]]))
            axes.plot(outline[:, 0], outline[:, 1], color="tab:blue", lw=1.5)
    for outline in fp.footprints_local():
        if outline.shape[0]:
            closed = crs_xy(np.vstack([outline, outline[:1]]))
            axes.plot(closed[:, 0], closed[:, 1], color="tab:red", lw=0.8, alpha=0.7)
    positions = fp.positions_crs
    axes.scatter(positions[:, 0], positions[:, 1], color="tab:red", edgecolor="black", zorder=3, s=30)
    for k, (x, y) in enumerate(positions[:, :2]):
        axes.annotate(str(k + 1), (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
    home = dem.to_crs(fp.takeoff_local.reshape(1, 3))[0]
    axes.scatter([home[0]], [home[1]], marker="^", color="yellow", edgecolor="black", s=80, zorder=4, label="take-off")
    from matplotlib.patches import Patch

    handles, _ = axes.get_legend_handles_labels()
    if grid is not None and raster is not None:
        handles.append(Patch(facecolor=_UNSEEN_WASH, alpha=0.6, edgecolor="0.3", linewidth=0.5, label="not seen"))
    axes.legend(handles=handles, loc="lower right", fontsize=8)
    if dem.geographic:
        mid = float(np.mean(positions[:, 1]))
        axes.set_aspect(1.0 / max(math.cos(math.radians(mid)), 1e-6))
        axes.set_xlabel("longitude (deg)")
        axes.tick_params(axis="x", labelrotation=30)
        axes.set_ylabel("latitude (deg)")
    else:
        axes.set_aspect("equal")
        axes.set_xlabel(f"x ({dem.crs_name})")
        axes.set_ylabel("y")
    axes.set_title(f"{fp.n_uavs} UAVs: {100 * fp.coverage:.1f} % of the area seen", fontsize=10)
    values = fp.mission.coverage
    curve.plot(np.arange(values.shape[0]), values, color="tab:blue")
    curve.set_xlabel("CAO iteration")
    curve.set_ylabel("coverage of the area")
    curve.set_title("CVT start, then CAO on the DEM", fontsize=10)
    curve.grid(alpha=0.3)
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", metadata={"Software": None})
    return buffer.getvalue()


def _report_md(fp: FlightPlan, document: dict[str, Any]) -> bytes:
    s = document["settings"]
    r = document["results"]
    home = r["takeoff"]
    lines = [
        "# uavcov plan",
        "",
        f"Command: `{document['command']}`" if document["command"] else "Made by `uavcov.field.write_plan`.",
        "",
        "![map](report.png)",
        "",
        "## Numbers",
        "",
        "| | |",
        "|---|---|",
        f"| coverage of the area (share of its ground seen by at least one UAV) | {r['coverage']:.3f} |",
        f"| at the CVT start (admissible) | {r['initial_coverage']:.3f} |",
        f"| area | {r['area_m2'] / 1e6:.3f} km^2, {r['targets']} DEM cells ({r['seen_targets']} seen) |",
        f"| best configuration at CAO iteration | {r['best_iteration']} of {s['iterations']} |",
        f"| take-off (home) | {home['longitude']:.7f}, {home['latitude']:.7f}, ground {home['ground_amsl_m']:.1f} m |",
    ]
    if document["runtime_s"] is not None:
        lines.append(f"| runtime (reading the DEM and planning; files not included) | {document['runtime_s']:.1f} s |")
    lines += [
        "",
        "| UAV | longitude | latitude | AMSL (m) | above ground (m) | above home (m) | transit AMSL (m) |",
        "|---|---|---|---|---|---|---|",
    ]
    for k in range(fp.n_uavs):
        lon, lat = fp.positions_wgs84[k]
        lines.append(
            f"| {k + 1} | {lon:.7f} | {lat:.7f} | {fp.altitude_amsl[k]:.1f} | {fp.altitude_agl[k]:.1f} | "
            f"{fp.altitude_home[k]:.1f} | {fp.transit_amsl[k]:.1f} |"
        )
    lines += [
        "",
        "## Frames",
        "",
        f"- DEM: `{document['dem']['source']}`, CRS {document['dem']['crs']}, {document['dem']['nodata_cells']} nodata cells.",
        f"- Heights: {fp.dem.vertical_datum}.",
        "- Longitude, latitude: WGS 84 (EPSG:4326) in every file (GeoJSON, KML, .plan, CSV).",
        "- AMSL: above the DEM's datum; above ground: above the DEM under the UAV; above home: above the take-off point's DEM ground.",
        f"- `.plan` altitudes: {_ALTITUDE_FRAME}.",
        (
            "- Transit: each UAV climbs at home, flies straight at h_min above the highest ground of its path, descends and "
            "holds. Transit paths are not deconflicted between UAVs: stagger the take-offs."
        ),
        (
            "- Footprints: what each sensor reaches on the horizontal plane through the ground under it (reach, not sight); "
            "`coverage.tif` holds what is seen."
        ),
        "",
        "## Settings",
        "",
        f"- area: {document['area']}",
        f"- team: {s['n_uavs']} UAVs, range d_max = {s['d_max_m']:g} m" + _sensors_line(s["sensors"], s["attitude_deg"]),
        (
            f"- flight limits: {s['h_min_m']:g} to {s['h_max_m']:g} m above ground, {s['separation_m']:g} m apart, "
            "inside the area's bounding box"
        ),
        f"- known beforehand: {'the full DEM' if s['prior'] == 'full' else str(s['prior']) + ' sparse points (+ the area hull)'}",
        (
            f"- method: CVT start on S' (paper Table 1 CVT), then {s['iterations']} CAO iterations on the DEM "
            f"(paper Table 1 constants, alpha0 = {s['cao_alpha0_m']:.4g} m), seed {s['seed']}"
        ),
        f"- versions: {versions_line(document['versions'])}; every setting of the mission in `plan.json` (`mission_settings`)",
        "",
    ]
    return "\n".join(lines).encode("utf-8")
