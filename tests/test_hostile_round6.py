"""Hostile input, round six: what got through the five rounds before.

Numbers that ``float()`` cannot hold (an int or Fraction past 1.8e308) or that numpy counts as
integers without being numbers of anything (``np.timedelta64``), masked arrays read as the data
under their mask, unsigned indices that wrapped to negative ones, counts that overflowed the
core or a float (a CVT ``window``, a subnormal ``move_step``, cell or dpi, a camera of 10**400
pixels) and settings whose derived constants underflowed. Files, paths and writers are in
``tests/test_hostile_round6_files.py``. Each class is tried with several hostile
values, each asserting the precise error of :mod:`uavcov.errors` and a message naming what is
wrong, or the right answer.
"""

from __future__ import annotations

import dataclasses
import re
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import uavcov
from refusals import refused
from uavcov.errors import InvalidInputError, InvalidTypeError, MeshError, ResultsFormatError
from uavcov.limits import Constraints, feasibility

HILLS = uavcov.gaussian_hills(size=30, spacing=1, n_hills=2, rng=0)
UAVS = np.array([[10.0, 10.0, 30.0], [20.0, 20.0, 30.0]])
HUGE = 10**400  # an int float() cannot hold

# ---------------------------------------------------------------------------------------------
# Numbers float() cannot hold: an OverflowError leaked from every float setting


SETTINGS = [
    (uavcov.MissionSettings, {"n_uavs": 2, "d_max": 10.0}, "d_max"),
    (uavcov.PlanSettings, {"n_uavs": 2, "d_max": 10.0}, "h_min"),
    (uavcov.PlanSettings, {"n_uavs": 2, "d_max": 10.0}, "cruise_speed"),
    (uavcov.CVTSettings, {}, "tol"),
    (uavcov.CVTSettings, {}, "normal_weight"),
    (uavcov.CAOSettings, {}, "alpha0"),
    (uavcov.Constraints, {}, "z_max"),
    (uavcov.StartSettings, {}, "altitude"),
    (uavcov.EscapeSettings, {}, "hop"),
]


@pytest.mark.parametrize("value", [HUGE, -HUGE, Fraction(HUGE), Fraction(-HUGE, 3)])
@pytest.mark.parametrize("cls, base, field", SETTINGS, ids=[f"{c.__name__}.{f}" for c, _, f in SETTINGS])
def test_a_number_beyond_the_largest_float_is_refused_not_an_overflow(cls: Any, base: dict[str, Any], field: str, value: Any) -> None:
    refused(InvalidInputError, f"{field} must be finite, got a number beyond the largest float", cls, **{**base, field: value})


@pytest.mark.parametrize("value", [HUGE, Fraction(HUGE)])
@pytest.mark.parametrize("cls, base, field", SETTINGS[:4], ids=[f"{c.__name__}.{f}" for c, _, f in SETTINGS[:4]])
def test_replace_checks_again_what_the_constructor_checks(cls: Any, base: dict[str, Any], field: str, value: Any) -> None:
    settings = cls(**base)
    refused(InvalidInputError, f"{field} must be finite", dataclasses.replace, settings, **{field: value})


@pytest.mark.parametrize(
    "call",
    [
        lambda v: uavcov.Terrain.from_grid(np.zeros((4, 4)), spacing=v),
        lambda v: uavcov.Visibility(HILLS, v, n_threads=1),
        lambda v: uavcov.gaussian_hills(size=v, spacing=1, n_hills=2, rng=0),
    ],
    ids=["from_grid-spacing", "Visibility-d_max", "gaussian_hills-size"],
)
@pytest.mark.parametrize("value", [HUGE, -HUGE, 3 * HUGE])
def test_functions_refuse_a_number_beyond_the_largest_float(call: Any, value: Any) -> None:
    refused(InvalidInputError, "beyond the largest float", call, value)


