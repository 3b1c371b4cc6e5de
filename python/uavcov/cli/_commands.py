"""The commands that run experiments and draw them: ``demo``, ``reproduce``, ``sweep``, ``plot``, ``view``."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from ._common import (
    EXIT_OK,
    EXIT_RUNS_FAILED,
    _execution,
    _finish,
    _say,
)

# ---------------------------------------------------------------------------------------------
# Commands


def _reproduce(args: argparse.Namespace) -> int:
    from ..paper import reproduce

    if args.experiment not in ("realistic", "flown-table1") and (args.measurements or args.standoff is not None):
        from ..errors import InvalidInputError

        raise InvalidInputError("--measurements and --standoff are the realistic scenario's flags")
    if args.experiment == "all":
        return _reproduce_all(args)
    if args.experiment == "ablation":
        return _reproduce_ablation(args)
    if args.experiment == "structures":
        return _reproduce_structures(args)
    if args.experiment in ("realistic", "flown-table1"):
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
    """The paper's realistic scenario flown (uavcov.sim, the ``sim`` extra): serial, one core,
    resumable (``--resume``); once every run is in, ``--resume`` only rewrites the report."""
    from ..errors import InvalidInputError
    from ..paper import reproduce_flown_table1, reproduce_realistic

    out = Path(args.out or f"out/{args.experiment}")
    if args.experiment == "flown-table1":
        if args.measurements or args.standoff is not None:
            raise InvalidInputError("--measurements and --standoff are the realistic scenario's: Table 1 flown measures exactly")
        rows = reproduce_flown_table1(
            out,
            seeds=args.seeds,
            starts=args.starts or ("cvt", "random", "corner"),
            iterations=100 if args.iterations is None else args.iterations,
            resume=bool(args.resume),
            progress=_say,
        )
    else:
        rows = reproduce_realistic(
            out,
            seeds=args.seeds,
            starts=args.starts or ("cvt", "pairs"),
            measurements=args.measurements or ("exact", "sensed"),
            iterations=200 if args.iterations is None else args.iterations,
            resume=bool(args.resume),
            progress=_say,
            standoff=args.standoff,
        )
    print((out / "realistic.md").read_text(encoding="utf-8"))
    failed = sum(bool(r["failure"]) for r in rows)
    _say(f"{len(rows)} flown run(s), {failed} failed, in {out}/")
    return 0


def _refuse_choice_within(args: argparse.Namespace, what: str) -> None:
    """``--team-sizes`` and ``--starts`` pick cells of one experiment; ``what`` runs several."""
    from ..errors import ConfigError

    if args.team_sizes is not None or args.starts is not None:
        raise ConfigError(f"--team-sizes and --starts choose within one experiment, not with {what}")


def _reproduce_ablation(args: argparse.Namespace) -> int:
    from ..paper import ablate

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

    from ..experiments import available_cores, parse_seeds
    from ..paper import StructuresExperiment, reproduce_structures

    report = "structures.md"  # what reproduce_structures writes beside rows.jsonl and config.json

    _refuse_choice_within(args, "structures")
    experiment = StructuresExperiment()
    if args.seeds is not None:
        experiment = replace(experiment, report_seeds=parse_seeds(args.seeds))
    if args.iterations is not None:
        experiment = replace(experiment, iterations=args.iterations, trace_iterations=max(args.iterations, experiment.trace_iterations))
    out = Path(args.out or "out/structures")
    started = time.perf_counter()
    if args.scheduler is None and args.dask_workers is None:
        workers = args.workers or available_cores()
        rows = reproduce_structures(out, experiment, workers=workers, resume=bool(args.resume), progress=_say)
    else:
        with _execution(args) as options:
            rows = reproduce_structures(out, experiment, executor=options["executor"], resume=bool(args.resume), progress=_say)
    print((out / report).read_text(encoding="utf-8"))
    _say(f"{len(rows)} run(s) in {time.perf_counter() - started:.1f} s; results in {out}/: rows.jsonl, config.json, {report}, figures/")
    return EXIT_RUNS_FAILED if any(r["error"] for r in rows) else EXIT_OK


def _reproduce_all(args: argparse.Namespace) -> int:
    from ..paper import reproduce_all

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
    from ..experiments import load_sweep_config, run_sweep
    from ..paper import EXPERIMENTS

    config = load_sweep_config(args.config, bases=EXPERIMENTS)
    out = Path(args.out or f"out/{Path(args.config).stem}")
    started = time.perf_counter()
    with _execution(args) as options:
        execution = options.pop("execution")
        rows = run_sweep(config, out, source_text=Path(args.config).read_text(encoding="utf-8"), execution=execution, **options)
    print((out / "summary.md").read_text(encoding="utf-8"))
    return _finish(rows, out, started, ["runs.csv", "config.json", "sweep.toml", "summary.md"] + ([] if args.no_save_runs else ["runs/"]))


def _report_figures(folder: Path) -> list[str]:
    from ..plotting import report_figures

    return report_figures(folder)


def _plot_directory(out: Path) -> list[Path] | None:
    """Draw the figures of ``out`` (not the animation, which takes longer) when plotting is available."""
    try:
        from ..plotting import plot_directory

        return list(plot_directory(out, animation=False) or [])
    except ImportError as exc:  # plotting.py missing, or matplotlib when it draws
        _say(f"(no figures: plotting needs matplotlib, pip install 'uavcov[plot]': {exc})")
        return None


def _demo(args: argparse.Namespace) -> int:
    from ..experiments import available_cores
    from ..paper import EXAMPLE, reproduce
    from ..terrain import HillsGenerator

    out = Path(args.out)
    threads = args.threads or available_cores()
    experiment = EXAMPLE
    terrain = experiment.generator
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
    from ..errors import ConfigError, MissingExtraError

    directory = Path(args.directory)
    if not directory.is_dir():
        raise ConfigError(f"{directory} is not a directory of results")
    try:
        from ..plotting import plot_directory

        figures = list(plot_directory(directory, args.out, max_runs=args.max_runs, animation=not args.no_animation) or [])
    except ImportError as exc:  # plotting.py missing, or matplotlib when it draws
        raise MissingExtraError(f"plotting is not available: pip install 'uavcov[plot]' (needs matplotlib; {exc})") from exc
    for figure in figures:
        print(figure)
    _say(f"{len(figures)} figure(s) written from {directory}")
    return EXIT_OK


def _view(args: argparse.Namespace) -> int:
    from ..errors import MissingExtraError, ResultsFolderError

    try:
        from ..plotting import find_run, write_view
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
