"""Experiments on a surface of the user's own: the same results folder as the paper's generators.

An :class:`~uavcov.experiments.Experiment` whose terrain is a :class:`~uavcov.Terrain` runs
every seed on that surface; its settings hash (so its run ids and its folder's identity) holds a
digest of the surface's geometry.
"""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

import uavcov
from uavcov.errors import ConfigError, InvalidInputError, InvalidTypeError, ResultsInUseError
from uavcov.experiments import Experiment, experiment_specs, read_runs, run_specs, summarise
from uavcov.experiments._sweep import settings_hash

TIMING = {"wall_time_s", "time_measure_s", "time_optimizer_s", "time_feasibility_s", "start_time_s"}


def valley(dz: float = 0.0) -> uavcov.Terrain:
    x = np.arange(0.0, 40.1, 2.0)
    z = 100.0 + 6.0 * np.sin(x[None, :] / 8.0) + 3.0 * np.cos(x[:, None] / 6.0)
    z[3, 4] += dz
    return uavcov.Terrain.from_grid(z, spacing=2.0)


LIMITS = uavcov.Constraints(h_min=3.0, h_max=20.0, z_max=140.0)
MISSION = uavcov.MissionSettings(n_uavs=2, d_max=12.0, n_prior=10, iterations=8, constraints=LIMITS)


def own(terrain: uavcov.Terrain | None = None) -> Experiment:
    surface = valley() if terrain is None else terrain
    return Experiment("valley", surface, MISSION, team_sizes=(2, 3), starts=("cvt", "random"), seeds=(0, 1))


def without_timing(rows):
    return [{k: v for k, v in r.items() if k not in TIMING} for r in rows]


def test_each_row_is_the_mission_on_that_surface_and_the_folder_reads_back(tmp_path) -> None:
    experiment = own()
    specs = experiment_specs(experiment)
    rows = run_specs(specs, out=tmp_path / "sweep", workers=1)
    assert len(rows) == 8 and all(r["error"] == "" for r in rows)
    for spec, row in zip(specs, rows, strict=True):
        direct = uavcov.run_mission(experiment.terrain, spec.mission, rng=spec.seed)
        assert row["max_coverage"] == direct.best_coverage and row["initial_coverage"] == direct.initial_coverage
        assert spec.run_id.startswith(f"valley-{spec.start}-n{spec.n_uavs:02d}-s{spec.seed:04d}-")
    assert without_timing(read_runs(tmp_path / "sweep" / "runs.csv")) == without_timing(rows)
    cells = summarise(rows, by=("n_uavs", "init"))
    assert sorted(cells) == [(2, "cvt"), (2, "random"), (3, "cvt"), (3, "random")]
    assert cells[(3, "cvt")]["max_coverage"][0] == pytest.approx(np.mean([r["max_coverage"] for r in rows[2::4]]))
    config = json.loads((tmp_path / "sweep" / "config.json").read_text())
    (entry,) = config["settings"].values()
    assert entry["experiment"]["terrain_kind"] == "surface"
    assert entry["experiment"]["terrain"]["grid"] == [21, 21] and len(entry["experiment"]["terrain"]["sha256"]) == 64
    saved = uavcov.load_mission(tmp_path / "sweep" / "runs" / f"{rows[0]['run_id']}.npz")
    np.testing.assert_array_equal(saved.terrain.grid.z, experiment.terrain.grid.z)
    # a resume runs nothing again; another surface in the same folder is refused
    assert without_timing(run_specs(specs, out=tmp_path / "sweep", resume=True, workers=1)) == without_timing(rows)
    with pytest.raises(ResultsInUseError):
        run_specs(experiment_specs(own(valley(dz=0.5))), out=tmp_path / "sweep", resume=True, exclusive=True, workers=1)


def test_the_settings_hash_follows_the_geometry_and_nothing_else() -> None:
    base = settings_hash(own())
    assert settings_hash(own(valley())) == base  # the same heights, another object
    assert settings_hash(own(valley(dz=1e-9))) != base  # one node moved by a nanometre
    mesh = uavcov.Terrain(valley().vertices, valley().faces)  # the same surface as a mesh is another input
    assert settings_hash(own(mesh)) not in (base, settings_hash(own(valley(dz=1.0))))
    shifted = uavcov.Terrain(valley().vertices + [0.0, 0.0, 1e-6], valley().faces)
    assert settings_hash(own(shifted)) != settings_hash(own(mesh))
    assert settings_hash(own().with_changes(d_max=13.0)) != base


def test_a_pool_gives_the_rows_of_one_process_and_specs_pickle() -> None:
    specs = experiment_specs(own(), team_sizes=[2], starts=["cvt"])
    assert [pickle.loads(pickle.dumps(s)).run_id for s in specs] == [s.run_id for s in specs]
    assert without_timing(run_specs(specs, workers=2)) == without_timing(run_specs(specs, workers=1))