def test_exact_fractions_and_numpy_scalars_within_range_keep_their_value() -> None:
    assert uavcov.CVTSettings(tol=Fraction(1, 4)).tol == 0.25
    assert uavcov.MissionSettings(n_uavs=np.int64(3), d_max=np.float32(12.5)).d_max == 12.5
    assert uavcov.MissionSettings(n_uavs=np.uint8(3), d_max=10**20).d_max == 1e20


# ---------------------------------------------------------------------------------------------
# np.timedelta64: an integer to numpy, not a count or a length


@pytest.mark.parametrize(
    "make, error, words",
    [
        (lambda td: uavcov.MissionSettings(n_uavs=td, d_max=10.0), InvalidTypeError, "n_uavs must be an integer, got timedelta64"),
        (lambda td: uavcov.MissionSettings(n_uavs=2, d_max=td), InvalidTypeError, "d_max must be a real number, got timedelta64"),
        (lambda td: uavcov.CVTSettings(window=td), InvalidTypeError, "window must be an integer"),
        (lambda td: uavcov.CAOSettings(n_candidates=td), InvalidTypeError, "n_candidates must be an integer"),
        (lambda td: uavcov.PlanSettings(n_uavs=2, d_max=10.0, hold_s=td), InvalidTypeError, "hold_s must be a real number"),
        (lambda td: uavcov.Terrain.from_grid(np.zeros((4, 4)), spacing=td), InvalidTypeError, "spacing must be a real number"),
    ],
)
@pytest.mark.parametrize("td", [np.timedelta64(5), np.timedelta64(5, "s"), np.timedelta64(1, "D")])
def test_a_timedelta_is_no_number(make: Any, error: type[Exception], words: str, td: Any) -> None:
    refused(error, words, make, td)


@pytest.mark.parametrize("unit", ["s", "ms", "D"])
@pytest.mark.parametrize(
    "make, words",
    [
        (lambda a: uavcov.Terrain(np.eye(3), a.reshape(1, 3)), "faces must hold integers, got dtype timedelta64"),
        (lambda a: uavcov.Terrain.from_grid(np.resize(a, (3, 3)), spacing=1.0), "z must hold real numbers, got dtype timedelta64"),
        (lambda a: uavcov.Terrain.from_grid(np.zeros((4, 4)), spacing=1.0, origin=a[:2]), "origin must be a real number"),
        (lambda a: uavcov.Visibility(HILLS, 10.0, n_threads=1).coverage(np.resize(a, (2, 3))), "uavs must hold real numbers"),
    ],
)
def test_timedelta_arrays_are_refused_as_numbers_and_indices(make: Any, words: str, unit: str) -> None:
    refused(InvalidTypeError, words, make, np.array([0, 1, 2], dtype=f"m8[{unit}]"))


# ---------------------------------------------------------------------------------------------
# Masked arrays: np.asarray reads the data under the mask


@pytest.mark.parametrize(
    "mask",
    [[[0, 0, 1], [0, 0, 0]], [[1, 0, 0], [0, 0, 0]], [[1, 1, 1], [1, 1, 1]]],
)
def test_masked_positions_are_refused_not_read_under_their_mask(mask: Any) -> None:
    visibility = uavcov.Visibility(HILLS, 10.0, n_threads=1)
    masked = np.ma.masked_array(UAVS, mask=mask)
    refused(InvalidInputError, "uavs has masked entries", visibility.coverage, masked)
    # a mesh's masked vertices are no-data, which a mesh cannot have
    refused(MeshError, "vertices contain NaN", uavcov.Terrain, np.ma.masked_array(np.eye(3), mask=np.eye(3)), [[0, 1, 2]])


@pytest.mark.parametrize("masked_value", [0.0, 1e300, -7.0])
def test_masked_heights_of_a_grid_are_nodata_whatever_the_data_under_them(masked_value: float) -> None:
    heights = np.zeros((5, 5))
    heights[2, 2] = masked_value
    mask = np.zeros((5, 5), bool)
    mask[2, 2] = True
    with_nan = heights.copy()
    with_nan[2, 2] = np.nan
    masked = uavcov.Terrain.from_grid(np.ma.masked_array(heights, mask=mask), spacing=1.0)
    nodata = uavcov.Terrain.from_grid(with_nan, spacing=1.0)
    assert masked.area == nodata.area == 13.0  # the 16 unit squares less the 4 round the hole, less 0.5 for each of 6 triangles
    np.testing.assert_array_equal(masked.vertices, nodata.vertices)
    np.testing.assert_array_equal(masked.faces, nodata.faces)


