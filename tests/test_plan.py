"""uavcov plan: from a geo-referenced DEM to flight plans, and every output read back.

References are independent of the code under test: pyproj's own transformer on pixel centres
computed by hand from the GeoTIFF's transform, rasterio reading the files back, and a fresh
``Visibility`` for the seen mask. DEMs are small (24 x 20 nodes every 30 m), teams of 3 and a
few CAO iterations, so the whole file runs in seconds.
"""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import numpy as np
import pyproj
import pytest
import rasterio
from rasterio.transform import Affine

from uavcov import Camera, FlightPlan, PlanSettings, Sensor, Visibility, plan, read_dem, sample_dem, write_plan
from uavcov.cli import EXIT_BAD_INPUT, EXIT_OK, main
from uavcov.errors import InfeasibleError, InvalidInputError
from uavcov.field import MAV_FRAME_GLOBAL_RELATIVE_ALT, bbox_area, read_area
from uavcov.field._area import points_in_rings
from uavcov.field._gis_files import COVERAGE_NODATA, read_coverage_geotiff, read_plan_geojson, read_plan_kml
from uavcov.field._plan_tables import read_positions_csv
from uavcov.field._qgc import MAV_CMD_NAV_LOITER_TIME, MAV_CMD_NAV_TAKEOFF, read_qgc_plan
from uavcov.optim import cao_preset
from uavcov.terrain import dem_from_array, read_mesh_dem

UTM33 = "EPSG:32633"
EAST, NORTH = 500_000.0, 5_000_000.0  # UTM zone 33N: easting 500 km lies on the central meridian, 15 deg E
ROWS, COLS, CELL = 20, 24, 30.0


def heights() -> np.ndarray:
    """Raster-order heights (row 0 north): two hills on a slope, 400-520 m, with two nodata holes."""
    rows, cols = np.mgrid[0:ROWS, 0:COLS].astype(np.float64)
    x, y = cols * CELL, (ROWS - 1 - rows) * CELL
    z = 400.0 + 0.05 * x
    z += 80.0 * np.exp(-((x - 200.0) ** 2 + (y - 300.0) ** 2) / (2 * 90.0**2))
    z += 60.0 * np.exp(-((x - 520.0) ** 2 + (y - 150.0) ** 2) / (2 * 70.0**2))
    z[3:5, 15:17] = -9999.0
    z[12, 4] = -9999.0
    return z


def write_geotiff(path: Path, z: np.ndarray, west: float, north: float, crs: str | None = UTM33) -> Path:
    profile = {
        "driver": "GTiff",
        "height": z.shape[0],
        "width": z.shape[1],
        "count": 1,
        "dtype": "float32",
        "transform": Affine(CELL, 0.0, west, 0.0, -CELL, north),
        "nodata": -9999.0,
    }
    if crs is not None:
        profile["crs"] = crs
    with rasterio.open(path, "w", **profile) as dataset:
        dataset.write(z.astype(np.float32), 1)
    return path


