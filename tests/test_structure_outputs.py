"""Outputs for structures (issue 35, point 5): seen point cloud PLY, ENU -> WGS84, a structure's plan, figures."""

from __future__ import annotations

import json
import math
import pickle
from pathlib import Path

import numpy as np
import pytest
import trimesh

from structure_meshes import box_on_ground, bridge, face_targets
from uavcov import Targets, Visibility
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError, ResultsFolderError
from uavcov.field import GeoAnchor
from uavcov.field._geodesy import enu_to_wgs84, local_to_true_heading
from uavcov.field._ply import read_seen_ply, seen_cloud_bytes, write_seen_ply
from uavcov.field._qgc import read_qgc_plan
from uavcov.field._structure_flight import structure_flight, write_structure_flight

pyproj = pytest.importorskip("pyproj")


# ------------------------------------------------------------------------------------------------
# PLY


def test_the_seen_cloud_round_trips_and_trimesh_reads_it(tmp_path: Path):
    surface = box_on_ground()
    targets = face_targets(surface)
    vis = Visibility(surface, d_max=60.0, targets=targets)
    uavs = np.array([[15.0, 0.0, 4.0], [0.0, -12.0, 12.0]])
    count = np.sum([vis.seen(u[None]) for u in uavs], axis=0)
    assert 0 < (count > 0).sum() < len(targets) and (count == 2).any()
    path = tmp_path / "seen.ply"
    write_seen_ply(path, targets, count)
    back = read_seen_ply(path)
    np.testing.assert_array_equal(back["points"], targets.points)
    np.testing.assert_allclose(back["normals"], targets.normals, atol=1e-7)
    np.testing.assert_array_equal(back["count"], count)
    np.testing.assert_array_equal(back["seen"], count > 0)
    # An independent reader.
    cloud = trimesh.load(path, process=False)
    np.testing.assert_array_equal(np.asarray(cloud.vertices), targets.points)
    raw = cloud.metadata["_ply_raw"]["vertex"]["data"]
    np.testing.assert_array_equal(raw["count"], count)
    np.testing.assert_array_equal(raw["seen"], (count > 0).astype(np.uint8))
    # No normals: zeros.
    bare = Targets(targets.points)
    assert read_seen_ply_bytes(seen_cloud_bytes(bare, count), tmp_path)["normals"].any() is np.False_


def read_seen_ply_bytes(data: bytes, tmp_path: Path) -> dict:
    path = tmp_path / "bytes.ply"
    path.write_bytes(data)
    return read_seen_ply(path)