def test_a_mask_that_hides_nothing_reads_as_its_data() -> None:
    visibility = uavcov.Visibility(HILLS, 10.0, n_threads=1)
    assert visibility.coverage(np.ma.masked_array(UAVS, mask=False)) == visibility.coverage(UAVS)


@pytest.mark.parametrize("mask", [[False, True], [True, False], [True, True]])
def test_masked_flags_and_indices_are_refused(mask: list[bool]) -> None:
    from uavcov._validate import as_bool_array, as_index_array

    refused(InvalidInputError, "seen has masked entries", as_bool_array, np.ma.masked_array([True, False], mask=mask), "seen", 2)
    refused(InvalidInputError, "faces has masked entries", as_index_array, np.ma.masked_array([[0, 1]], mask=[mask]), "faces", columns=2)


# ---------------------------------------------------------------------------------------------
# Other array-likes that are not plain float64 arrays: the same answer as the plain array


@pytest.mark.parametrize(
    "convert",
    [
        np.matrix,
        lambda a: a.astype(">f8"),
        lambda a: a.astype(np.float32),
        lambda a: a.astype(np.longdouble),
        np.asfortranarray,
        lambda a: np.repeat(a, 2, axis=1)[:, ::2],
        lambda a: a[::-1][::-1],
        lambda a: a.tolist(),
        lambda a: tuple(map(tuple, a)),
    ],
    ids=["matrix", "big-endian", "float32", "longdouble", "fortran", "strided", "negative-stride", "list", "tuple"],
)
@pytest.mark.filterwarnings("ignore:the matrix subclass:PendingDeprecationWarning")
def test_array_likes_of_real_numbers_give_the_plain_arrays_answer(convert: Any) -> None:
    visibility = uavcov.Visibility(HILLS, 10.0, n_threads=1)
    assert visibility.coverage(convert(UAVS)) == visibility.coverage(UAVS)


@pytest.mark.parametrize(
    "value, error, words",
    [
        (np.array([[0, 1, 2**64 - 1]], dtype=np.uint64), InvalidInputError, "faces holds an index beyond int64"),
        (np.array([[0, 1, 2**63]], dtype=np.uint64), InvalidInputError, "faces holds an index beyond int64"),
        (np.array([[0, 1, 2]], dtype="m8"), InvalidTypeError, "faces must hold integers"),
        (np.array([[True, False, True]]), InvalidTypeError, "faces must hold integers"),
    ],
)
def test_face_indices_that_int64_would_wrap_are_refused(value: np.ndarray, error: type[Exception], words: str) -> None:
    refused(error, words, uavcov.Terrain, np.eye(3), value)


def test_unsigned_face_indices_within_int64_are_read() -> None:
    faces = np.array([[0, 1, 2]], dtype=np.uint64)
    assert uavcov.Terrain(np.eye(3), faces).area == uavcov.Terrain(np.eye(3), [[0, 1, 2]]).area


# ---------------------------------------------------------------------------------------------
# Counts that overflowed the core


@pytest.mark.parametrize("window", [2**64, 10**60, 10**6 + 1])
def test_a_cvt_window_beyond_the_iteration_limit_is_refused(window: int) -> None:
    refused(InvalidInputError, "window must be at most 1,000,000", uavcov.CVTSettings, window=window)
    refused(InvalidInputError, "window must be at most", dataclasses.replace, uavcov.CVTSettings(), window=window)


