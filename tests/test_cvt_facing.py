"""The CVT's normal weight (``CVTSettings.normal_weight``): regions that face one way, each
generator's facing, the paper's CVT unchanged at weight 0, the structure starts flown out along
the facing, and bad weights refused."""

from __future__ import annotations

import dataclasses
import json
import pickle

import numpy as np
import pytest

import uavcov
from tiny import tiny_experiment
from uavcov import Terrain
from uavcov.errors import InvalidInputError, InvalidTypeError
from uavcov.experiments._sweep import experiment_settings, settings_hash
from uavcov.placement import CVTSettings, cvt, standoff_start
from uavcov.records import load_mission, save_mission

# A closed 20 m x 10 m x 4 m slab, faces wound outward.
SLAB = np.array([[0, 0, 0], [20, 0, 0], [20, 10, 0], [0, 10, 0], [0, 0, 4], [20, 0, 4], [20, 10, 4], [0, 10, 4]], float)
SLAB_FACES = np.array(
    [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
)
AXES = np.array([[0, 0, -1], [0, 0, 1], [0, -1, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0]], float)
CENTRES = np.array([[10, 5, 0], [10, 5, 4], [10, 0, 2], [20, 5, 2], [10, 10, 2], [0, 5, 2]], float)


@pytest.fixture(scope="module")
def slab() -> Terrain:
    return Terrain(SLAB, SLAB_FACES)


def test_one_generator_per_face_of_a_slab_is_a_weighted_cvt_and_not_a_plain_one(slab):
    settings = CVTSettings(normal_weight=20.0, preset="annealed", tol=0.0, max_iterations=150)
    # From the faces' centroids the weighted CVT stays there, each facing its face's normal.
    fixed = cvt(slab, 6, settings, initial=CENTRES, rng=3, n_threads=1)
    np.testing.assert_allclose(fixed.normals, AXES, atol=1e-9)
    assert np.abs(fixed.generators - CENTRES).max() < 0.6
    # By position alone it does not: the small end faces (4 m x 10 m) are shared with the
    # large ones and keep no generator near their centres.
    plain = cvt(slab, 6, replace_weight(settings, 0.0), initial=CENTRES, rng=3, n_threads=1)
    assert (np.linalg.norm(plain.generators - CENTRES, axis=1)[[3, 5]] > 2.0).all()

    # From random starts (k-means has local minima) the weighted CVT finds one generator per
    # face on most seeds; the plain one on none.
    def faces_taken(result) -> int:
        agreement = result.normals @ AXES.T
        return len(set(agreement.argmax(axis=1)[agreement.max(axis=1) > 0.999]))

    weighted = [faces_taken(cvt(slab, 6, settings, rng=seed, n_threads=1)) for seed in range(5)]
    unweighted = [faces_taken(cvt(slab, 6, replace_weight(settings, 0.0), rng=seed, n_threads=1)) for seed in range(5)]
    assert sum(w == 6 for w in weighted) >= 4 and not any(u == 6 for u in unweighted), (weighted, unweighted)


def replace_weight(settings: CVTSettings, weight: float) -> CVTSettings:
    return dataclasses.replace(settings, normal_weight=weight)


def test_weight_zero_is_the_paper_cvt_and_facings_are_unit(slab):
    hills = uavcov.gaussian_hills(size=60.0, spacing=2.0, n_hills=3, rng=4)
    base = cvt(hills, 7, rng=11, n_threads=1)
    zero = cvt(hills, 7, CVTSettings(normal_weight=0.0), rng=11, n_threads=1)
    np.testing.assert_array_equal(base.generators, zero.generators)
    np.testing.assert_array_equal(base.energy, zero.energy)
    np.testing.assert_allclose(np.linalg.norm(base.normals, axis=1), 1.0)
    assert (base.normals[:, 2] > 0.5).all()  # hills face up
    weighted = cvt(hills, 7, CVTSettings(normal_weight=20.0), rng=11, n_threads=1)
    assert not np.array_equal(weighted.generators, base.generators)
    # The weight's energy counts the facing term: never below the positional energy's scale.
    assert weighted.energy[-1] > 0


@pytest.mark.parametrize("surface_name", ["slab", "hills"])
def test_weighted_runs_do_not_depend_on_threads(slab, surface_name):
    surface = slab if surface_name == "slab" else uavcov.gaussian_hills(size=80.0, spacing=1.0, n_hills=4, rng=1)
    settings = CVTSettings(normal_weight=8.0, max_iterations=30)
    one = cvt(surface, 6, settings, rng=5, n_threads=1)
    two = cvt(surface, 6, settings, rng=5, n_threads=2)
    np.testing.assert_array_equal(one.generators, two.generators)
    np.testing.assert_array_equal(one.normals, two.normals)
    again = pickle.loads(pickle.dumps(one))
    np.testing.assert_array_equal(again.normals, one.normals)


@pytest.mark.parametrize(
    "weight, error",
    [
        (-1.0, InvalidInputError),
        (float("nan"), InvalidInputError),
        (float("inf"), InvalidInputError),
        (1e300, InvalidInputError),
        ("5", InvalidTypeError),
    ],
)
def test_bad_weights_are_refused(weight, error):
    with pytest.raises(error):
        CVTSettings(normal_weight=weight)


def test_the_weight_keeps_old_settings_hashes_and_changes_new_ones():
    exp = tiny_experiment()
    assert "normal_weight" not in experiment_settings(exp)["mission"]["cvt"]
    weighted = dataclasses.replace(exp, mission=dataclasses.replace(exp.mission, cvt=CVTSettings(normal_weight=10.0)))
    assert experiment_settings(weighted)["mission"]["cvt"]["normal_weight"] == 10.0
    assert settings_hash(weighted) != settings_hash(exp)


def test_records_keep_the_facings_and_read_files_without_them(tmp_path):
    terrain = uavcov.gaussian_hills(size=30.0, spacing=1.0, n_hills=3, rng=2)
    run = uavcov.run_mission(terrain, uavcov.MissionSettings(n_uavs=2, d_max=15.0, n_prior=8, iterations=3), rng=1, n_threads=1)
    path = save_mission(run, tmp_path / "run.npz")
    np.testing.assert_array_equal(load_mission(path).cvt.normals, run.cvt.normals)
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files if k != "cvt_normals"}
    json.loads(str(arrays["header"]))
    np.savez(tmp_path / "old.npz", **arrays)
    old = load_mission(tmp_path / "old.npz")
    assert old.cvt.normals is None
    np.testing.assert_array_equal(old.cvt.generators, run.cvt.generators)


def test_a_weighted_start_flies_out_along_each_region_facing(slab):
    settings = CVTSettings(normal_weight=20.0, preset="annealed", tol=0.0, max_iterations=150)
    start = standoff_start(slab, 6, 3.0, cvt_settings=settings, rng=2, n_threads=1)
    np.testing.assert_allclose(start.positions, start.anchors + 3.0 * start.normals, atol=1e-9)
    np.testing.assert_allclose((start.normals @ AXES.T).max(axis=1), 1.0, atol=1e-9)  # along the axes
    # Every start outside the slab, 3 m from it.
    inside = ((start.positions > SLAB.min(axis=0)) & (start.positions < SLAB.max(axis=0))).all(axis=1)
    assert not inside.any()
    np.testing.assert_allclose(start.distance, 3.0, atol=1e-6)
