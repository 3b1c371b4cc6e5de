"""The ``uavcov`` command line (also ``python -m uavcov``): parses arguments, calls the library.

Commands
--------
``uavcov demo``
    The paper's illustrative example end to end (9 UAVs, d_max = 35 m, 30 prior samples, CVT
    start, then CAO): prints a summary, writes runs.csv, the run and its figures to ``--out``.
``uavcov reproduce table1|pyramid|example|comparison|buildings|ablation|structures|realistic|all``
    One of the paper's experiments; writes runs.csv, the runs, config.json and ``<name>.md``.
``uavcov sweep CONFIG.toml``
    Any grid of settings (see ``examples/sweep.toml``); writes summary.md beside the runs.
``uavcov plot DIR``
    Redraws every figure from the runs stored in DIR (needs ``uavcov[plot]``).
``uavcov view RUN_OR_DIR --out view.html``
    One self-contained HTML file (opens offline) with an interactive 3D view of a run: the
    surface coloured by what the team sees, the UAVs, paths and footprints, a slider over
    iterations (needs ``uavcov[view]``).
``uavcov plan DEM.tif|--sample``
    A flight plan on a real DEM (needs ``uavcov[geo]``): the paper's CVT start and CAO, then
    QGroundControl ``.plan`` files, CSV, GeoJSON, KML, a coverage GeoTIFF and a report in ``--out``.

Exit codes: 0 done; 1 done, but some runs failed (their errors are in runs.csv); 2 bad input
(nothing already in ``--out`` was changed); 130 interrupted (every finished run is in runs.csv;
rerun with ``--resume``).
"""

from __future__ import annotations

import argparse
import contextlib
import shlex
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any, NoReturn

__all__ = ["main"]

EXIT_OK = 0
EXIT_RUNS_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130


def _one_line(exc: BaseException) -> str:
    """An exception's message on one line (the CLI prints exactly one line per error)."""
    return " | ".join(part.strip() for part in str(exc).splitlines() if part.strip()) or type(exc).__name__