@pytest.mark.parametrize("move_step", [5e-324, 1e-300, 1e-310])
def test_a_subnormal_move_step_is_refused_before_its_sample_count_overflows(move_step: float) -> None:
    limits = Constraints(move_step=move_step, check_moves=True).resolve(HILLS)
    check = feasibility(limits, HILLS, n_threads=1)
    refused(InvalidInputError, "is over 10000 samples", check, UAVS, UAVS[None] + 1.0)


def test_a_fine_move_step_still_checks_moves() -> None:
    limits = Constraints(move_step=0.5, check_moves=True).resolve(HILLS)
    assert feasibility(limits, HILLS, n_threads=1)(UAVS, UAVS[None] + 1.0).tolist() == [True]


# ---------------------------------------------------------------------------------------------
# Subnormal settings whose derived constants underflowed: the error named the constant, not the setting


@pytest.mark.parametrize("d_max", [5e-324, 1e-323, 1.7e308])
def test_a_range_that_leaves_cao_no_first_step_is_refused_by_its_name(d_max: float) -> None:
    from uavcov.optim import cao_preset

    refused(InvalidInputError, re.escape(f"d_max = {d_max} m gives CAO no first step"), cao_preset, "plateau", d_max)
    if d_max < 1.0:
        refused(InvalidInputError, "d_max = .* gives CAO no first step", uavcov.PlanSettings, n_uavs=2, d_max=d_max)


def test_a_tiny_range_keeps_its_first_step() -> None:
    from uavcov.optim import cao_preset

    assert cao_preset("plateau", 1e-300).alpha0 == pytest.approx(2e-301)


@pytest.mark.parametrize("fov", [5e-324, 1e-323, 2e-323])
@pytest.mark.parametrize("name", ["hfov_deg", "vfov_deg"])
def test_a_field_of_view_too_narrow_for_its_sensor_is_refused_by_its_name(fov: float, name: str) -> None:
    angles = {"hfov_deg": 60.0, "vfov_deg": 45.0, name: fov}
    refused(InvalidInputError, f"{name} must be in \\(0, 180\\) degrees, got .*, too narrow", uavcov.Camera.from_fov, **angles)


def test_a_narrow_field_of_view_is_still_a_camera() -> None:
    assert uavcov.Camera.from_fov(1e-6, 45.0).hfov_deg == pytest.approx(1e-6)


# ---------------------------------------------------------------------------------------------
# A .plan's numbers reach the vehicle as 32-bit floats: 1e308 s was an endless hold, 5e-324 m/s none


@pytest.mark.parametrize("field", ["hold_s", "cruise_speed", "hover_speed"])
@pytest.mark.parametrize("value", [1e308, 3.5e38, 5e-324, 1e-40])
def test_a_plan_refuses_a_mission_item_value_float32_cannot_carry(field: str, value: float) -> None:
    refused(
        InvalidInputError,
        re.escape(f"{field} = {value} is beyond what a mission item's 32-bit float holds"),
        uavcov.PlanSettings,
        n_uavs=2,
        d_max=10.0,
        **{field: value},
    )


@pytest.mark.parametrize("hold, kept", [(0.0, 0.0), (-0.0, 0.0), (1e-30, 1e-30), (3e38, 3e38), (60, 60.0)])
def test_a_hold_float32_carries_is_kept(hold: float, kept: float) -> None:
    settings = uavcov.PlanSettings(n_uavs=2, d_max=10.0, hold_s=hold)
    assert settings.hold_s == kept and str(settings.hold_s) == str(kept)


# ---------------------------------------------------------------------------------------------
# Found by the fuzz harness's new values (scripts/fuzz_public_api.py --values "10**400;timedelta64;...")


@pytest.mark.parametrize("n", [HUGE, 10**20, 1001])
def test_check_team_refuses_a_team_beyond_the_limit_before_its_volume_overflows(n: int) -> None:
    limits = Constraints().resolve(HILLS)
    refused(InvalidInputError, "number of UAVs must be at most 1,000", limits.check_team, n, HILLS)


