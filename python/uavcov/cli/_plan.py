"""``uavcov plan``: a flight plan on a DEM, or round a structure."""

from __future__ import annotations

import argparse
import shlex
import time
from pathlib import Path

from ._common import (
    EXIT_OK,
)

_MESH_SUFFIXES = (".obj", ".stl", ".ply")


def _plan(args: argparse.Namespace) -> int:
    from ..engine import Camera, Gimbal, Sensor
    from ..errors import ConfigError
    from ..field import PlanSettings, bbox_area, check_plan_folder, plan, read_area, write_plan
    from ..terrain import read_dem, read_mesh_dem, sample_dem

    started = time.perf_counter()
    if args.structure is not None:
        return _plan_structure(args, started)
    if args.anchor is not None:
        raise ConfigError("--anchor places a structure (--structure); a DEM states its own georeference")
    if args.scale != 1.0 or args.open_mesh:
        raise ConfigError("--scale and --open-mesh read a structure's mesh file (--structure MESH), not a DEM")
    if (args.dem is None) == (not args.sample):
        raise ConfigError("give either a DEM file or the bundled sample (--sample), not both and not neither")
    check_plan_folder(args.out)  # before the work: a folder of other files is refused, never wiped
    if args.sample:
        if args.crs is not None:
            raise ConfigError("the sample's CRS is known (WGS 84): --crs is for DEM files")
        dem = sample_dem(args.window or (150, 190, 150, 190), args.stride)
    elif Path(args.dem).suffix.lower() in _MESH_SUFFIXES:
        if args.crs is None:
            raise ConfigError(f"a mesh file states no CRS: give it with --crs (e.g. EPSG:32633) for {args.dem}")
        dem = read_mesh_dem(args.dem, args.crs)
    elif Path(args.dem).suffix.lower() in (".npy", ".npz"):
        raise ConfigError(
            f"{args.dem} is a numpy array, which places no pixel on the Earth: save it as a GeoTIFF with its "
            "geotransform and CRS, or plan it in Python with uavcov.terrain.dem_from_array(z, transform, crs) and "
            'uavcov.plan (docs/plan.md); `uavcov sweep` runs missions on it as [terrain] kind = "file"'
        )
    else:
        dem = read_dem(args.dem, crs=args.crs)
    if args.window is not None and not args.sample:
        raise ConfigError("--window crops the bundled sample (--sample) only")
    area = None
    if args.aoi is not None:
        area = read_area(args.aoi)
    elif args.bbox is not None:
        area = bbox_area(*args.bbox, frame=args.coords)
    sensor = None
    if args.camera is not None:
        sensor = Sensor(args.d_max, camera=Camera.from_fov(*args.camera))
    elif args.free_heading or args.pitch_range is not None or args.footprint_start:
        raise ConfigError("--free-heading, --pitch-range and --footprint-start need a camera (--camera HFOV,VFOV)")
    gimbal = Gimbal(free_yaw=args.free_heading, pitch_range=args.pitch_range) if args.free_heading or args.pitch_range else None
    settings = PlanSettings(
        n_uavs=args.uavs,
        d_max=args.d_max,
        h_min=10.0 if args.h_min is None else args.h_min,
        h_max=60.0 if args.h_max is None else args.h_max,
        d_safe=args.separation,
        takeoff=args.takeoff,
        takeoff_frame=args.coords,
        prior=args.prior,
        iterations=args.iterations,
        sensor=sensor,
        attitude=args.attitude,
        gimbal=gimbal,
        footprint_start=args.footprint_start,
        hold_s=args.hold,
    )
    flight_plan = plan(dem, settings, area=area, rng=args.seed, n_threads=args.threads)
    command = "uavcov " + shlex.join(args.argv)
    written = write_plan(flight_plan, args.out, command=command, runtime_s=time.perf_counter() - started)
    print(
        f"uavcov plan: {settings.n_uavs} UAVs over {dem.crs_name}: coverage {flight_plan.coverage:.3f} of the area "
        f"(start {flight_plan.initial_coverage:.3f}), {flight_plan.area_m2 / 1e6:.3f} km^2"
    )
    for k in range(flight_plan.n_uavs):
        lon, lat = flight_plan.positions_wgs84[k]
        print(
            f"  UAV {k + 1}: {lon:.7f}, {lat:.7f}  {flight_plan.altitude_amsl[k]:.1f} m AMSL, "
            f"{flight_plan.altitude_agl[k]:.1f} m above ground, {flight_plan.altitude_home[k]:.1f} m above home"
        )
    print(f"  wrote {len(written)} files to {args.out}/ in {time.perf_counter() - started:.1f} s: " + ", ".join(p.name for p in written))
    return EXIT_OK