@pytest.fixture(scope="module")
def utm_tif(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_geotiff(tmp_path_factory.mktemp("dem") / "utm.tif", heights(), EAST, NORTH + ROWS * CELL)


SETTINGS = PlanSettings(n_uavs=3, d_max=150.0, h_min=10.0, h_max=60.0, d_safe=5.0, iterations=20)


@pytest.fixture(scope="module")
def utm_plan(utm_tif: Path) -> FlightPlan:
    return plan(read_dem(utm_tif), SETTINGS, rng=0, n_threads=1)


def test_a_plan_its_dem_and_its_mission_print_as_one_line_summaries(utm_plan: FlightPlan):
    # The default dataclass reprs ran to thousands of characters (the CRS's WKT, every array).
    text = repr(utm_plan)
    assert text == (
        f"FlightPlan(3 UAVs over {utm_plan.dem.crs_name}: coverage {utm_plan.coverage:.3f} of "
        f"{utm_plan.area_m2 / 1e6:.3f} km^2 (start {utm_plan.initial_coverage:.3f}), seed 0)"
    )
    assert "UTM zone 33N" in text
    dem = repr(utm_plan.dem)
    assert dem.startswith("GeoDem('") and "utm.tif" in dem and "UTM zone 33N" in dem and repr(utm_plan.dem.terrain) in dem
    assert "PROJCRS" not in dem and len(dem) < 400
    mission = repr(utm_plan.mission)
    assert mission.startswith("MissionResult(3 UAVs, d_max 150 m, cvt start, cao 20 iterations: coverage ")
    assert f"best {utm_plan.mission.best_coverage:.3f} at iteration {utm_plan.mission.best_iteration}" in mission
    assert "\n" not in text + dem + mission


# ---------------------------------------------------------------------------------------------
# Coordinates


def test_utm_pixel_centres_go_to_wgs84_as_pyproj_takes_them(utm_tif: Path):
    dem = read_dem(utm_tif)
    rows = np.array([0, 0, ROWS - 1, 7])
    cols = np.array([0, COLS - 1, 0, 11])
    # pixel centres by hand from the transform (row 0 at the top)
    easting = EAST + (cols + 0.5) * CELL
    northing = NORTH + ROWS * CELL - (rows + 0.5) * CELL
    grid = dem.terrain.grid
    i, j = dem.raster.node_of_pixel(rows, cols)
    local = np.column_stack([grid.origin[0] + j * grid.spacing[0], grid.origin[1] + i * grid.spacing[1], np.zeros(4)])
    np.testing.assert_allclose(dem.to_crs(local)[:, :2], np.column_stack([easting, northing]), rtol=0, atol=1e-9)
    lon, lat = pyproj.Transformer.from_crs(UTM33, "EPSG:4326", always_xy=True).transform(easting, northing)
    np.testing.assert_allclose(dem.to_wgs84(local)[:, :2], np.column_stack([lon, lat]), rtol=0, atol=1e-12)
    # the central meridian of zone 33N, independent of any transformer
    on_meridian = dem.to_wgs84(dem.from_crs([[500_000.0, 5_000_000.0, 0.0]]))[0]
    assert on_meridian[0] == pytest.approx(15.0, abs=1e-12)


@pytest.mark.parametrize("which", ["utm", "geographic"])
def test_local_to_wgs84_to_local_within_a_millimetre(utm_tif: Path, which: str):
    dem = read_dem(utm_tif) if which == "utm" else sample_dem((0, 30, 0, 30))
    high = dem.terrain.bounds[1]
    local = np.random.default_rng(3).uniform([0, 0, 0], high + [0, 0, 100.0], size=(200, 3))
    back = dem.from_wgs84(dem.to_wgs84(local))
    assert np.abs(back - local).max() < 1e-3
    assert np.abs(dem.from_crs(dem.to_crs(local)) - local).max() < 1e-6


def test_the_sample_states_wgs84_and_an_unknown_vertical_datum():
    dem = sample_dem((0, 10, 0, 12))
    assert dem.crs == "EPSG:4326" and dem.is_wgs84 and dem.geographic
    assert "unknown vertical datum" in dem.vertical_datum
    # the south-west node: the file's west and south edges plus half a 3 arc-second cell
    from matplotlib import cbook

    with np.load(cbook.get_sample_data("jacksboro_fault_dem.npz", asfileobj=False)) as data:
        west = float(data["xmin"]) + 0.5 * float(data["dx"])
        south = min(float(data["ymin"]), float(data["ymax"])) + 0.5 * float(data["dy"])
        corner = float(np.asarray(data["elevation"])[::-1][0, 0])
    node = dem.to_wgs84([[0.0, 0.0, dem.terrain.grid.z[0, 0]]])[0]
    np.testing.assert_allclose(node, [west, south, corner], rtol=0, atol=1e-9)


def test_a_compound_crs_names_its_vertical_datum():
    z = np.full((4, 5), 300.0)
    dem = dem_from_array(z, (30.0, 0.0, EAST, 0.0, -30.0, NORTH), "EPSG:32633+5773")
    assert "EGM96" in dem.vertical_datum and "5773" in dem.vertical_datum


# ---------------------------------------------------------------------------------------------
# Precision: a UTM DEM plans as the same heights at the origin


def test_a_utm_geotiff_plans_as_the_same_heights_at_the_origin(tmp_path: Path, utm_plan: FlightPlan):
    at_origin = write_geotiff(tmp_path / "origin.tif", heights(), 0.0, ROWS * CELL)
    near = plan(read_dem(at_origin), SETTINGS, rng=0, n_threads=1)
    assert utm_plan.coverage == near.coverage
    np.testing.assert_array_equal(utm_plan.seen, near.seen)
    np.testing.assert_allclose(utm_plan.positions_local, near.positions_local, rtol=0, atol=1e-9)
    offset = utm_plan.positions_crs[:, :2] - near.positions_crs[:, :2]
    np.testing.assert_allclose(offset, np.tile([EAST, NORTH], (3, 1)), rtol=0, atol=1e-6)
    assert utm_plan.dem.nodata_cells == 5


# ---------------------------------------------------------------------------------------------
# Outputs, read back


def test_outputs_round_trip(tmp_path: Path, utm_tif: Path, utm_plan: FlightPlan):
    fp = utm_plan
    written = write_plan(fp, tmp_path / "out")
    names = {p.name for p in written}
    assert {"uav_01.plan", "uav_03.plan", "positions.csv", "waypoints.csv", "plan.geojson", "plan.kml", "coverage.tif"} <= names
    assert {"report.md", "report.png", "plan.json"} <= names
    assert not list((tmp_path / "out").glob(".*tmp*")), "a temporary file was left behind"

    for k in range(3):
        document = read_qgc_plan(tmp_path / "out" / f"uav_{k + 1:02d}.plan")
        lat_home, lon_home, alt_home = document["home"]
        assert (lon_home, lat_home, alt_home) == tuple(fp.takeoff_wgs84)
        items = document["items"]
        assert items[0]["command"] == MAV_CMD_NAV_TAKEOFF and items[-1]["command"] == MAV_CMD_NAV_LOITER_TIME
        assert {i["frame"] for i in items} == {MAV_FRAME_GLOBAL_RELATIVE_ALT}
        hold = items[-1]
        assert (hold["lon"], hold["lat"]) == tuple(fp.positions_wgs84[k])
        assert hold["alt"] == pytest.approx(fp.altitude_home[k], abs=1e-9)
        assert hold["alt"] + alt_home == pytest.approx(fp.altitude_amsl[k], abs=1e-9)
        # the relative altitude is the local height difference above the take-off ground
        assert hold["alt"] == pytest.approx(fp.positions_local[k, 2] - fp.takeoff_local[2], abs=1e-9)
        assert items[1]["alt"] >= hold["alt"]

    geojson = read_plan_geojson(tmp_path / "out" / "plan.geojson")
    kml = read_plan_kml(tmp_path / "out" / "plan.kml")
    expected = np.column_stack([fp.positions_wgs84, fp.altitude_amsl])
    np.testing.assert_array_equal(geojson["positions"], expected)
    np.testing.assert_array_equal(kml, expected)
    assert len(geojson["footprints"]) == 3 and len(geojson["area"]) == 1
    csv_columns = read_positions_csv(tmp_path / "out" / "positions.csv")
    np.testing.assert_array_equal(csv_columns["longitude"], fp.positions_wgs84[:, 0])
    np.testing.assert_array_equal(csv_columns["altitude_agl_m"], fp.altitude_agl)
    np.testing.assert_array_equal(csv_columns["x_crs"], fp.positions_crs[:, 0])

    bands, transform, crs = read_coverage_geotiff(tmp_path / "out" / "coverage.tif")
    with rasterio.open(utm_tif) as source:
        assert transform == tuple(source.transform)[:6]
        assert rasterio.crs.CRS.from_wkt(crs) == source.crs
        nodata = source.read(1, masked=True).mask
    assert bands.shape == (2, ROWS, COLS)
    # the engine's seen mask, computed afresh from the positions, cell by cell
    vis = Visibility(fp.dem.terrain, fp.settings.d_max, fp.targets)
    seen = vis.seen(fp.positions_local)
    count = sum(vis.seen(fp.positions_local[k : k + 1]).astype(int) for k in range(3))
    rows, cols = fp.target_pixels.T
    np.testing.assert_array_equal(bands[0, rows, cols], seen.astype(np.uint16))
    np.testing.assert_array_equal(bands[1, rows, cols], count)
    assert (bands[:, nodata] == COVERAGE_NODATA).all()
    assert 0 < seen.sum() < seen.size
    assert vis.coverage(fp.positions_local) == fp.coverage


def test_plans_are_admissible_deterministic_and_pickle(utm_tif: Path, utm_plan: FlightPlan):
    again = plan(read_dem(utm_tif), SETTINGS, rng=0, n_threads=1)
    np.testing.assert_array_equal(again.positions_local, utm_plan.positions_local)
    assert (utm_plan.altitude_agl >= 10.0 - 1e-9).all() and (utm_plan.altitude_agl <= 60.0 + 1e-9).all()
    gaps = np.linalg.norm(utm_plan.positions_local[:, None] - utm_plan.positions_local[None], axis=2)
    assert gaps[np.triu_indices(3, 1)].min() >= 5.0
    restored = pickle.loads(pickle.dumps(utm_plan))
    np.testing.assert_array_equal(restored.positions_wgs84, utm_plan.positions_wgs84)


# ---------------------------------------------------------------------------------------------
# Areas of interest


def _lonlat(dem, easting: np.ndarray, northing: np.ndarray) -> np.ndarray:
    lon, lat = pyproj.Transformer.from_crs(UTM33, "EPSG:4326", always_xy=True).transform(easting, northing)
    return np.column_stack([lon, lat])


def test_a_geojson_or_kml_area_restricts_targets_and_the_team(tmp_path: Path, utm_tif: Path):
    dem = read_dem(utm_tif)
    # the western 300 m x 400 m of the DEM, minus a 90 m square hole, in WGS84
    outer = _lonlat(dem, EAST + np.array([0.0, 300, 300, 0]), NORTH + np.array([100.0, 100, 500, 500]))
    hole = _lonlat(dem, EAST + np.array([120.0, 210, 210, 120]), NORTH + np.array([250.0, 250, 340, 340]))
    geometry = {"type": "Polygon", "coordinates": [[*outer.tolist(), outer[0].tolist()], [*hole.tolist(), hole[0].tolist()]]}
    (tmp_path / "area.geojson").write_text(json.dumps({"type": "Feature", "geometry": geometry, "properties": {}}))
    ring = lambda r: " ".join(f"{float(x)!r},{float(y)!r},0" for x, y in [*r, r[0]])  # noqa: E731
    (tmp_path / "area.kml").write_text(
        '<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Placemark><Polygon>'
        f"<outerBoundaryIs><LinearRing><coordinates>{ring(outer)}</coordinates></LinearRing></outerBoundaryIs>"
        f"<innerBoundaryIs><LinearRing><coordinates>{ring(hole)}</coordinates></LinearRing></innerBoundaryIs>"
        "</Polygon></Placemark></kml>"
    )
    from_geojson = plan(dem, SETTINGS, area=read_area(tmp_path / "area.geojson"), rng=1, n_threads=1)
    from_kml = plan(dem, SETTINGS, area=read_area(tmp_path / "area.kml"), rng=1, n_threads=1)
    np.testing.assert_array_equal(from_geojson.targets.points, from_kml.targets.points)
    np.testing.assert_array_equal(from_geojson.positions_local, from_kml.positions_local)
    # targets: pixel centres strictly inside the rectangle and outside the hole (edges are 15 m
    # from the nearest centre, so the straight-in-UTM and straight-in-local rings agree)
    crs_xy = dem.to_crs(from_geojson.targets.points)[:, :2] - [EAST, NORTH]
    in_outer = (crs_xy[:, 0] < 300) & (crs_xy[:, 1] > 100) & (crs_xy[:, 1] < 500)
    in_hole = (crs_xy[:, 0] > 120) & (crs_xy[:, 0] < 210) & (crs_xy[:, 1] > 250) & (crs_xy[:, 1] < 340)
    assert in_outer.all() and not in_hole.any()
    assert len(from_geojson.targets) == 10 * 14 - 9 - 1  # 10 columns (x 15..285) x 14 rows (y 105..495), the hole's 9, one nodata node
    positions = from_geojson.positions_crs[:, :2] - [EAST, NORTH]
    assert (positions[:, 0] <= 285 + 1e-6).all() and (positions[:, 1] >= 115 - 1e-6).all() and (positions[:, 1] <= 475 + 1e-6).all()


def test_points_in_rings_by_hand():
    square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
    hole = np.array([[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]])
    points = [[0.5, 0.5], [2.0, 2.0], [3.5, 2.0], [5.0, 2.0], [-1.0, 2.0]]
    assert points_in_rings(points, [square, hole]).tolist() == [True, False, True, False, False]


def test_a_bbox_in_the_dem_crs_and_a_sparse_prior(utm_tif: Path):
    dem = read_dem(utm_tif)
    area = bbox_area(EAST + 100, NORTH + 100, EAST + 500, NORTH + 500, frame="dem")
    result = plan(dem, PlanSettings(n_uavs=3, d_max=150.0, prior=8, iterations=5), area=area, rng=2, n_threads=1)
    crs_xy = dem.to_crs(result.targets.points)[:, :2] - [EAST, NORTH]
    assert (crs_xy >= 100).all() and (crs_xy <= 500).all()
    assert result.prior_points.shape[0] >= 8 + 3  # the random nodes and the area's hull


def test_a_nadir_camera_footprint_over_flat_ground():
    dem = dem_from_array(np.full((21, 21), 250.0), (10.0, 0.0, EAST, 0.0, -10.0, NORTH), UTM33)
    camera = Camera.from_fov(60.0, 40.0)
    settings = PlanSettings(n_uavs=1, d_max=200.0, h_min=40.0, h_max=50.0, d_safe=0.0, iterations=3, sensor=Sensor(200.0, camera=camera))
    result = plan(dem, settings, rng=0, n_threads=1)
    outline = result.footprints_local()[0] - result.positions_local[0, :2]
    h = result.altitude_agl[0]
    half = [h * np.tan(np.radians(30.0)), h * np.tan(np.radians(20.0))]
    np.testing.assert_allclose(np.abs(outline), np.tile(half, (4, 1)), rtol=1e-9)


# ---------------------------------------------------------------------------------------------
# Bad input: clear errors, nothing written


def test_a_dem_without_crs_is_refused_unless_given_one(tmp_path: Path):
    path = write_geotiff(tmp_path / "nocrs.tif", heights(), EAST, NORTH + ROWS * CELL, crs=None)
    with pytest.raises(InvalidInputError, match="states no CRS"):
        read_dem(path)
    assert read_dem(path, crs=UTM33).crs_name.startswith("WGS 84 / UTM zone 33N")


def test_bad_input_raises_clear_errors(tmp_path: Path, utm_tif: Path):
    dem = read_dem(utm_tif)
    with pytest.raises(InvalidInputError, match="outside the DEM"):
        plan(dem, SETTINGS, area=bbox_area(10.0, 10.0, 10.1, 10.1))
    with pytest.raises(InfeasibleError, match="cannot fit"):
        plan(
            dem,
            PlanSettings(n_uavs=50, d_max=100.0, h_min=10, h_max=11, d_safe=60.0),
            area=bbox_area(EAST, NORTH, EAST + 100, NORTH + 100, frame="dem"),
        )
    with pytest.raises(InvalidInputError, match="take-off"):
        plan(dem, PlanSettings(n_uavs=2, d_max=100.0, takeoff=(16.0, 45.0)))
    everywhere = write_geotiff(tmp_path / "nodata.tif", np.full((5, 5), -9999.0), EAST, NORTH)
    with pytest.raises(InvalidInputError, match="no grid cell with four valid corners"):
        read_dem(everywhere)
    fake = tmp_path / "fake.tif"
    fake.write_text("not a raster")
    with pytest.raises(InvalidInputError, match="cannot read"):
        read_dem(fake)


@pytest.mark.parametrize(
    "case, message",
    [
        ("nocrs", "states no CRS"),
        ("outside", "outside the DEM"),
        ("crowded", "cannot fit"),
        ("nodata", "four valid corners"),
        ("fake", "cannot read"),
        ("numpy", "dem_from_array"),
        ("both", "not both"),
        ("heading without a camera", "need a camera"),
        ("pitch out of range", "pitch_range"),
        ("camera pointing up", "point up"),
    ],
)
def test_the_cli_answers_bad_input_with_one_line_and_writes_nothing(tmp_path: Path, capsys, utm_tif: Path, case: str, message: str):
    out = tmp_path / "out"
    dem = str(utm_tif)
    extra: list[str] = []
    if case == "nocrs":
        dem = str(write_geotiff(tmp_path / "nocrs.tif", heights(), EAST, NORTH, crs=None))
    elif case == "outside":
        extra = ["--bbox", "10,10,10.1,10.1"]
    elif case == "crowded":
        extra = [
            "--uavs",
            "50",
            "--separation",
            "60",
            "--h-max",
            "11",
            "--coords",
            "dem",
            "--bbox",
            f"{EAST},{NORTH},{EAST + 100},{NORTH + 100}",
        ]
    elif case == "nodata":
        dem = str(write_geotiff(tmp_path / "nodata.tif", np.full((5, 5), -9999.0), EAST, NORTH))
    elif case == "fake":
        (tmp_path / "fake.tif").write_text("not a raster")
        dem = str(tmp_path / "fake.tif")
    elif case == "numpy":  # a height grid saved by numpy: what to do with it instead
        np.save(tmp_path / "heights.npy", heights())
        dem = str(tmp_path / "heights.npy")
    elif case == "both":
        extra = ["--sample"]
    elif case == "heading without a camera":
        extra = ["--free-heading"]
    elif case == "pitch out of range":
        extra = ["--camera", "60,45", "--pitch-range=-120,0"]
    elif case == "camera pointing up":
        extra = ["--camera", "60,45", "--attitude=0,30"]
    code = main(["plan", dem, "--uavs", "3", "--d-max", "100", "--iterations", "2", "--out", str(out), *extra])
    err = capsys.readouterr().err
    assert code == EXIT_BAD_INPUT
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("uavcov plan: error: ") and message in lines[0], err
    assert not out.exists()


def test_a_failing_writer_leaves_the_folder_as_it_was(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, utm_plan: FlightPlan):
    from uavcov.field import _outputs as plan_outputs

    out = tmp_path / "out"
    write_plan(utm_plan, out)
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    def broken(fp: FlightPlan) -> bytes:
        raise InvalidInputError("the map cannot be drawn")

    monkeypatch.setattr(plan_outputs, "_map_png", broken)
    with pytest.raises(InvalidInputError):
        write_plan(utm_plan, out)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


def test_the_cli_plans_on_the_bundled_sample(tmp_path: Path, capsys):
    out = tmp_path / "sample"
    args = ["plan", "--sample", "--window", "0,20,0,20", "--uavs", "3", "--d-max", "500", "--h-min", "30", "--h-max", "120"]
    code = main([*args, "--separation", "20", "--iterations", "10", "--seed", "0", "--out", str(out)])
    printed = capsys.readouterr().out
    assert code == EXIT_OK and "WGS 84 (EPSG:4326)" in printed
    document = json.loads((out / "plan.json").read_text())
    assert document["dem"]["crs"] == "WGS 84 (EPSG:4326)" and "unknown vertical datum" in document["dem"]["vertical_datum"]
    assert 0.0 < document["results"]["coverage"] <= 1.0
    assert (out / "report.png").read_bytes().startswith(b"\x89PNG")


def test_a_mesh_with_its_crs_plans_without_a_coverage_raster(tmp_path: Path):
    trimesh = pytest.importorskip("trimesh")
    x, y = np.meshgrid(np.arange(0.0, 300.0, 30.0), np.arange(0.0, 300.0, 30.0))
    vertices = np.column_stack([x.ravel() + EAST, y.ravel() + NORTH, 400.0 + 20.0 * np.sin(x.ravel() / 60.0)])
    corners = np.arange(100).reshape(10, 10)[:-1, :-1].ravel()
    faces = np.concatenate([np.column_stack([corners, corners + 1, corners + 11]), np.column_stack([corners, corners + 11, corners + 10])])
    trimesh.Trimesh(vertices, faces, process=False).export(tmp_path / "ground.ply")
    with pytest.raises(InvalidInputError, match="projected CRS in metres"):
        read_mesh_dem(tmp_path / "ground.ply", "EPSG:4326")
    result = plan(read_mesh_dem(tmp_path / "ground.ply", UTM33), PlanSettings(n_uavs=2, d_max=120.0, iterations=3), rng=0, n_threads=1)
    names = {p.name for p in write_plan(result, tmp_path / "out")}
    assert "coverage.tif" not in names and {"uav_01.plan", "plan.geojson"} <= names
    inside = (result.positions_crs[:, :2] >= [EAST, NORTH]) & (result.positions_crs[:, :2] <= [EAST + 270, NORTH + 270])
    assert inside.all()


# ---------------------------------------------------------------------------------------------
# Cameras: headings from true north, the gimbal's pitch, in every output


def test_a_camera_plan_carries_true_headings_and_gimbal_pitch(tmp_path: Path):
    pyproj = pytest.importorskip("pyproj")
    from uavcov import Gimbal
    from uavcov.field import MAV_CMD_DO_MOUNT_CONTROL

    # 300 km east of the central meridian (about 18.8 deg E at 45 deg N): grid north is not true north
    west, north = EAST + 300_000.0, NORTH
    dem = dem_from_array(np.where(heights() < 0, 450.0, heights()), (CELL, 0.0, west, 0.0, -CELL, north), UTM33)
    camera = Sensor(150.0, camera=Camera.from_fov(60.0, 45.0), max_incidence_deg=75.0, good_gsd_m=0.02)
    settings = PlanSettings(
        n_uavs=3,
        d_max=150.0,
        h_min=20.0,
        h_max=80.0,
        d_safe=5.0,
        iterations=20,
        sensor=camera,
        attitude=(30.0, -60.0),
        gimbal=Gimbal(free_yaw=True, pitch_range=(-90.0, -40.0)),
        footprint_start=True,
    )
    fp = plan(dem, settings, rng=1, n_threads=1)
    assert fp.attitudes is not None and fp.attitudes_local is not None
    np.testing.assert_array_equal(fp.attitudes_local, fp.mission.best_attitudes)
    np.testing.assert_array_equal(fp.attitudes[:, 1], fp.attitudes_local[:, 1])
    # the reference: pyproj's geodesic azimuth from each UAV to a point 1 m ahead along its grid heading
    to_wgs84 = pyproj.Transformer.from_crs(UTM33, "EPSG:4326", always_xy=True)
    geod = pyproj.Geod(ellps="WGS84")
    for k in range(3):
        x, y = fp.positions_crs[k, :2]
        yaw = np.radians(fp.attitudes_local[k, 0])
        lon0, lat0 = to_wgs84.transform(x, y)
        lon1, lat1 = to_wgs84.transform(x + np.sin(yaw), y + np.cos(yaw))
        azimuth = geod.inv(lon0, lat0, lon1, lat1)[0] % 360.0
        assert abs((fp.attitudes[k, 0] - azimuth + 180.0) % 360.0 - 180.0) < 1e-3
        convergence = (fp.attitudes[k, 0] - fp.attitudes_local[k, 0] + 180.0) % 360.0 - 180.0
        assert 2.0 < abs(convergence) < 3.0  # about (18.8 - 15) sin(45 deg) = 2.7 deg
    # the coverage is what the cameras see, posed as the plan says
    vis = Visibility(dem.terrain, 150.0, fp.targets)
    poses = np.column_stack([fp.positions_local, fp.attitudes_local])
    np.testing.assert_array_equal(fp.seen, vis.seen(poses, sensors=[camera] * 3))
    assert fp.coverage == vis.coverage(poses, sensors=[camera] * 3)
    # incidence and quality on the plan's targets are the whole grid's (the DEM's node normals)
    whole = Visibility(dem.terrain, 150.0)
    inside = np.isin(whole.targets.points.view("f8,f8,f8"), fp.targets.points.view("f8,f8,f8")).ravel()
    np.testing.assert_array_equal(fp.quality, whole.quality(poses, sensors=[camera] * 3)[inside])
    assert 0.0 < fp.quality.max() <= 1.0 and (fp.quality[~fp.seen] == 0.0).all()
    # and every output reads back the same angles
    write_plan(fp, tmp_path / "out")
    for k in range(3):
        items = read_qgc_plan(tmp_path / "out" / f"uav_{k + 1:02d}.plan")["items"]
        position = next(i for i in items if i["command"] == 16 and i["params"][3] is not None)
        mount = next(i for i in items if i["command"] == MAV_CMD_DO_MOUNT_CONTROL)
        assert position["params"][3] == fp.attitudes[k, 0] and mount["params"][0] == fp.attitudes[k, 1]
        assert items.index(mount) == len(items) - 2  # the gimbal is set before the hold
    columns = read_positions_csv(tmp_path / "out" / "positions.csv")
    np.testing.assert_array_equal(np.column_stack([columns["heading_deg"], columns["pitch_deg"]]), fp.attitudes)
    band, transform, _ = read_coverage_geotiff(tmp_path / "out" / "quality.tif")
    rows, cols = fp.target_pixels.T
    np.testing.assert_array_equal(band[0, rows, cols], fp.quality.astype(np.float32))
    outside = np.ones(band.shape[1:], dtype=bool)
    outside[rows, cols] = False
    assert np.isnan(band[0][outside]).all() and transform == dem.raster.transform
    document = json.loads((tmp_path / "out" / "plan.geojson").read_text())
    points = [f["properties"] for f in document["features"] if f["properties"]["kind"] == "position"]
    assert [(p["heading_deg"], p["pitch_deg"]) for p in points] == [tuple(a) for a in fp.attitudes.tolist()]


def test_a_mixed_team_plans_with_each_uavs_sensor(tmp_path: Path, utm_tif: Path):
    team = (Sensor(150.0, camera=Camera.from_fov(84.0, 62.0)), Sensor(100.0), Sensor(120.0, camera=Camera.from_fov(60.0, 45.0)))
    settings = PlanSettings(n_uavs=3, d_max=150.0, h_min=20.0, h_max=80.0, d_safe=5.0, iterations=10, sensor=team, attitude=(0.0, -80.0))
    fp = plan(read_dem(utm_tif), settings, rng=0, n_threads=1)
    poses = np.column_stack([fp.positions_local, fp.attitudes_local])
    vis = Visibility(fp.dem.terrain, 150.0, fp.targets)
    assert fp.coverage == vis.coverage(poses, sensors=list(team))
    np.testing.assert_array_equal(fp.seen_count, sum(vis.seen(poses[k : k + 1], sensors=[team[k]]).astype(int) for k in range(3)))
    outlines = fp.footprints_local()
    assert outlines[0].shape == (4, 2) and outlines[2].shape == (4, 2) and outlines[1].shape[0] > 4  # two frusta, one range circle
    write_plan(fp, tmp_path / "out")
    document = json.loads((tmp_path / "out" / "plan.json").read_text())
    assert [r["d_max_m"] for r in document["settings"]["sensors"]] == [150.0, 100.0, 120.0]
    assert document["settings"]["sensors"][1]["camera"] is None
    # Each UAV senses to its own sensor's range, as in any mission: d_max only names the default.
    assert PlanSettings(n_uavs=3, d_max=200.0, sensor=team).mission.team_sensors() == list(team)
    with pytest.raises(InvalidInputError, match="one per UAV"):
        PlanSettings(n_uavs=2, d_max=150.0, sensor=team)


def test_plans_default_cao_is_table1_with_the_plateau_step_scaled_to_the_range():
    from uavcov.paper import _data as paper

    table1 = paper.TABLE1.mission.cao
    assert PlanSettings(n_uavs=2, d_max=800.0).mission.cao == cao_preset("plateau", 800.0)
    cao = cao_preset("plateau", 800.0)
    assert (cao.alpha0, cao.stability) == pytest.approx((5.0 * 800.0 / 25.0, 5.0))
    assert (cao.decay, cao.n_candidates, cao.history, cao.ridge) == (table1.decay, table1.n_candidates, table1.history, table1.ridge)
    plateau = paper.ABLATIONS_BY_NAME["plateau-step"]
    assert cao_preset("plateau") == paper.TABLE1.with_changes(**plateau.changes).mission.cao
    with pytest.raises(InvalidInputError):
        cao_preset("plateau", -1.0)