def _say(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _int_list(text: str) -> tuple[int, ...]:
    try:
        values = tuple(int(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected integers separated by commas, got {text!r}") from None
    if not values:
        raise argparse.ArgumentTypeError("expected at least one integer")
    return values


def _str_list(text: str) -> tuple[str, ...]:
    values = tuple(v.strip() for v in text.split(",") if v.strip())
    if not values:
        raise argparse.ArgumentTypeError("expected at least one name")
    return values


def _int_at_least(minimum: int) -> Callable[[str], int]:
    """An argparse type: an integer >= ``minimum``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {value}")
        return value

    return parse


_positive_int = _int_at_least(1)
_non_negative_int = _int_at_least(0)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text}")
    return value


# ---------------------------------------------------------------------------------------------
# Execution options shared by reproduce and sweep


def _add_execution(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("execution")
    group.add_argument("--workers", type=_positive_int, help="runs at once on a local process pool (default: every core)")
    group.add_argument("--threads", type=_positive_int, help="Rust threads per run (default: cores // workers)")
    where = group.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS", help="run on the Dask cluster of this scheduler (uavcov[distributed])")
    where.add_argument("--dask-workers", type=_positive_int, metavar="N", help="run on a local Dask cluster of N worker processes")
    group.add_argument(
        "--scheduler-timeout",
        type=_positive_float,
        default=10.0,
        metavar="SECONDS",
        help="give up on an unreachable scheduler after this long (default 10)",
    )
    group.add_argument("--resume", action="store_true", help="continue the sweep in --out: skip finished runs")
    group.add_argument("--retry-failed", action="store_true", help="with --resume: run again the runs that failed")
    group.add_argument("--no-save-runs", action="store_true", help="write only runs.csv, not one .npz per run")
    bar = group.add_mutually_exclusive_group()
    bar.add_argument("--progress", dest="progress", action="store_true", default=None, help="always show the progress bar")
    bar.add_argument("--no-progress", dest="progress", action="store_false", help="never show the progress bar")


@contextlib.contextmanager
def _execution(args: argparse.Namespace) -> Iterator[dict[str, Any]]:
    """Keyword arguments for run_specs (executor, workers, threads, ...) and what to record."""
    from .experiments import available_cores, dask_executor, plan_execution

    options: dict[str, Any] = {
        "resume": bool(args.resume or args.retry_failed),
        "rerun": "failed" if args.retry_failed else "none",
        "save_runs": not args.no_save_runs,
        "progress": args.progress,
    }
    cores = available_cores()
    if args.scheduler is None and args.dask_workers is None:
        plan = plan_execution(args.workers, args.threads)
        options.update(workers=plan.workers, n_threads=plan.n_threads)
        record = {
            "executor": "process pool (spawn)" if plan.workers > 1 else "this process",
            "workers": plan.workers,
            "threads_per_run": plan.n_threads,
            "cores": cores,
        }
        yield {**options, "execution": record}
        return
    if args.workers is not None:
        from .errors import ConfigError

        raise ConfigError("--workers is for the local process pool; with Dask the cluster decides (use --dask-workers)")
    if args.dask_workers is not None:
        plan = plan_execution(args.dask_workers, args.threads)
        threads = plan.n_threads
    else:
        threads = args.threads or 1  # a remote worker's cores are unknown here: one thread per run
    with dask_executor(args.scheduler, args.dask_workers, timeout=args.scheduler_timeout) as (executor, slots):
        record = {
            "executor": f"dask ({args.scheduler or 'local cluster'})",
            "workers": slots,
            "threads_per_run": threads,
            "cores": cores,
        }
        yield {**options, "executor": executor, "workers": slots, "n_threads": threads, "execution": record}


def _finish(rows: list[dict[str, Any]], out: Path, started: float, wrote: Sequence[str]) -> int:
    failed = [r for r in rows if r.get("error")]
    seconds = time.perf_counter() - started
    _say(f"{len(rows)} run(s) in {seconds:.1f} s; results in {out}/: " + ", ".join(wrote))
    if failed:
        _say(f"{len(failed)} run(s) failed; their errors are in the error column of {out / 'runs.csv'}, e.g.")
        _say(f"  {failed[0]['run_id']}: {failed[0]['error']}")
        return EXIT_RUNS_FAILED
    return EXIT_OK


# ---------------------------------------------------------------------------------------------
# Commands


def _reproduce(args: argparse.Namespace) -> int:
    from .paper import reproduce

    if args.experiment == "all":
        return _reproduce_all(args)
    if args.experiment == "ablation":
        return _reproduce_ablation(args)
    if args.experiment == "structures":
        return _reproduce_structures(args)
    if args.experiment == "realistic":
        return _reproduce_realistic(args)
    out = Path(args.out or f"out/{args.experiment}")
    started = time.perf_counter()
    with _execution(args) as options:
        execution = options.pop("execution")
        rows = reproduce(
            args.experiment,
            out,
            seeds=args.seeds,
            team_sizes=args.team_sizes,
            starts=args.starts,
            iterations=args.iterations,
            execution=execution,
            **options,
        )
    table = out / f"{args.experiment}.md"
    if table.exists():
        print(table.read_text(encoding="utf-8"))
    wrote = ["runs.csv", "config.json", table.name] + ([] if args.no_save_runs else ["runs/"])
    code = _finish(rows, out, started, wrote)
    if not args.no_plots and not args.no_save_runs and any(not r.get("error") for r in rows):
        figures = _plot_directory(out)
        if figures:
            _say(f"{len(figures)} figure(s) in {Path(figures[0]).parent}/ (`uavcov plot {out}` adds an animation)")
    return code


def _reproduce_realistic(args: argparse.Namespace) -> int:
    """The paper's realistic scenario flown (uavcov.sim, the ``sim`` extra): serial, one core."""
    from .paper import reproduce_realistic

    out = Path(args.out or "out/realistic")
    rows = reproduce_realistic(
        out,
        seeds=args.seeds,
        starts=args.starts or ("cvt", "pairs"),
        iterations=200 if args.iterations is None else args.iterations,
    )
    print((out / "realistic.md").read_text(encoding="utf-8"))
    failed = sum(bool(r["failure"]) for r in rows)
    _say(f"{len(rows)} flown run(s), {failed} failed, in {out}/")
    return 0


def _refuse_choice_within(args: argparse.Namespace, what: str) -> None:
    """``--team-sizes`` and ``--starts`` pick cells of one experiment; ``what`` runs several."""
    from .errors import ConfigError

    if args.team_sizes is not None or args.starts is not None:
        raise ConfigError(f"--team-sizes and --starts choose within one experiment, not with {what}")


def _reproduce_ablation(args: argparse.Namespace) -> int:
    from .paper import ablate

    _refuse_choice_within(args, "ablation")
    out = Path(args.out or "out/ablation")
    started = time.perf_counter()
    with _execution(args) as options:
        execution = options.pop("execution")
        rows = ablate(out, seeds=args.seeds, iterations=args.iterations, execution=execution, **options)
    print((out / "ablation.md").read_text(encoding="utf-8"))
    return _finish(rows, out, started, ["runs.csv", "config.json", "ablation.md"] + ([] if args.no_save_runs else ["runs/"]))


def _reproduce_structures(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from .errors import ConfigError
    from .experiments import available_cores, parse_seeds
    from .paper import StructuresExperiment, reproduce_structures

    report = "structures.md"  # what reproduce_structures writes beside rows.jsonl and config.json

    _refuse_choice_within(args, "structures")
    if args.scheduler is not None or args.dask_workers is not None:
        raise ConfigError("the structures experiment runs on the local process pool (--workers), not on Dask")
    experiment = StructuresExperiment()
    if args.seeds is not None:
        experiment = replace(experiment, report_seeds=parse_seeds(args.seeds))
    if args.iterations is not None:
        experiment = replace(experiment, iterations=args.iterations)
    out = Path(args.out or "out/structures")
    started = time.perf_counter()
    workers = args.workers or available_cores()
    rows = reproduce_structures(out, experiment, workers=workers, resume=bool(args.resume), progress=_say)
    print((out / report).read_text(encoding="utf-8"))
    _say(f"{len(rows)} run(s) in {time.perf_counter() - started:.1f} s; results in {out}/: rows.jsonl, config.json, {report}, figures/")
    return EXIT_RUNS_FAILED if any(r["error"] for r in rows) else EXIT_OK


def _reproduce_all(args: argparse.Namespace) -> int:
    from .paper import reproduce_all

    _refuse_choice_within(args, "all")
    out = Path(args.out or "out/all")
    started = time.perf_counter()
    with _execution(args) as options:
        execution = options.pop("execution")
        results = reproduce_all(
            out,
            seeds=args.seeds,
            iterations=args.iterations,
            figures=None if args.no_plots else _report_figures,
            execution=execution,
            **options,
        )
    rows = [row for name in results for row in results[name]]
    return _finish(rows, out, started, [*(f"{name}/" for name in results), "report.md"])


def _sweep(args: argparse.Namespace) -> int:
    from .experiments import load_sweep_config, run_sweep
    from .paper import EXPERIMENTS

    config = load_sweep_config(args.config, bases=EXPERIMENTS)
    out = Path(args.out or f"out/{Path(args.config).stem}")
    started = time.perf_counter()
    with _execution(args) as options:
        execution = options.pop("execution")
        rows = run_sweep(config, out, source_text=Path(args.config).read_text(encoding="utf-8"), execution=execution, **options)
    print((out / "summary.md").read_text(encoding="utf-8"))
    return _finish(rows, out, started, ["runs.csv", "config.json", "sweep.toml", "summary.md"] + ([] if args.no_save_runs else ["runs/"]))


def _report_figures(folder: Path) -> list[str]:
    from .plotting import report_figures

    return report_figures(folder)


def _plot_directory(out: Path) -> list[Path] | None:
    """Draw the figures of ``out`` (not the animation, which takes longer) when plotting is available."""
    try:
        from .plotting import plot_directory

        return list(plot_directory(out, animation=False) or [])
    except ImportError as exc:  # plotting.py missing, or matplotlib when it draws
        _say(f"(no figures: plotting needs matplotlib, pip install 'uavcov[plot]': {exc})")
        return None


def _demo(args: argparse.Namespace) -> int:
    from .experiments import available_cores
    from .paper import EXAMPLE, reproduce
    from .terrain import HillsGenerator

    out = Path(args.out)
    threads = args.threads or available_cores()
    experiment = EXAMPLE
    terrain = experiment.terrain
    hills = f"{terrain.n_hills} Gaussian hills" if isinstance(terrain, HillsGenerator) else "buildings"
    print("uavcov demo: the paper's illustrative example (Fig. 5)")
    print(f"  terrain  {terrain.size:g} m x {terrain.size:g} m, {hills} (seed {args.seed}), coverage on a {terrain.spacing:g} m grid")
    print(f"  prior    {experiment.mission.n_prior} random samples + the 4 corners -> approximating surface S'")
    print(
        f"  team     {experiment.team_sizes[0]} UAVs, d_max = {experiment.d_max:g} m, CVT start on S', "
        f"then {args.iterations} CAO iterations on the real terrain ({threads} thread(s))",
        flush=True,
    )
    started = time.perf_counter()
    # The demo's folder holds its own run only: a rerun with the same settings replaces it.
    rows = reproduce(
        "example",
        out,
        seeds=[args.seed],
        iterations=args.iterations,
        workers=1,
        n_threads=threads,
        resume=True,
        rerun="all",
        exclusive=True,
        progress=False,
        command="demo",
        execution={"executor": "this process", "threads_per_run": threads},
    )
    out_path = out
    row = rows[0]
    if row["error"]:
        _say(f"the demo run failed: {row['error']}")
        return EXIT_RUNS_FAILED
    print()
    print("  | coverage of the real terrain | share |")
    print("  |---|---|")
    print(f"  | at the start (CVT on S', lifted to flying height) | {row['initial_coverage']:.3f} |")
    print(f"  | best reached by CAO (the paper: close to 1) | {row['max_coverage']:.3f} |")
    print(f"  | after the last iteration | {row['final_coverage']:.3f} |")
    print(f"\n  95 % of the best reached at iteration {row['iterations_to_95']}; best at iteration {row['best_iteration']}")
    print(
        f"  time: {row['wall_time_s']:.1f} s for the mission ({row['time_measure_s']:.1f} s in coverage measurements, "
        f"{row['time_optimizer_s']:.1f} s in the optimiser)"
    )
    wrote = ["runs.csv", f"runs/{row['run_id']}.npz", "example.md", "coverage.csv", "config.json"]
    if not args.no_plots:
        figures = _plot_directory(out_path)
        if figures:
            wrote += [str(Path(f).relative_to(out_path)) if Path(f).is_relative_to(out_path) else str(f) for f in figures]
    print(f"\n  wrote to {out_path}/: " + ", ".join(wrote))
    if not args.no_plots:
        print(f"  `uavcov plot {out_path}` redraws them and adds an animation of the mission")
    print(f"  total {time.perf_counter() - started:.1f} s")
    return EXIT_OK


def _plot(args: argparse.Namespace) -> int:
    from .errors import ConfigError, MissingExtraError

    directory = Path(args.directory)
    if not directory.is_dir():
        raise ConfigError(f"{directory} is not a directory of results")
    try:
        from .plotting import plot_directory

        figures = list(plot_directory(directory, args.out, max_runs=args.max_runs, animation=not args.no_animation) or [])
    except ImportError as exc:  # plotting.py missing, or matplotlib when it draws
        raise MissingExtraError(f"plotting is not available: pip install 'uavcov[plot]' (needs matplotlib; {exc})") from exc
    for figure in figures:
        print(figure)
    _say(f"{len(figures)} figure(s) written from {directory}")
    return EXIT_OK


def _view(args: argparse.Namespace) -> int:
    from .errors import MissingExtraError, ResultsFolderError

    try:
        from .plotting import find_run, write_view
    except ImportError as exc:
        raise MissingExtraError(f"the view is not available: pip install 'uavcov[view]' ({exc})") from exc
    folder = Path(args.out).absolute().parent
    if not folder.is_dir():  # before the view is drawn, which takes seconds
        raise ResultsFolderError(f"cannot write {args.out}: the folder {folder} does not exist")
    run = find_run(args.run_or_dir, args.run_name)
    out = write_view(run, args.out, max_vertices=args.max_vertices, max_frames=args.max_frames)
    size = out.stat().st_size / 1e6
    _say(f"view of {run} written to {out} ({size:.1f} MB, opens offline)")
    return EXIT_OK


def _floats(count: int, what: str) -> Callable[[str], tuple[float, ...]]:
    """An argparse type: ``count`` numbers separated by commas."""

    def parse(text: str) -> tuple[float, ...]:
        try:
            values = tuple(float(v) for v in text.split(","))
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if len(values) != count or not all(abs(v) < float("inf") for v in values):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return values

    return parse


def _prior(text: str) -> str | int:
    if text == "full":
        return text
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected 'full' or a number of sparse points, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected 'full' or a number of sparse points >= 1, got {value}")
    return value


_MESH_SUFFIXES = (".obj", ".stl", ".ply")


def _plan(args: argparse.Namespace) -> int:
    from .engine import Camera, Gimbal, Sensor
    from .errors import ConfigError
    from .field import PlanSettings, bbox_area, check_plan_folder, plan, read_area, write_plan
    from .terrain import read_dem, read_mesh_dem, sample_dem

    started = time.perf_counter()
    if args.structure is not None:
        return _plan_structure(args, started)
    if args.anchor is not None:
        raise ConfigError("--anchor places a structure (--structure); a DEM states its own georeference")
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
    from .errors import ConfigError
    from .field import GeoAnchor, check_plan_folder, plan_structure, write_structure_plan
    from .placement import Constraints, StartSettings
    from .settings import MissionSettings
    from .terrain import STRUCTURE_SCENES, load_structure

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
        structure = STRUCTURE_SCENES[args.structure](rng=args.seed)
    elif Path(args.structure).suffix.lower() in _MESH_SUFFIXES:
        structure = load_structure(args.structure)
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
        from .plotting import plot_structure_seen

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


# ---------------------------------------------------------------------------------------------
# Parser


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line, like every other error of the command line."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="uavcov",
        description="Multi-UAV visual coverage of partially known 3D surfaces (Renzaglia et al.): "
        "the paper's experiments, sweeps and figures.",
    )
    from ._core import __version__

    parser.add_argument("--version", action="version", version=f"uavcov {__version__}", help="print uavcov's version and exit")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    demo = commands.add_parser("demo", help="the paper's illustrative example end to end, in seconds")
    demo.add_argument("--out", default="out/demo", help="output directory (default out/demo)")
    demo.add_argument("--iterations", type=_non_negative_int, default=300, help="CAO iterations (default 300)")
    demo.add_argument("--seed", type=_non_negative_int, default=0, help="the scenario: terrain, prior, start, optimiser (default 0)")
    demo.add_argument("--threads", type=_positive_int, help="Rust threads (default: every core)")
    demo.add_argument("--no-plots", action="store_true", help="skip the figures")
    demo.set_defaults(run=_demo)

    reproduce = commands.add_parser("reproduce", help="one of the paper's experiments, with its table beside the paper's")
    reproduce.add_argument(
        "experiment", choices=("table1", "pyramid", "example", "comparison", "buildings", "ablation", "structures", "realistic", "all")
    )
    reproduce.add_argument("--out", help="output directory (default out/EXPERIMENT); with all, one folder per experiment and report.md")
    reproduce.add_argument("--seeds", help="scenarios, e.g. 0-39 or 1000-1009,2000 (default: the experiment's)")
    reproduce.add_argument("--team-sizes", type=_int_list, metavar="N,N,...", help="a subset of the team sizes")
    reproduce.add_argument("--starts", type=_str_list, metavar="S,S,...", help="a subset of the starts")
    reproduce.add_argument("--iterations", type=_non_negative_int, help="CAO iterations instead of the experiment's")
    reproduce.add_argument("--no-plots", action="store_true", help="skip the figures (drawn when uavcov[plot] is installed)")
    _add_execution(reproduce)
    reproduce.set_defaults(run=_reproduce)

    sweep = commands.add_parser("sweep", help="a grid of settings from a TOML file (see examples/sweep.toml)")
    sweep.add_argument("config", metavar="CONFIG.toml")
    sweep.add_argument("--out", help="output directory (default out/<config name>)")
    _add_execution(sweep)
    sweep.set_defaults(run=_sweep)

    plot = commands.add_parser("plot", help="redraw every figure from the runs stored in a directory")
    plot.add_argument("directory", metavar="DIR")
    plot.add_argument("--out", help="where the figures go (default DIR/figures)")
    plot.add_argument("--max-runs", type=_non_negative_int, default=6, help="runs drawn one by one (default 6)")
    plot.add_argument("--no-animation", action="store_true", help="skip the animation of the first run")
    plot.set_defaults(run=_plot)

    view = commands.add_parser("view", help="one self-contained HTML file with an interactive 3D view of a run")
    view.add_argument("run_or_dir", metavar="RUN_OR_DIR", help="a run's .npz, a results folder (runs/*.npz) or a folder of .npz runs")
    view.add_argument("--out", default="view.html", help="the HTML file to write (default view.html)")
    view.add_argument(
        "--run",
        dest="run_name",
        metavar="RUN_ID",
        help="in a folder, the run to show (its run_id: the file name without .npz; default the first)",
    )
    view.add_argument(
        "--max-vertices", type=_int_at_least(16), default=40_000, help="vertices of the drawn surface, at most (default 40000)"
    )
    view.add_argument("--max-frames", type=_int_at_least(2), default=60, help="iterations the slider offers, at most (default 60)")
    view.set_defaults(run=_view)

    planning = commands.add_parser("plan", help="a flight plan on a real DEM: .plan files, CSV, GeoJSON, KML, coverage GeoTIFF, report")
    planning.add_argument(
        "dem", nargs="?", metavar="DEM", help="GeoTIFF (any projected or geographic CRS) or mesh (.obj/.stl/.ply, with --crs)"
    )
    planning.add_argument("--sample", action="store_true", help="plan on the bundled sample: matplotlib's Jacksboro DEM (WGS 84)")
    planning.add_argument(
        "--window", type=_int_list, metavar="R0,R1,C0,C1", help="with --sample: rows and columns kept (default 150,190,150,190)"
    )
    planning.add_argument("--stride", type=_positive_int, default=1, help="with --sample: keep every n-th row and column (default 1)")
    planning.add_argument("--crs", help="the DEM's CRS when its file states none (e.g. EPSG:32633)")
    planning.add_argument("--uavs", type=_positive_int, required=True, help="team size")
    planning.add_argument("--d-max", type=_positive_float, required=True, help="sensing range, metres")
    planning.add_argument(
        "--h-min", type=float, help="least height above ground, metres (default 10); with --structure the least distance to it (default 2)"
    )
    planning.add_argument(
        "--h-max",
        type=_positive_float,
        help="most height above ground, metres (default 60); with --structure the most distance (default none)",
    )
    planning.add_argument(
        "--structure",
        metavar="SCENE|MESH",
        help="plan round a structure instead of over a DEM: a scene (girder_bridge, arch_bridge, wind_turbine, facade, "
        "lattice_pylon; --seed makes it) or a closed mesh file (.obj/.stl/.ply) in local metres",
    )
    planning.add_argument(
        "--anchor", type=_floats(3, "LON,LAT,ALT"), metavar="LON,LAT,ALT", help="with --structure: the WGS84 point of its local origin"
    )
    planning.add_argument("--separation", type=float, default=5.0, help="least distance between UAVs, metres (default 5)")
    planning.add_argument(
        "--takeoff", type=_floats(2, "LON,LAT or X,Y"), metavar="LON,LAT", help="take-off point (default: the area's centre)"
    )
    planning.add_argument(
        "--coords", choices=("wgs84", "dem"), default="wgs84", help="--takeoff and --bbox in WGS 84 (default) or the DEM's CRS"
    )
    where = planning.add_mutually_exclusive_group()
    where.add_argument("--aoi", metavar="AREA", help="area of interest: a GeoJSON or KML polygon file (WGS 84)")
    where.add_argument("--bbox", type=_floats(4, "XMIN,YMIN,XMAX,YMAX"), metavar="XMIN,YMIN,XMAX,YMAX", help="area of interest: a box")
    planning.add_argument(
        "--prior", type=_prior, default="full", help="what is known beforehand: full (the DEM) or N sparse points (default full)"
    )
    planning.add_argument(
        "--camera", type=_floats(2, "HFOV,VFOV in degrees"), metavar="HFOV,VFOV", help="a camera (default: omnidirectional)"
    )
    planning.add_argument(
        "--attitude",
        type=_floats(2, "YAW,PITCH in degrees"),
        metavar="YAW,PITCH",
        default=(0.0, -90.0),
        help="the camera's heading (from the DEM's grid north) and gimbal pitch (default 0,-90: nadir)",
    )
    planning.add_argument("--free-heading", action="store_true", help="optimise each camera's heading beside its position")
    planning.add_argument(
        "--pitch-range",
        type=_floats(2, "LOWEST,HIGHEST pitch in degrees"),
        metavar="LO,HI",
        help="optimise the gimbal pitch within this range",
    )
    planning.add_argument(
        "--footprint-start", action="store_true", help="lift each CVT generator until its camera's view of S' matches its cell"
    )
    planning.add_argument("--iterations", type=_non_negative_int, default=300, help="CAO iterations (default 300)")
    planning.add_argument("--hold", type=float, default=60.0, help="seconds each UAV holds its position (default 60)")
    planning.add_argument("--seed", type=_non_negative_int, default=0, help="the random streams (default 0)")
    planning.add_argument("--threads", type=_positive_int, help="Rust threads (default: every core)")
    planning.add_argument("--out", default="out/plan", help="output folder (default out/plan)")
    planning.set_defaults(run=_plan)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (see the module docstring)."""
    from .errors import UavcovError

    args = _parser().parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)  # the report states the command that made it
    try:
        return int(args.run(args))
    except UavcovError as exc:
        _say(f"uavcov {args.command}: error: {_one_line(exc)}")
        return EXIT_BAD_INPUT
    except (OSError, MemoryError) as exc:  # the system refused (disk full, no permission, no memory): one line too
        _say(f"uavcov {args.command}: error: {type(exc).__name__}: {_one_line(exc)}")
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        out = getattr(args, "out", None)
        where = f" in {out}/runs.csv" if out else ""
        _say(f"\ninterrupted: every finished run is saved{where}; rerun with --resume to continue")
        return EXIT_INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