@pytest.mark.parametrize(
    "field, value, words",
    [
        ("longitude", HUGE, "anchor longitude must be finite and within"),
        ("latitude", -HUGE, "anchor latitude must be finite and within"),
        ("height", HUGE, "anchor height must be finite and within"),
        ("longitude", np.timedelta64(5, "s"), "anchor longitude must be a number"),
        ("height", np.timedelta64(1, "D"), "anchor height must be a number"),
    ],
)
def test_a_geo_anchor_refuses_numbers_float_cannot_hold_and_timedeltas(field: str, value: Any, words: str) -> None:
    refused(InvalidInputError, words, uavcov.field.GeoAnchor, **{"longitude": 5.0, "latitude": 45.0, "height": 0.0, field: value})


@pytest.mark.parametrize("c", [np.timedelta64(0), np.timedelta64(1, "s"), True, 1.0])
def test_a_candidate_index_is_an_integer_not_a_timedelta(c: Any) -> None:
    from uavcov.cover import CoverageProblem

    visibility = uavcov.Visibility(HILLS, 10.0, n_threads=1)
    problem = CoverageProblem(visibility, UAVS, n_threads=1)
    refused(InvalidTypeError, "c must be an int", problem.seen, c)
    assert problem.seen(np.int64(1)).shape == problem.seen(1).shape


@pytest.fixture(scope="module")
def mission() -> Any:
    settings = uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=2, cao=uavcov.CAOSettings(n_candidates=10))
    return uavcov.run_mission(HILLS, settings, n_threads=1, rng=0)


@pytest.mark.parametrize("max_polygons", [HUGE, 10**9, 2**64])
def test_a_figure_refuses_a_polygon_count_beyond_the_limit(mission: Any, max_polygons: int) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_cvt

    refused(InvalidInputError, "max_polygons must be at most 100,000,000", plot_cvt, mission, max_polygons=max_polygons)


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"max_frames": np.timedelta64(5)}, "max_frames must be an integer >= 2"),
        ({"max_vertices": np.timedelta64(100, "s")}, "max_vertices must be an integer >= 16"),
        ({"max_frames": True}, "max_frames must be an integer >= 2"),
    ],
)
def test_a_view_counts_frames_and_vertices_in_integers(mission: Any, kwargs: dict[str, Any], words: str) -> None:
    pytest.importorskip("plotly")
    from uavcov.plotting import view

    refused(InvalidInputError, words, view, mission, **kwargs)


@pytest.mark.parametrize("configuration", [np.timedelta64(1), np.timedelta64(0, "s")])
def test_a_coverage_map_takes_an_iteration_not_a_timedelta(mission: Any, configuration: Any) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_coverage_map

    with pytest.raises(uavcov.errors.UavcovError) as caught:
        plot_coverage_map(mission, configuration=configuration)
    assert "configuration" in str(caught.value)


@pytest.mark.parametrize("trajectory", [HUGE, Fraction(HUGE), [[[HUGE, 0, 0]]]])
def test_a_trajectory_beyond_the_largest_float_is_no_trajectory(trajectory: Any) -> None:
    from uavcov.plotting._inputs import _trajectory

    refused(ResultsFormatError, "the trajectory is not numeric", _trajectory, trajectory)


@pytest.mark.parametrize(
    "obj, changes, words",
    [
        (uavcov.MissionSettings(n_uavs=2, d_max=10.0), {5: 1}, "a field name must be a string"),
        (uavcov.MissionSettings(n_uavs=2, d_max=10.0), {None: 1}, "a field name must be a string"),
        (uavcov.MissionSettings(n_uavs=2, d_max=10.0), {b"start.kind": "random"}, "a field name must be a string"),
        (uavcov.MissionSettings(n_uavs=2, d_max=10.0), [("start.kind", "random")], "changes must be a mapping"),
        (uavcov.MissionSettings, {"n_uavs": 3}, "changes a settings dataclass"),
        ({"n_uavs": 2}, {"n_uavs": 3}, "changes a settings dataclass"),
    ],
)
def test_nested_replace_takes_a_dataclass_and_names_that_are_strings(obj: Any, changes: Any, words: str) -> None:
    from uavcov.settings import nested_replace

    refused(InvalidTypeError, words, nested_replace, obj, changes)


