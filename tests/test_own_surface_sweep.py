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
