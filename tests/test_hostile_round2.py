"""Hostile input, round two (issue 43, and issue 46's leaking errors and plan records): each class
fixed where it starts, tried with several inputs beyond the issue's, and every output file of a
plan read back by a strict reader."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from uavcov import Camera, PlanSettings, Sensor, Terrain, Visibility, plan, read_dem, sample_dem, write_plan
from uavcov.cli import EXIT_BAD_INPUT, EXIT_OK, main
from uavcov.engine import camera_axes
from uavcov.errors import InvalidInputError, MeshError, ResultsFolderError, ResultsFormatError, ResultsInUseError
from uavcov.field import GeoAnchor, bbox_area, check_plan_folder, read_area
from uavcov.field._geodesy import local_to_true_heading
from uavcov.records import load_mission
from uavcov.structures import load_structure
from uavcov.terrain import dem_from_array, wrap_longitude
from uavcov.terrain._meshes import load_mesh

rasterio = pytest.importorskip("rasterio")
trimesh = pytest.importorskip("trimesh")

SAMPLE = ["--sample", "--window", "0,14,0,14", "--iterations", "2", "--threads", "1"]


def cli(capsys: pytest.CaptureFixture[str], *argv: Any) -> tuple[int, str]:
    """Run the CLI with warnings shown (as a user's terminal would); (exit code, stderr)."""
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        code = main([str(a) for a in argv])
    return code, capsys.readouterr().err


def assert_one_line(code: int, err: str, *words: str) -> None:
    lines = err.strip().splitlines()
    assert code == EXIT_BAD_INPUT and len(lines) == 1 and "Traceback" not in err and "Warning" not in err, err
    for word in words:
        assert word in lines[0], err


def write_tif(path: Path, z: np.ndarray, transform: tuple[float, ...], crs: str | None, dtype: str = "float32") -> Path:
    from rasterio.transform import Affine

    profile = {"driver": "GTiff", "height": z.shape[0], "width": z.shape[1], "count": 1, "dtype": dtype, "transform": Affine(*transform)}
    if crs is not None:
        profile["crs"] = crs
    with rasterio.open(path, "w", **profile) as dataset:
        dataset.write(z.astype(dtype), 1)
    return path


def hills(rows: int = 24, cols: int = 24) -> np.ndarray:
    y, x = np.mgrid[0:rows, 0:cols]
    return 100.0 + 8.0 * np.sin(x / 4.0) * np.cos(y / 5.0)


# ---------------------------------------------------------------------------------------------
# A strict reader of every file a plan writes


def _refuse_constant(name: str) -> Any:
    raise AssertionError(f"{name} in a JSON file")


def strict_json(path: Path) -> Any:
    return json.loads(path.read_text(encoding="utf-8"), parse_constant=_refuse_constant)


def lonlats(node: Any) -> list[tuple[float, float]]:
    """Every (longitude, latitude) position of a GeoJSON geometry tree."""
    if isinstance(node, dict):
        if node.get("type") in ("Point", "LineString", "Polygon", "MultiPolygon"):
            coordinates = np.asarray(node["coordinates"], dtype=np.float64).reshape(-1, np.shape(node["coordinates"])[-1])
            return [(float(p[0]), float(p[1])) for p in coordinates]
        return [p for value in node.values() for p in lonlats(value)]
    if isinstance(node, list):
        return [p for value in node for p in lonlats(value)]
    return []


def in_range(points: list[tuple[float, float]]) -> bool:
    return bool(points) and all(-180.0 <= lon <= 180.0 and -90.0 <= lat <= 90.0 for lon, lat in points)


def read_back_strictly(folder: Path) -> dict[str, Any]:
    """Every file of a plan folder, read strictly; the parsed JSON documents by name."""
    documents: dict[str, Any] = {}
    for path in sorted(folder.iterdir()):
        assert not path.name.startswith("."), f"a temporary file was left: {path.name}"
        if path.suffix in (".json", ".plan", ".geojson"):
            documents[path.name] = strict_json(path)
        elif path.suffix == ".csv":
            with path.open(newline="", encoding="utf-8") as handle:
                rows = list(csv.DictReader(handle))
            assert rows, path.name
            for row in rows:
                for column, cell in row.items():
                    if column in ("name", "part") or cell == "":
                        continue
                    assert math.isfinite(float(cell)), f"{path.name} {column}: {cell}"
                    if column == "longitude":
                        assert -180.0 <= float(cell) <= 180.0, f"{path.name}: longitude {cell}"
                    if column == "latitude":
                        assert -90.0 <= float(cell) <= 90.0, f"{path.name}: latitude {cell}"
        elif path.suffix == ".kml":
            import xml.etree.ElementTree as ET

            root = ET.parse(path).getroot()
            tuples = [t for e in root.iter() if e.tag.endswith("coordinates") for t in (e.text or "").split()]
            points = [(float(t.split(",")[0]), float(t.split(",")[1])) for t in tuples]
            assert in_range(points), path.name
            assert all(math.isfinite(float(v)) for t in tuples for v in t.split(","))
        elif path.suffix == ".tif":
            with rasterio.open(path) as dataset:
                dataset.read()
    for name, document in documents.items():
        if name.endswith(".plan"):
            items = document["mission"]["items"]
            points = [(item["params"][5], item["params"][4]) for item in items if item["command"] != 205]
            home = document["mission"]["plannedHomePosition"]
            assert in_range([*points, (home[1], home[0])]), name
        if name.endswith(".geojson"):
            assert in_range(lonlats(document["features"])), name
    return documents


@pytest.fixture(scope="module")
def camera_plan_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("camera") / "plan"
    argv = ["plan", *SAMPLE, "--uavs", "3", "--d-max", "400", "--camera", "60,45", "--free-heading", "--seed", "0", "--out", out]
    assert main([str(a) for a in argv]) == EXIT_OK
    return out


@pytest.fixture(scope="module")
def structure_plan_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("structure") / "plan"
    argv = ["plan", "--structure", "facade", "--anchor", "7.0,46.0,500", "--uavs", "3", "--d-max", "15", "--iterations", "2"]
    assert main([*argv, "--threads", "1", "--seed", "3", "--out", str(out)]) == EXIT_OK
    return out


def test_every_file_of_a_camera_plan_reads_back_strictly_with_its_seed_and_settings(camera_plan_folder: Path):
    documents = read_back_strictly(camera_plan_folder)
    record = documents["plan.json"]
    assert record["settings"]["seed"] == 0 and record["mission_settings"]["n_uavs"] == 3
    assert record["mission_settings"]["sensor"]["camera"] is not None and record["mission_settings"]["gimbal"]["free_yaw"] is True
    assert set(record["versions"]) >= {"uavcov", "python", "numpy"}
    assert 0.0 < record["results"]["coverage"] <= 1.0
    report = (camera_plan_folder / "report.md").read_text()
    assert "seed 0" in report and "seed None" not in report and "uavcov " in report
    with (camera_plan_folder / "positions.csv").open() as handle:
        header = next(csv.reader(handle))
    assert {"heading_deg", "pitch_deg"} <= set(header)  # a camera: its columns are there


def test_every_file_of_an_omnidirectional_sample_plan_reads_back_strictly(tmp_path: Path, capsys):
    out = tmp_path / "plan"
    code, err = cli(capsys, "plan", *SAMPLE, "--uavs", "3", "--d-max", "400", "--seed", "5", "--out", out)
    assert code == EXIT_OK, err
    documents = read_back_strictly(out)
    assert documents["plan.json"]["settings"]["seed"] == 5
    with (out / "positions.csv").open() as handle:
        header = next(csv.reader(handle))
    assert "heading_deg" not in header  # no camera: no column of NaN


def test_a_structure_plan_records_what_made_it_and_reads_back_strictly(structure_plan_folder: Path):
    documents = read_back_strictly(structure_plan_folder)
    record = documents["plan.json"]
    assert record["format"] == "uavcov.structure_plan/1" and record["seed"] == 3
    assert record["settings"]["n_uavs"] == 3 and record["settings"]["d_max"] == 15.0
    assert record["command"].startswith("uavcov plan --structure facade")
    parts = record["results"]["coverage_by_part"]
    assert parts and all(0.0 <= share <= 1.0 for share in parts.values())
    assert 0.0 < record["results"]["coverage"] <= 1.0 and set(record["versions"]) >= {"uavcov", "numpy"}
    report = (structure_plan_folder / "report.md").read_text()
    assert "seed 3" in report and all(part in report for part in parts)
    with (structure_plan_folder / "parts.csv").open() as handle:
        table = {row["part"]: float(row["seen_share"]) for row in csv.DictReader(handle)}
    assert table["all"] == pytest.approx(record["results"]["coverage"], abs=1e-6)


# ---------------------------------------------------------------------------------------------
# Areas of interest: a schema check before use


MALFORMED_AREAS = {
    "coordinates a number": {"type": "Polygon", "coordinates": 5},
    "features a number": {"type": "FeatureCollection", "features": 5},
    "features an object": {"type": "FeatureCollection", "features": {"a": 1}},
    "crs a number": {"type": "Polygon", "crs": 5, "coordinates": [[[0, 0], [1, 0], [1, 1]]]},
    "crs properties a list": {"type": "Polygon", "crs": {"properties": [1]}, "coordinates": [[[0, 0], [1, 0], [1, 1]]]},
    "a ring a number": {"type": "Polygon", "coordinates": [5]},
    "a position of strings": {"type": "Polygon", "coordinates": [[["a", "b"], [1, 0], [1, 1]]]},
    "a position of one number": {"type": "Polygon", "coordinates": [[[1], [1, 0], [1, 1]]]},
    "a boolean coordinate": {"type": "Polygon", "coordinates": [[[True, 0], [1, 0], [1, 1]]]},
    "an integer beyond float": {"type": "Polygon", "coordinates": [[[10**400, 0], [1, 0], [1, 1]]]},
    "a MultiPolygon of numbers": {"type": "MultiPolygon", "coordinates": [5, 6]},
    "a geometry a number": {"type": "Feature", "geometry": 5},
    "a type that is not GeoJSON": {"type": "Circle", "coordinates": [0, 0]},
    "geometries an object": {"type": "GeometryCollection", "geometries": {"a": 1}},
}


@pytest.mark.parametrize("name", sorted(MALFORMED_AREAS))
def test_a_malformed_geojson_area_is_one_clear_error(tmp_path: Path, name: str):
    path = tmp_path / "a.geojson"
    path.write_text(json.dumps(MALFORMED_AREAS[name]))
    with pytest.raises(InvalidInputError, match=r"a\.geojson"):
        read_area(path)


@pytest.mark.parametrize(
    "text",
    [
        '{"type": "Polygon", "coordinates": ' + "[" * 100_000 + "]" * 100_000 + "}",  # RecursionError in json
        '{"type": "Polygon", "coordinates": [[[NaN, 0], [1, 0], [1, 1]]]}',
        '{"type": "Polygon", "coordinates": [[[Infinity, 0], [1, 0], [1, 1]]]}',
        '{"type": "Polygon", "coordinates": [[[1e400, 0], [1, 0], [1, 1]]]}',
        '{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": null}]}',  # no polygon
        "[1, 2, 3]",
        "<kml><Polygon><outerBoundaryIs><coordinates>1,2 3 4,5</coordinates></outerBoundaryIs></Polygon></kml>",
        "<kml><Polygon><outerBoundaryIs><coordinates>1,2 nan,4 4,5</coordinates></outerBoundaryIs></Polygon></kml>",
        "<kml>" + "<a>" * 50_000 + "</a>" * 50_000 + "</kml>",
    ],
)
def test_hostile_area_texts_are_clear_errors(tmp_path: Path, text: str):
    path = tmp_path / "area.txt"
    path.write_text(text)
    with pytest.raises(InvalidInputError, match=r"area\.txt"):
        read_area(path)


def test_collections_nested_beyond_reason_are_refused(tmp_path: Path):
    node: dict[str, Any] = {"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1]]]}
    for _ in range(200):
        node = {"type": "GeometryCollection", "geometries": [node]}
    path = tmp_path / "deep.geojson"
    path.write_text(json.dumps(node))
    with pytest.raises(InvalidInputError, match="nests"):
        read_area(path)


@pytest.mark.parametrize("name", ["coordinates a number", "features a number", "crs a number", "deep"])
def test_the_cli_answers_a_malformed_area_in_one_line(tmp_path: Path, capsys, name: str):
    path = tmp_path / "a.geojson"
    if name == "deep":
        path.write_text('{"type": "Polygon", "coordinates": ' + "[" * 100_000 + "]" * 100_000 + "}")
    else:
        path.write_text(json.dumps(MALFORMED_AREAS[name]))
    code, err = cli(capsys, "plan", *SAMPLE, "--uavs", "3", "--d-max", "400", "--aoi", path, "--out", tmp_path / "o")
    assert_one_line(code, err, "a.geojson")
    assert not (tmp_path / "o").exists()


# ---------------------------------------------------------------------------------------------
# Coordinates and transforms within their domain; longitudes wrapped where formats need it


@pytest.mark.parametrize("west, north", [(2e7, 5e6), (-2e7, 5e6), (5e5, 2.5e7), (1e9, 5e6)])
def test_a_projected_dem_outside_its_crs_domain_is_refused(tmp_path: Path, west: float, north: float):
    path = write_tif(tmp_path / "far.tif", hills(), (10.0, 0.0, west, 0.0, -10.0, north), "EPSG:32633")
    with pytest.raises(InvalidInputError, match="outside the domain of its CRS"):
        read_dem(path)


def test_the_cli_refuses_the_issues_utm_dem_at_easting_2e7(tmp_path: Path, capsys):
    path = write_tif(tmp_path / "far.tif", hills(), (10.0, 0.0, 2e7, 0.0, -10.0, 5e6), "EPSG:32633")
    code, err = cli(capsys, "plan", path, "--uavs", "3", "--d-max", "100", "--iterations", "2", "--out", tmp_path / "o")
    assert_one_line(code, err, "outside the domain")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    "transform",
    [
        (0.001, 0.0, 1e6, 0.0, -0.001, 45.01),  # the issue's
        (0.001, 0.0, -400.0, 0.0, -0.001, 45.01),
        (1.0, 0.0, -180.0, 0.0, -1.0, 45.0),  # 400 columns of a degree: wider than the Earth
        (0.001, 0.0, 10.0, 0.0, -0.001, 95.0),  # beyond the pole
    ],
)
def test_a_geographic_dem_off_the_earth_is_refused(transform: tuple[float, ...]):
    with pytest.raises(InvalidInputError, match=r"longitudes|latitudes"):
        dem_from_array(np.ones((5, 400)), transform, "EPSG:4326")


def test_wrap_longitude_is_exact_in_range_and_wraps_outside():
    inside = np.array([-180.0, -84.123456789012345, 0.0, 179.99999999999997, 180.0])
    assert np.array_equal(wrap_longitude(inside), inside)
    np.testing.assert_allclose(wrap_longitude([180.006, 359.5, -190.0, 540.25, 1e6]), [-179.994, -0.5, 170.0, -179.75, -80.0], atol=1e-9)


def test_a_plan_across_the_antimeridian_writes_longitudes_within_180(tmp_path: Path, capsys):
    path = write_tif(tmp_path / "dateline.tif", hills(), (0.022 / 24, 0.0, 179.988, 0.0, -0.0007, 45.01), "EPSG:4326")
    out = tmp_path / "o"
    code, err = cli(capsys, "plan", path, "--uavs", "4", "--d-max", "300", "--iterations", "3", "--threads", "1", "--out", out)
    assert code == EXIT_OK, err
    documents = read_back_strictly(out)
    positions = [f for f in documents["plan.geojson"]["features"] if f["properties"]["kind"] == "position"]
    assert len(positions) == 4
    dem = read_dem(path)
    # the take-off given west of the antimeridian lands on the DEM east of it (180.005 = -179.995)
    settings = PlanSettings(n_uavs=2, d_max=300.0, iterations=0, takeoff=(-179.995, 45.0))
    flight = plan(dem, settings, rng=0, n_threads=1)
    assert flight.takeoff_wgs84[0] == pytest.approx(-179.995, abs=1e-3)
    assert np.all(np.abs(flight.positions_wgs84[:, 0]) <= 180.0)


def test_to_wgs84_refuses_points_that_have_no_longitude(tmp_path: Path):
    dem = read_dem(write_tif(tmp_path / "utm.tif", hills(), (10.0, 0.0, 5e5, 0.0, -10.0, 5e6), "EPSG:32633"))
    with pytest.raises(InvalidInputError, match="outside the domain"):
        dem.to_wgs84([[3e7, 0.0, 0.0]])


@pytest.mark.parametrize("d_max", ["1e300", "1e6", "1.5e5"])
def test_a_sensing_range_beyond_reason_is_one_line(tmp_path: Path, capsys, d_max: str):
    code, err = cli(capsys, "plan", *SAMPLE, "--uavs", "3", "--d-max", d_max, "--out", tmp_path / "o")
    assert_one_line(code, err, "sensing range")
    with pytest.raises(InvalidInputError, match="sensing range"):
        PlanSettings(n_uavs=2, d_max=200.0, sensor=(Sensor(200.0), Sensor(float(d_max))))


def test_strict_writers_refuse_what_json_and_csv_cannot_hold():
    from uavcov.field._plan_tables import _csv
    from uavcov.field._strict_json import json_bytes

    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(InvalidInputError, match="not finite"):
            json_bytes({"a": [1.0, bad]})
    with pytest.raises(InvalidInputError, match="infinite"):
        _csv([[1, math.inf]], ("uav", "x"))
    assert _csv([[1, math.nan, 2.0], [2, 1.5, math.nan]], ("uav", "a", "b")) == b"uav,a,b\n1,,2.0\n2,1.5,\n"
    assert _csv([[1, math.nan], [2, math.nan]], ("uav", "heading_deg")) == b"uav\n1\n2\n"


# ---------------------------------------------------------------------------------------------
# A results folder owned by the run that writes it


def test_a_new_plan_replaces_the_old_one_as_a_whole(tmp_path: Path, capsys):
    out = tmp_path / "r"
    for uavs in ("5", "3"):
        code, err = cli(capsys, "plan", *SAMPLE, "--uavs", uavs, "--d-max", "400", "--out", out)
        assert code == EXIT_OK, err
    names = sorted(p.name for p in out.iterdir())
    assert [n for n in names if n.endswith(".plan")] == ["uav_01.plan", "uav_02.plan", "uav_03.plan"]
    assert strict_json(out / "plan.json")["settings"]["n_uavs"] == 3
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no staging folder left


def test_a_structure_plan_replaces_a_dem_plan_and_back(tmp_path: Path, capsys, structure_plan_folder: Path):
    out = tmp_path / "r"
    assert cli(capsys, "plan", *SAMPLE, "--uavs", "2", "--d-max", "400", "--out", out)[0] == EXIT_OK
    from uavcov.field._results_folder import write_files

    files = {p.name: p.read_bytes() for p in structure_plan_folder.iterdir()}
    write_files(files, out)
    assert sorted(p.name for p in out.iterdir()) == sorted(files)


@pytest.mark.parametrize("foreign", ["notes.txt", "uav_1.plan", "runs.csv", "subfolder/"])
def test_a_folder_of_other_files_is_refused_before_the_work_and_kept(tmp_path: Path, capsys, foreign: str):
    out = tmp_path / "mine"
    out.mkdir()
    if foreign.endswith("/"):
        (out / foreign).mkdir()
    else:
        (out / foreign).write_text("keep me")
    code, err = cli(capsys, "plan", *SAMPLE, "--uavs", "3", "--d-max", "400", "--out", out)
    assert_one_line(code, err, "not a uavcov plan's", foreign.rstrip("/"))
    assert sorted(p.name for p in out.iterdir()) == [foreign.rstrip("/")]


def test_plan_files_without_plan_json_are_not_taken_for_a_plan(tmp_path: Path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "report.md").write_text("my own report")
    with pytest.raises(ResultsInUseError, match=r"report\.md"):
        check_plan_folder(out)
    assert (out / "report.md").read_text() == "my own report"


def test_a_file_or_a_symbolic_link_in_place_of_the_folder_is_refused(tmp_path: Path, capsys):
    (tmp_path / "file").write_text("x")
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to(tmp_path / "real")
    for out in ("file", "link"):
        with pytest.raises(ResultsFolderError):
            check_plan_folder(tmp_path / out)
    dem = sample_dem((0, 12, 0, 12))
    flight = plan(dem, PlanSettings(n_uavs=2, d_max=300.0, iterations=0), rng=0, n_threads=1)
    with pytest.raises(ResultsFolderError, match="symbolic link"):
        write_plan(flight, tmp_path / "link")
    assert list((tmp_path / "real").iterdir()) == []
    written = write_plan(flight, tmp_path / "new" / "deeper")  # parents are made
    assert all(p.is_file() for p in written)


# ---------------------------------------------------------------------------------------------
# Angles reduced exactly before any trigonometry


@pytest.mark.parametrize("yaw", [1e300, -1e300, 7.5e15, 1e16 + 4.0, 720.25, -3600.5, 2.0**70])
def test_a_huge_heading_sees_what_its_reduced_heading_sees(yaw: float):
    reduced = math.fmod(yaw, 360.0)
    for a, b in zip(camera_axes([yaw], [-45.0]), camera_axes([reduced], [-45.0]), strict=True):
        assert np.array_equal(a, b)
    flat = Terrain.from_grid(np.zeros((41, 41)), spacing=1.0)
    vis = Visibility(flat, d_max=100.0)
    camera = Sensor(100.0, camera=Camera.from_fov(60.0, 45.0))
    assert vis.coverage([[20.0, 20.0, 10.0, yaw, -45.0]], sensors=[camera]) == vis.coverage(
        [[20.0, 20.0, 10.0, reduced, -45.0]], sensors=[camera]
    )
    anchor = GeoAnchor(7.0, 46.0, 500.0)
    assert (
        local_to_true_heading([[100.0, 50.0, 0.0]], [yaw], anchor)[0] == local_to_true_heading([[100.0, 50.0, 0.0]], [reduced], anchor)[0]
    )


def test_angles_within_a_turn_are_untouched():
    yaw = np.array([0.0, 45.123456789, 359.999999, -270.5])
    forward, _, _ = camera_axes(yaw, np.full(4, -30.0))
    y = np.radians(yaw)
    assert np.array_equal(forward[:, 0], np.sin(y) * np.cos(np.radians(-30.0)))


# ---------------------------------------------------------------------------------------------
# Files that are not what they say: complex rasters, pictures, OBJ faces, meshes beyond 1e15 m


@pytest.mark.parametrize("dtype", ["complex64", "complex128"])
def test_a_complex_geotiff_is_refused(tmp_path: Path, dtype: str):
    z = hills(8, 8)
    path = write_tif(tmp_path / "c.tif", z + 1j * z, (10.0, 0.0, 5e5, 0.0, -10.0, 5e6), "EPSG:32633", dtype=dtype)
    with pytest.raises(InvalidInputError, match="not heights"):
        read_dem(path)


@pytest.mark.parametrize("crs", [None, "EPSG:32633"])
def test_a_picture_is_not_a_dem_and_says_so_without_rasterios_warning(tmp_path: Path, capsys, crs: str | None):
    from PIL import Image

    picture = tmp_path / "photo.png"
    Image.fromarray((hills() % 256).astype(np.uint8)).save(picture)
    extra = [] if crs is None else ["--crs", crs]
    code, err = cli(capsys, "plan", picture, *extra, "--uavs", "3", "--d-max", "100", "--out", tmp_path / "o")
    assert_one_line(code, err, "not geo-referenced")
    result = subprocess.run(
        [sys.executable, "-m", "uavcov", "plan", str(picture), "--uavs", "3", "--d-max", "100", "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert_one_line(result.returncode, result.stderr, "not geo-referenced")


OBJ_VERTICES = "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nv 0 0 4\n"


@pytest.mark.parametrize(
    "faces, message",
    [
        ("f 0 2 3\nf 1 3 4", "vertex 0, but OBJ counts from 1"),
        ("f 1 2 3\nf 1 3 0", "vertex 0"),
        ("f 1 2 99", "vertex 99, but the file defines 5"),
        ("f -9 1 2", "reaches before the first vertex"),
        ("f 1 2", "at least 3 vertices"),
        ("f a b c", "not a face vertex"),
        ("f 1.5 2 3", "not a face vertex"),
        ("f 1/2/3/4 2 3", "not a face vertex"),
        ("f /1 2 3", "not a face vertex"),
        ("f 1/1 2/1 3/1", "texture coordinate 1, but the file defines 0"),
    ],
)
def test_a_malformed_obj_face_is_refused_naming_its_line(tmp_path: Path, faces: str, message: str):
    path = tmp_path / "m.obj"
    path.write_text(OBJ_VERTICES + faces + "\n")
    with pytest.raises(MeshError, match=message) as caught:
        load_mesh(path)
    assert "line " in str(caught.value)


def test_relative_obj_references_mean_what_obj_says(tmp_path: Path):
    relative = tmp_path / "relative.obj"
    relative.write_text("v 0 0 0\nv 4 0 0\nv 4 4 0\nf -3 -2 -1\nv 0 4 0\nv 0 8 1\nf -5 -3 -2\nf -2 -1 -3\n")
    absolute = tmp_path / "absolute.obj"
    absolute.write_text("v 0 0 0\nv 4 0 0\nv 4 4 0\nf 1 2 3\nv 0 4 0\nv 0 8 1\nf 1 3 4\nf 4 5 3\n")
    a, b = load_mesh(relative).terrain, load_mesh(absolute).terrain
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    assert float(a.area) == pytest.approx(float(b.area))


@pytest.mark.parametrize("how", ["shifted to x = 1e300", "scaled by 1e300", "scaled by 1e20", "shifted to x = 2e15", "scaled by -1e200"])
def test_a_mesh_beyond_1e15_m_is_refused_with_one_message(tmp_path: Path, how: str):
    box = trimesh.creation.box(extents=(4.0, 4.0, 4.0))
    factor = float(how.rsplit(maxsplit=1)[-1])
    vertices = box.vertices * factor if how.startswith("scaled") else box.vertices + [factor, 0.0, 0.0]
    path = tmp_path / "cube.obj"
    trimesh.Trimesh(vertices, box.faces, process=False).export(path)
    for load in (load_mesh, load_structure):
        with pytest.raises(MeshError, match="beyond 1e15 m in magnitude"):
            load(path)


# ---------------------------------------------------------------------------------------------
# Errors that leaked a library's words


def test_the_view_into_a_missing_folder_names_the_folder_not_a_temporary_file(tmp_path: Path, capsys):
    run = tmp_path / "r.npz"
    run.write_bytes(b"PK\x05\x06" + bytes(18))  # any path will do: the folder is checked first
    for out in ("missing/v.html", "missing/deeper/v.html"):
        code, err = cli(capsys, "view", run, "--out", tmp_path / out)
        assert_one_line(code, err, "does not exist")
        assert ".tmp-" not in err


@pytest.mark.parametrize("content", [b"hello", b"uav,x\n1,2\n", b"\x89PNG\r\n\x1a\n" + bytes(40), b"\x80\x04K\x01."])
def test_a_file_that_is_not_a_run_is_said_so_without_numpys_pickle_hint(tmp_path: Path, capsys, content: bytes):
    path = tmp_path / "not_a_run.npz"
    path.write_bytes(content)
    with pytest.raises(ResultsFormatError, match=r"not a \.npz archive"):
        load_mission(path)
    code, err = cli(capsys, "view", path, "--out", tmp_path / "v.html")
    assert_one_line(code, err, "not_a_run.npz")
    assert "pickle" not in err


def test_atomic_writes_into_a_missing_folder_name_the_file(tmp_path: Path):
    from uavcov._io import atomic_write

    with pytest.raises(ResultsFolderError) as caught:  # an OSError, since round 6 a uavcov one
        atomic_write(tmp_path / "nowhere" / "x.json", "{}")
    assert ".tmp-" not in str(caught.value) and "x.json" in str(caught.value) and "No such file" in str(caught.value)


def test_a_bbox_area_and_a_geojson_area_with_longitudes_past_180_write_wrapped(tmp_path: Path):
    path = write_tif(tmp_path / "dateline.tif", hills(), (0.022 / 24, 0.0, 179.988, 0.0, -0.0007, 45.01), "EPSG:4326")
    dem = read_dem(path)
    area = bbox_area(179.99, 44.996, 180.006, 45.008)
    flight = plan(dem, PlanSettings(n_uavs=2, d_max=300.0, iterations=0), area=area, rng=0, n_threads=1)
    out = tmp_path / "o"
    write_plan(flight, out)
    documents = read_back_strictly(out)
    areas = [f for f in documents["plan.geojson"]["features"] if f["properties"]["kind"] == "area"]
    assert areas and in_range(lonlats(areas))


@pytest.mark.parametrize("west, width", [(179.99, 0.02), (0.0, 350.0), (-190.0, 20.0)])
def test_longitudes_of_either_sign_land_on_a_dem_that_counts_past_180(west: float, width: float):
    columns = 10 if width < 1 else int(width)
    dem = dem_from_array(np.ones((6, columns)), (width / columns, 0.0, west, 0.0, -0.001, 45.0), "EPSG:4326")
    middle = float(wrap_longitude([west + 0.75 * width])[0])  # three quarters across: past 180 on the wide one
    for lon in (middle, middle - 360.0, middle + 360.0):  # the same meridian, counted three ways
        if abs(lon) <= 360.0:
            local = dem.from_wgs84([[lon, 44.998]])
            assert dem.terrain.bounds[0, 0] <= local[0, 0] <= dem.terrain.bounds[1, 0]  # on the DEM
            assert dem.to_wgs84(local)[0, 0] == pytest.approx(middle, abs=1e-9)