def test_nested_replace_still_reaches_nested_fields() -> None:
    from uavcov.settings import nested_replace

    changed = nested_replace(uavcov.MissionSettings(n_uavs=2, d_max=10.0), {"start.kind": "random", "cao__history": 3})
    assert (changed.start.kind, changed.cao.history) == ("random", 3)


@pytest.mark.parametrize("pixels", [HUGE, 2**64, 1_000_001])
@pytest.mark.parametrize("name", ["image_width_px", "image_height_px"])
def test_a_camera_of_more_pixels_than_any_is_refused(pixels: int, name: str) -> None:
    sizes = {"image_width_px": 4000, "image_height_px": 3000, name: pixels}
    refused(InvalidInputError, f"{name} must be at most 1,000,000 pixels", uavcov.Camera, 13.2, 8.8, 8.8, **sizes)
    refused(InvalidInputError, f"{name} must be at most 1,000,000 pixels", uavcov.Camera.from_fov, 60.0, 45.0, **sizes)


def test_a_camera_of_a_million_pixels_a_side_is_one() -> None:
    camera = uavcov.Camera(13.2, 8.8, 8.8, 1_000_000, 1_000_000)
    assert camera.gsd_m(10.0) == pytest.approx(10.0 * 13.2 / (8.8 * 1_000_000))


@pytest.mark.parametrize("max_sweeps", [HUGE, 2**64, 10**6 + 1])
def test_closest_admissible_refuses_sweeps_beyond_the_iteration_limit(max_sweeps: int) -> None:
    from uavcov.limits import closest_admissible

    limits = Constraints().resolve(HILLS)
    refused(InvalidInputError, "max_sweeps must be at most 1,000,000", closest_admissible, limits, HILLS, UAVS, max_sweeps=max_sweeps)


# ---------------------------------------------------------------------------------------------
# Subnormal sizes and rates (the fuzz harness's 5e-324): counts of cells or frames that overflowed


@pytest.mark.parametrize("step", [5e-324, 1e-310, 1e-300])
def test_a_subnormal_cell_is_refused_before_its_count_overflows(step: float) -> None:
    from uavcov.structures import girder_bridge, height_field_violation
    from uavcov.terrain import approximation_error, buildings_scene, sample_prior

    refused(InvalidInputError, "size \\(24 m\\) in cells of .* m is .* cells, more than 10,000", buildings_scene, spacing=step, rng=0)
    refused(
        InvalidInputError,
        "resolution \\(.* m\\) in cells of .* m is .* cells, more than 10,000",
        height_field_violation,
        girder_bridge(rng=0),
        resolution=step,
    )
    approx = uavcov.terrain.approximate_surface(sample_prior(HILLS, 30, rng=0).points)
    refused(
        InvalidInputError,
        "resolution \\(.* m\\) in cells of .* m is .* cells, more than 10,000",
        approximation_error,
        HILLS,
        approx,
        resolution=step,
    )


@pytest.mark.parametrize("dpi", [5e-324, 1e-300, 0.5])
def test_a_figure_refuses_a_dpi_below_one(mission: Any, dpi: float) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import plot_coverage_curves, plot_coverage_map

    refused(InvalidInputError, "dpi must be at least 1", plot_coverage_map, mission, dpi=dpi)
    refused(InvalidInputError, "dpi must be at least 1", plot_coverage_curves, [mission], dpi=dpi)


@pytest.mark.parametrize("fps", [5e-324, 1e-300, 0.0009])
def test_an_animation_refuses_an_fps_whose_frames_never_end(mission: Any, tmp_path: Path, fps: float) -> None:
    pytest.importorskip("matplotlib")
    from uavcov.plotting import animate_mission

    refused(InvalidInputError, "fps must be at least 0.001", animate_mission, mission, tmp_path / "run.gif", fps=fps)
    assert list(tmp_path.iterdir()) == []