def test_bad_clouds_are_clear_errors(tmp_path: Path):
    targets = Targets([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    for bad in ([1], [1, -1], [0.5, 1], [math.nan, 0]):
        with pytest.raises(InvalidInputError):
            seen_cloud_bytes(targets, bad)
    with pytest.raises(InvalidTypeError):
        seen_cloud_bytes(np.zeros((2, 3)), [0, 0])  # type: ignore[arg-type]
    good = seen_cloud_bytes(targets, [0, 3])
    for name, data in (
        ("truncated", good[:-3]),
        ("text", b"hello\n"),
        ("other", good.replace(b"property int count", b"property int other")),
    ):
        path = tmp_path / f"{name}.ply"
        path.write_bytes(data)
        with pytest.raises(InvalidInputError):
            read_seen_ply(path)
    with pytest.raises(InvalidInputError, match="cannot read"):
        read_seen_ply(tmp_path / "missing.ply")
    (tmp_path / "folder.ply").mkdir()
    with pytest.raises(ResultsFolderError):
        write_seen_ply(tmp_path / "folder.ply", targets, [0, 1])
    assert not (tmp_path / "folder.ply").is_file()


# ------------------------------------------------------------------------------------------------
# Geodesy


def _pyproj_enu_to_wgs84(points: np.ndarray, anchor: GeoAnchor) -> np.ndarray:
    pipeline = (
        f"+proj=pipeline +step +inv +proj=topocentric +ellps=WGS84 +lon_0={anchor.longitude!r} +lat_0={anchor.latitude!r} "
        f"+h_0={anchor.height!r} +step +inv +proj=cart +ellps=WGS84 +step +proj=unitconvert +xy_in=rad +xy_out=deg"
    )
    lon, lat, h = pyproj.Transformer.from_pipeline(pipeline).transform(points[:, 0], points[:, 1], points[:, 2])
    return np.column_stack([lon, lat, h])


@pytest.mark.parametrize(
    "anchor", [(7.0, 46.0, 500.0), (-179.99, -45.0, -30.0), (120.0, 0.0, 8000.0), (0.0, 89.9, 0.0), (-73.98, 40.75, 10.0)]
)
def test_enu_to_wgs84_matches_pyproj(anchor: tuple[float, float, float]):
    geo = GeoAnchor(*anchor)
    points = np.random.default_rng(1).uniform(-5000.0, 5000.0, size=(200, 3))
    ours = enu_to_wgs84(points, geo)
    ref = _pyproj_enu_to_wgs84(points, geo)
    np.testing.assert_allclose((ours[:, 0] - ref[:, 0] + 180.0) % 360.0 - 180.0, 0.0, atol=1e-9)
    np.testing.assert_allclose(ours[:, 1], ref[:, 1], atol=1e-9)
    np.testing.assert_allclose(ours[:, 2], ref[:, 2], atol=1e-6)
    np.testing.assert_allclose(enu_to_wgs84([[0.0, 0.0, 0.0]], geo)[0], anchor, atol=1e-9)


def test_true_headings_follow_the_meridians():
    geo = GeoAnchor(7.0, 46.0, 0.0)
    points = np.array([[0.0, 0.0, 10.0], [3000.0, 0.0, 10.0], [-3000.0, 500.0, 10.0]])
    heading = local_to_true_heading(points, [0.0, 0.0, 90.0], geo)
    # The local north at a point east of the anchor leans east of true north by the meridians'
    # convergence, d_lon sin(lat); pyproj's geodesic azimuth from the point towards the point
    # 1 km further along the local north is the reference.
    north = points + [0.0, 1000.0, 0.0]
    a, b = enu_to_wgs84(points, geo), enu_to_wgs84(north, geo)
    azimuth, _, _ = pyproj.Geod(ellps="WGS84").inv(a[:, 0], a[:, 1], b[:, 0], b[:, 1])
    np.testing.assert_allclose((heading[:2] - azimuth[:2] + 180.0) % 360.0 - 180.0, 0.0, atol=1e-3)
    assert heading[0] == pytest.approx(0.0, abs=1e-9)
    convergence = (a[1, 0] - 7.0) * math.sin(math.radians(46.0))
    assert heading[1] == pytest.approx(convergence, rel=1e-2)


@pytest.mark.parametrize(
    "bad",
    [
        (math.nan, 46.0, 0.0),
        (7.0, 91.0, 0.0),
        (7.0, -90.5, 0.0),
        (181.0, 0.0, 0.0),
        (7.0, 46.0, 1e300),
        (7.0, 46.0, math.inf),
        ("7", 46.0, 0.0),
    ],
)
def test_bad_anchors_are_clear_errors(bad):
    with pytest.raises(InvalidInputError, match="anchor"):
        GeoAnchor(*bad)


def test_bad_local_points_are_clear_errors():
    geo = GeoAnchor(7.0, 46.0)
    for bad in ([[0.0, 0.0, math.nan]], [[1e300, 0.0, 0.0]], [[0.0, 0.0]], np.zeros((2, 3, 1))):
        with pytest.raises(InvalidInputError):
            enu_to_wgs84(bad, geo)
    with pytest.raises(InvalidInputError):
        enu_to_wgs84([[0.0, 0.0, 0.0]], (7.0, 46.0))  # type: ignore[arg-type]


# ------------------------------------------------------------------------------------------------
# A structure's plan


def test_a_structure_plan_writes_files_in_wgs84_with_relative_altitudes(tmp_path: Path):
    geo = GeoAnchor(-1.5, 52.0, 80.0)
    positions = np.array([[-18.0, 0.0, 12.0], [18.0, 0.0, 14.0]])
    plan = structure_flight(positions, geo, takeoff=[0.0, -18.0, 0.0], attitudes=[[90.0, -30.0], [270.0, 20.0]], surface=bridge())
    written = write_structure_flight(plan, tmp_path / "out")
    names = sorted(p.name for p in written)
    assert names == ["plan.geojson", "plan.json", "positions.csv", "uav_01.plan", "uav_02.plan", "waypoints.csv"]
    ref = _pyproj_enu_to_wgs84(positions, geo)
    np.testing.assert_allclose(plan.positions_wgs84, ref, atol=1e-9)
    document = read_qgc_plan(tmp_path / "out" / "uav_02.plan")
    items = document["items"]
    assert [i["command"] for i in items] == [22, 16, 16, 205, 19]
    assert document["home"][2] == pytest.approx(_pyproj_enu_to_wgs84(np.array([[0.0, -18.0, 0.0]]), geo)[0, 2], abs=1e-6)
    position = items[2]["params"]
    assert position[4] == pytest.approx(ref[1, 1], abs=1e-12) and position[5] == pytest.approx(ref[1, 0], abs=1e-12)
    pad_h = _pyproj_enu_to_wgs84(np.array([[0.0, -18.0, 0.0]]), geo)[0, 2]
    assert position[6] == pytest.approx(ref[1, 2] - pad_h, abs=1e-6)  # relative to home: about 14 m
    assert position[6] == pytest.approx(14.0, abs=0.01)
    assert items[3]["params"][0] == 20.0  # the gimbal pitched 20 degrees up
    assert position[3] == pytest.approx(270.0, abs=0.01)
    geojson = json.loads((tmp_path / "out" / "plan.geojson").read_text())
    assert geojson["features"][1]["geometry"]["coordinates"] == pytest.approx(ref[0].tolist())
    assert pickle.loads(pickle.dumps(plan)).positions_wgs84.tolist() == plan.positions_wgs84.tolist()


def test_a_route_through_the_structure_is_refused_and_a_route_round_it_is_not():
    surface = bridge()
    geo = GeoAnchor(7.0, 46.0)
    under = [[0.0, 0.0, 7.0]]  # under the deck: the default climb-then-cross route is clear from the side pad
    structure_flight(under, geo, takeoff=[0.0, -18.0, 0.0], surface=surface)
    with pytest.raises(InfeasibleError, match="UAV 1's route crosses the structure"):
        structure_flight(under, geo, takeoff=[0.0, -18.0, 0.0], routes=[[[0.0, -18.0, 15.0], [0.0, 0.0, 15.0]]], surface=surface)
    with pytest.raises(InfeasibleError):
        structure_flight([[0.0, 0.0, 15.0]], geo, takeoff=[0.0, 0.0, 11.0], routes=[[[0.0, 0.0, 5.0]]], surface=surface)


def test_bad_plans_are_clear_errors(tmp_path: Path):
    geo = GeoAnchor(7.0, 46.0)
    with pytest.raises(InvalidInputError):
        structure_flight([[0.0, 0.0, math.nan]], geo, takeoff=[0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError):
        structure_flight(np.zeros((0, 3)), geo, takeoff=[0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError):
        structure_flight([[0.0, 0.0, 5.0]], geo, takeoff=[0.0, 0.0])
    with pytest.raises(InvalidInputError, match="pitch"):
        structure_flight([[0.0, 0.0, 5.0]], geo, takeoff=[0.0, 0.0, 0.0], attitudes=[[0.0, 120.0]])
    with pytest.raises(InvalidInputError):
        structure_flight([[2e5, 0.0, 5.0]], geo, takeoff=[0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError):
        structure_flight([[0.0, 0.0, 5.0]], geo, takeoff=[0.0, 0.0, 0.0], routes=[])
    with pytest.raises(InvalidTypeError):
        structure_flight([[0.0, 0.0, 5.0]], (7.0, 46.0), takeoff=[0.0, 0.0, 0.0])  # type: ignore[arg-type]
    plan = structure_flight([[0.0, 0.0, 5.0]], geo, takeoff=[0.0, 0.0, 0.0])
    (tmp_path / "file").write_text("x")
    with pytest.raises(ResultsFolderError):
        write_structure_flight(plan, tmp_path / "file")


# ------------------------------------------------------------------------------------------------
# Figures


def test_the_structure_figure_takes_a_structure_with_its_ground_part():
    from uavcov.plotting import plot_structure_seen
    from uavcov.structures import facade

    scene = facade(rng=0)
    targets = scene.targets(spacing=2.0)
    seen = targets.normals[:, 1] < -0.5  # the faces turned to -y
    below = [(-30.0, -60.0)]
    ground = scene.face_parts == scene.ground_part

    def drawn(fig):
        return fig.axes[0].collections[0].get_facecolor()

    whole = drawn(plot_structure_seen(scene, seen, targets=targets, views=below))
    np.testing.assert_array_equal(whole, drawn(plot_structure_seen(scene.surface, seen, targets=targets, views=below, ground=ground)))
    assert (whole[:, 0] > whole[:, 2]).any()  # some seen face (red) drawn from below


def test_the_structure_figure_colours_faces_by_their_targets_and_shows_several_sides(tmp_path: Path):
    from uavcov.plotting import plot_structure_seen
    from uavcov.plotting._structures import face_seen_share

    surface = bridge()
    targets = face_targets(surface)
    # Seen: only the faces facing down (the deck's underside, the ground sees nothing of it).
    seen = targets.normals[:, 2] < -0.5
    share = face_seen_share(surface, targets, seen)
    np.testing.assert_array_equal(share, seen.astype(float))  # one target per face, on its own face
    fig = plot_structure_seen(surface, seen, targets=targets, positions=[[0.0, 0.0, 7.0]], out=tmp_path / "bridge.png")
    axes = [ax for ax in fig.axes if ax.name == "3d"]
    assert len(axes) == 4 and min(ax.elev for ax in axes) < 0  # one view from below
    assert (tmp_path / "bridge.png").stat().st_size > 10_000
    # The drawn face colours: seen faces red, the others the unseen colour (shading only scales
    # them), so the hue tells which is which (matplotlib sorts the faces by depth: count them).
    # Back faces are culled: from above, no face turned down is drawn, so nothing red; from
    # below, without the ground, every downward face is (and the sides facing the view).
    for ax in axes:
        colours = ax.collections[0].get_facecolor()[:, :3]
        red = int((colours[:, 0] > colours[:, 2]).sum())
        assert red == (int(seen.sum()) if ax.elev < 0 else 0)
        assert len(colours) < surface.n_faces
    with pytest.raises(InvalidInputError, match="ground"):
        plot_structure_seen(surface, seen, targets=targets, ground=[True])
    with pytest.raises(InvalidTypeError, match="Terrain or Structure"):
        plot_structure_seen(surface.vertices, seen, targets=targets)
    # Per-face values, decimated drawing of a fine mesh, and bad input.
    plot_structure_seen(surface, np.linspace(0.0, 1.0, surface.n_faces), views=[(20.0, 0.0)], max_polygons=10)
    with pytest.raises(InvalidInputError):
        plot_structure_seen(surface, [1.0, 0.0])
    with pytest.raises(InvalidInputError):
        plot_structure_seen(surface, np.full(surface.n_faces, 2.0))
    with pytest.raises(InvalidInputError):
        plot_structure_seen(surface, seen, targets=targets, views=[])
    with pytest.raises(InvalidTypeError):
        plot_structure_seen(box_on_ground().vertices, seen)  # type: ignore[arg-type]