def _plan_structure(args: argparse.Namespace, started: float) -> int:
    """``uavcov plan --structure NAME|MESH --anchor LON,LAT,ALT``: a team round a structure."""
    from ..errors import ConfigError
    from ..field import GeoAnchor, check_plan_folder, plan_structure, write_structure_plan
    from ..limits import Constraints
    from ..placement import StartSettings
    from ..settings import MissionSettings
    from ..structures import STRUCTURE_SCENES, load_structure

    if args.dem is not None or args.sample:
        raise ConfigError("--structure plans round a structure: give no DEM and no --sample")
    if args.anchor is None:
        raise ConfigError("a structure's plan needs its WGS84 anchor: --anchor LON,LAT,ALT (the local origin)")
    for flag, value in (
        ("--aoi", args.aoi),
        ("--bbox", args.bbox),
        ("--crs", args.crs),
        ("--camera", args.camera),
        ("--takeoff", args.takeoff),
    ):
        if value is not None:
            raise ConfigError(f"{flag} is for a DEM's plan, not a structure's")
    check_plan_folder(args.out)
    if args.structure in STRUCTURE_SCENES:
        if args.scale != 1.0 or args.open_mesh:
            raise ConfigError("--scale and --open-mesh are for a mesh file, not a scene")
        structure = STRUCTURE_SCENES[args.structure](rng=args.seed)
    elif Path(args.structure).suffix.lower() in _MESH_SUFFIXES:
        structure = load_structure(args.structure, scale=args.scale, closed=not args.open_mesh)
    else:
        raise ConfigError(f"--structure must be one of {sorted(STRUCTURE_SCENES)} or a mesh file (.obj/.stl/.ply), got {args.structure!r}")
    top = float(structure.surface.bounds[1, 2])
    h_min = 2.0 if args.h_min is None else args.h_min
    settings = MissionSettings(
        n_uavs=args.uavs,
        d_max=args.d_max,
        n_prior=100,
        iterations=args.iterations,
        start=StartSettings(kind="cvt", altitude=max(4.0, h_min + 1.0), altitude_reference="normal", climb=0.5),
        constraints=Constraints(
            clearance="standoff", h_min=h_min, h_max=args.h_max, d_safe=args.separation, z_max=top + 10.0, check_moves=True
        ),
    )
    lon, lat, alt = args.anchor
    planned = plan_structure(structure, settings, GeoAnchor(lon, lat, alt), hold_s=args.hold, rng=args.seed, n_threads=args.threads)
    command = "uavcov " + shlex.join(args.argv)
    written = write_structure_plan(planned, args.out, command=command, runtime_s=time.perf_counter() - started)
    try:
        from ..plotting import plot_structure_seen

        figure = Path(args.out) / "seen.png"
        best = planned.result.best_positions
        plot_structure_seen(structure.surface, planned.seen_count > 0, targets=planned.targets, positions=best, out=figure)
        written.append(figure)
    except ImportError:  # matplotlib is the [plot] extra: the plan stands without the figure
        pass
    result = planned.result
    print(
        f"uavcov plan: {settings.n_uavs} UAVs round {structure.name}: "
        f"coverage {result.best_coverage:.3f} (start {result.initial_coverage:.3f})"
    )
    for part, share in (result.coverage_by_part or {}).items():
        print(f"  {part}: {share:.3f}")
    for k in range(planned.flight.n_uavs):
        lon_k, lat_k, h_k = planned.flight.positions_wgs84[k]
        print(f"  UAV {k + 1}: {lon_k:.7f}, {lat_k:.7f}  {h_k:.1f} m (WGS84 ellipsoid)")
    print(f"  wrote {len(written)} files to {args.out}/ in {time.perf_counter() - started:.1f} s: " + ", ".join(p.name for p in written))
    return EXIT_OK
