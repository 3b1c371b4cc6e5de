"""The command line's parser: every command and flag, and the function each command runs."""

from __future__ import annotations

import argparse
from typing import Any, NoReturn

from ._commands import (
    _demo,
    _plot,
    _reproduce,
    _sweep,
    _view,
)
from ._common import (
    EXIT_BAD_INPUT,
    _add_execution,
    _floats,
    _int_at_least,
    _int_list,
    _non_negative_int,
    _path_text,
    _positive_float,
    _positive_int,
    _prior,
    _str_list,
)
from ._plan import _plan

# ---------------------------------------------------------------------------------------------
# Parser


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line, like every other error of the command line."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


# What each experiment is and how many runs it makes by default (tests/test_cli.py checks the counts
# against uavcov.paper.EXPERIMENTS): a new user should not start 640 runs by surprise.
_REPRODUCE_EPILOG = """\
experiments (docs/reproduction.md sets each beside the paper):
  example       Fig. 5: 9 UAVs, d_max 35 m, CVT start, 500 iterations; 1 run, seconds
  comparison    Fig. 6: corner, random and CVT starts, N = 10, one terrain; 3 runs
  buildings     Figs. 7-8: 4 UAVs among buildings, CVT from a simplified map against two pairs; 2 runs
  pyramid       section V-D: S' from the 4 corners and the centre only, N = 12, seeds 0-39; 40 runs
  table1        Table 1: N = 5, 8, 12, 20 x starts cvt, random, corner, greedy x seeds 0-39; 640 runs
                (try --seeds 0 first: 16 runs)
  ablation      the paper's model and 13 single changes, N = 5 and 12, seeds 0-9; 840 runs
  structures    bridges, a tower, a facade, a pylon: CVT on the 3D prior against others (docs/structures.md)
  realistic     the realistic scene flown by RotorPy quadrotors (extra uavcov[sim]), serial, resumable
  flown-table1  Table 1 at N = 12 flown (extra uavcov[sim])
  all           every experiment, one folder each, then report.md with every claim and its verdict"""


def _command(commands: Any, name: str, summary: str, details: str = "", **options: Any) -> argparse.ArgumentParser:
    """A command: ``summary`` in ``uavcov --help``'s list, and at the top of ``uavcov NAME --help`` with ``details``."""
    description = f"uavcov {name}: {summary}." + (f" {details}" if details and not details.startswith("\n") else details)
    parser: argparse.ArgumentParser = commands.add_parser(name, help=summary, description=description, **options)
    return parser