def test_what_only_a_generator_has_is_refused_with_a_clear_error() -> None:
    experiment = own()
    assert experiment.scenario(5) is experiment.terrain and experiment.known(5) is None
    with pytest.raises(ConfigError, match="surface of its own"):
        _ = experiment.generator
    with pytest.raises(InvalidInputError, match="no fields to set"):
        experiment.with_changes(**{"terrain.spacing": 1.0})
    with pytest.raises(InvalidInputError, match="'map' prior"):
        experiment.with_changes(prior="map")
    for bad in ("valley.ply", valley().grid, None, valley().vertices):
        with pytest.raises(InvalidTypeError, match="HillsGenerator, BuildingsGenerator or Terrain"):
            Experiment("valley", bad, MISSION, team_sizes=(2,), starts=("cvt",))


# ---------------------------------------------------------------------------------------------
# A sweep file on a surface of one's own: [terrain] kind = "file"

SWEEP = """
name = "valley"
seeds = [0, 1]
team_sizes = [2]
starts = ["cvt", "random"]
d_max = 12.0
n_prior = 10
iterations = 8

[terrain]
kind = "file"
{terrain}

[constraints]
h_min = 3.0
h_max = 20.0
z_max = 140.0

[sweep]
"cao.alpha0" = [1.0, 2.0]
"""


def sweep_file(folder, terrain: str):
    path = folder / "sweep.toml"
    path.write_text(SWEEP.format(terrain=terrain))
    return path


def test_a_sweep_file_runs_on_a_grid_or_a_mesh_of_ones_own(tmp_path, monkeypatch) -> None:
    from uavcov.experiments import load_sweep_config, run_sweep
    from uavcov.paper import EXPERIMENTS

    np.save(tmp_path / "valley.npy", valley().grid.z)
    monkeypatch.chdir(tmp_path.parent)  # the path is read from the sweep file's folder, not from here
    config = load_sweep_config(sweep_file(tmp_path, 'path = "valley.npy"\nspacing = 2.0'), bases=EXPERIMENTS)
    (experiment, _), _ = config.variants
    np.testing.assert_array_equal(experiment.terrain.grid.z, valley().grid.z)
    rows = run_sweep(config, tmp_path / "out", workers=1)
    assert len(rows) == 8 and all(r["error"] == "" for r in rows)
    for row in rows:  # each the mission of its variant on that surface
        (variant,) = [e for e, extra in config.variants if dict(extra)["cao.alpha0"] == float(row["cao.alpha0"])]
        direct = uavcov.run_mission(valley(), variant.mission_settings(2, row["init"]), rng=row["seed"])
        assert row["max_coverage"] == direct.best_coverage
    assert "| 2.0 | 2 | random | 2 |" in (tmp_path / "out" / "summary.md").read_text()

    trimesh = pytest.importorskip("trimesh")
    trimesh.Trimesh(valley().vertices, valley().faces, process=False).export(tmp_path / "valley.ply")
    config = load_sweep_config(sweep_file(tmp_path, 'path = "valley.ply"\nup = "z"'), bases=EXPERIMENTS)
    assert config.variants[0][0].terrain.grid is None and config.variants[0][0].terrain.n_faces == valley().n_faces


def test_a_sweep_file_with_a_bad_surface_is_refused_naming_the_key(tmp_path) -> None:
    from uavcov.experiments import load_sweep_config
    from uavcov.paper import EXPERIMENTS

    np.save(tmp_path / "valley.npy", valley().grid.z)
    np.save(tmp_path / "line.npy", np.zeros(10))
    np.save(tmp_path / "tall.npy", np.zeros((4001, 2)))
    np.save(tmp_path / "objects.npy", np.array([{"z": 1.0}], dtype=object), allow_pickle=True)
    (tmp_path / "text.npy").write_text("not an array")
    (tmp_path / "junk.stl").write_bytes(b"solid x\x00\xff" * 10)
    cases = {
        'path = "missing.npy"\nspacing = 1.0': "terrain.path: .*missing.npy",
        'path = "valley.npy"': "terrain.spacing: a .npy grid needs its cell size",
        'path = "valley.npy"\nspacing = -1.0': "terrain.path: .*spacing must be > 0",
        'path = "valley.npy"\nspacing = 1.0\nup = "y"': "terrain.up: not read for a .npy file",
        'path = "line.npy"\nspacing = 1.0': r"terrain.path: .*got \(10,\)",
        'path = "tall.npy"\nspacing = 1.0': "at most 4000 nodes a side",
        'path = "objects.npy"\nspacing = 1.0': "terrain.path: .*objects.npy",
        'path = "text.npy"\nspacing = 1.0': "not a .npy array of heights",
        'path = "junk.stl"': "terrain.path: .*junk.stl",
        'path = "junk.stl"\nspacing = 1.0': "terrain.spacing: not read for a .stl file",
        'path = "dem.tif"': "terrain.path: .*dem.tif",
        'path = "."': "terrain.path: .*directory",
        "path = 3": 'terrain.path: kind = "file" needs the path',
        'paht = "valley.npy"': "terrain.paht: unknown key",
    }
    for table, words in cases.items():
        with pytest.raises(ConfigError, match=words):
            load_sweep_config(sweep_file(tmp_path, table), bases=EXPERIMENTS)