def _parser() -> argparse.ArgumentParser:
    """Every command with its flags, each bound to the function it runs (``args.run``)."""
    parser = _Parser(
        prog="uavcov",
        description="Multi-UAV visual coverage of partially known 3D surfaces (Renzaglia et al.): "
        "the paper's experiments, sweeps and figures.",
    )
    from .._core import __version__

    parser.add_argument("--version", action="version", version=f"uavcov {__version__}", help="print uavcov's version and exit")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    demo = _command(
        commands,
        "demo",
        "the paper's illustrative example end to end, in seconds",
        "9 UAVs, d_max 35 m, 30 known points -> S', a CVT start on S', then CAO on the true terrain; "
        "prints a summary and writes runs.csv, the run and its figures to --out.",
    )
    demo.add_argument("--out", type=_path_text, default="out/demo", help="output directory (default out/demo)")
    demo.add_argument("--iterations", type=_non_negative_int, default=300, help="CAO iterations (default 300)")
    demo.add_argument("--seed", type=_non_negative_int, default=0, help="the scenario: terrain, prior, start, optimiser (default 0)")
    demo.add_argument("--threads", type=_positive_int, help="Rust threads (default: every core)")
    demo.add_argument("--no-plots", action="store_true", help="skip the figures")
    demo.set_defaults(run=_demo)

    reproduce = _command(
        commands,
        "reproduce",
        "one of the paper's experiments, with its table beside the paper's",
        "\nRuns the experiment's missions into --out (runs.csv, runs/, config.json, EXPERIMENT.md)\nand prints its table.",
        epilog=_REPRODUCE_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    reproduce.add_argument(
        "experiment",
        choices=("table1", "pyramid", "example", "comparison", "buildings", "ablation", "structures", "realistic", "flown-table1", "all"),
        help="which experiment (see the list below)",
    )
    reproduce.add_argument(
        "--out", type=_path_text, help="output directory (default out/EXPERIMENT); with all, one folder per experiment and report.md"
    )
    reproduce.add_argument("--seeds", help="scenarios, e.g. 0-39 or 1000-1009,2000 (default: the experiment's)")
    reproduce.add_argument("--team-sizes", type=_int_list, metavar="N,N,...", help="a subset of the team sizes")
    reproduce.add_argument("--starts", type=_str_list, metavar="S,S,...", help="a subset of the starts")
    reproduce.add_argument("--iterations", type=_non_negative_int, help="CAO iterations instead of the experiment's")
    reproduce.add_argument("--no-plots", action="store_true", help="skip the figures (drawn when uavcov[plot] is installed)")
    reproduce.add_argument(
        "--measurements", type=_str_list, metavar="M,M", help="realistic only: CAO's measurements, among exact,sensed (default both)"
    )
    reproduce.add_argument(
        "--standoff",
        type=_positive_float,
        metavar="M",
        help="realistic only: fly under a 3D standoff of M metres from any surface instead of eq. 2's clearance straight down",
    )
    _add_execution(reproduce)
    reproduce.set_defaults(run=_reproduce)

    sweep = _command(
        commands,
        "sweep",
        "a grid of settings from a TOML file (see examples/sweep.toml)",
        "Every combination of the settings under [sweep], for every seed, team size and start, on the paper's "
        'terrains or a surface of your own ([terrain] kind = "file"); writes runs.csv and summary.md to --out.',
    )
    sweep.add_argument("config", type=_path_text, metavar="CONFIG.toml", help="the sweep file (examples/sweep.toml explains every key)")
    sweep.add_argument("--out", type=_path_text, help="output directory (default out/<config name>)")
    _add_execution(sweep)
    sweep.set_defaults(run=_sweep)

    plot = _command(commands, "plot", "redraw every figure from the runs stored in a directory")
    plot.add_argument(
        "directory", type=_path_text, metavar="DIR", help="a results folder (runs.csv, runs/*.npz) of demo, reproduce or sweep"
    )
    plot.add_argument("--out", type=_path_text, help="where the figures go (default DIR/figures)")
    plot.add_argument("--max-runs", type=_non_negative_int, default=6, help="runs drawn one by one (default 6)")
    plot.add_argument("--no-animation", action="store_true", help="skip the animation of the first run")
    plot.set_defaults(run=_plot)

    view = _command(commands, "view", "one self-contained HTML file with an interactive 3D view of a run")
    view.add_argument(
        "run_or_dir", type=_path_text, metavar="RUN_OR_DIR", help="a run's .npz, a results folder (runs/*.npz) or a folder of .npz runs"
    )
    view.add_argument("--out", type=_path_text, default="view.html", help="the HTML file to write (default view.html)")
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

    _add_plan(commands)
    return parser


def _add_plan(commands: Any) -> None:
    """``uavcov plan`` and its flags: the site, the team and its limits, the camera, the run."""
    planning = _command(
        commands, "plan", "a flight plan on a real DEM or round a structure: .plan files, CSV, GeoJSON, KML, coverage GeoTIFF, report"
    )
    planning.add_argument(
        "dem",
        nargs="?",
        type=_path_text,
        metavar="DEM",
        help="GeoTIFF (any projected or geographic CRS) or mesh (.obj/.stl/.ply, with --crs)",
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
        type=_path_text,
        metavar="SCENE|MESH",
        help="plan round a structure instead of over a DEM: a scene (girder_bridge, arch_bridge, wind_turbine, facade, "
        "lattice_pylon; --seed makes it) or a closed mesh file (.obj/.stl/.ply) in local metres",
    )
    planning.add_argument(
        "--anchor",
        type=_floats(3, "LON,LAT,ALT"),
        metavar="LON,LAT,ALT",
        help="with --structure: WGS 84 longitude, latitude (degrees) and ellipsoidal height (metres) of its local origin: "
        "a scene's (0, 0, 0), a mesh file's lowest south-west bounding-box corner",
    )
    planning.add_argument(
        "--scale", type=_positive_float, default=1.0, help="with --structure MESH: metres per unit of the file (0.001 for millimetres)"
    )
    planning.add_argument(
        "--open-mesh",
        action="store_true",
        help="with --structure MESH: read a mesh that is not closed solids (open or non-manifold edges, solids sharing an edge)",
    )
    planning.add_argument("--separation", type=float, default=5.0, help="least distance between UAVs, metres (default 5)")
    planning.add_argument(
        "--takeoff", type=_floats(2, "LON,LAT or X,Y"), metavar="LON,LAT", help="take-off point (default: the area's centre)"
    )
    planning.add_argument(
        "--coords", choices=("wgs84", "dem"), default="wgs84", help="--takeoff and --bbox in WGS 84 (default) or the DEM's CRS"
    )
    where = planning.add_mutually_exclusive_group()
    where.add_argument("--aoi", type=_path_text, metavar="AREA", help="area of interest: a GeoJSON or KML polygon file (WGS 84)")
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
    planning.add_argument("--out", type=_path_text, default="out/plan", help="output folder (default out/plan)")
    planning.set_defaults(run=_plan)
