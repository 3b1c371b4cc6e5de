"""Constraints of the paper's eq. 2: feasibility masks and closest admissible starts.

The checks are compared with a per-UAV, per-pair loop written from the definition, on a small
analytic world (a flat ground with box buildings) whose clearance, heights and segment tests are
exact, and on real ``Terrain`` grids when the engine is built.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from uavcov import Constraints
from uavcov.errors import InfeasibleError, InvalidInputError, InvalidTypeError
from uavcov.limits import closest_admissible, feasibility
from uavcov.limits._constraints import feasible_mask, trajectory_feasible

# ---------------------------------------------------------------------------------------------
# An analytic world: ground z = ground on [0, size]^2, closed boxes standing on it
# ---------------------------------------------------------------------------------------------


class BoxWorld:
    """Flat ground with axis-aligned closed boxes; every query exact, with call counters."""

    def __init__(self, size: float = 30.0, ground: float = 0.0, boxes=(), holes=()):
        self.size = float(size)
        self.ground = float(ground)
        # (xmin, ymin, xmax, ymax, top)
        self.boxes = [tuple(map(float, b)) for b in boxes]
        # (xmin, ymin, xmax, ymax): no surface at all there (nodata)
        self.holes = [tuple(map(float, h)) for h in holes]
        self.calls = {"clearance": 0, "segments_clear": 0, "ground_height": 0}
        self.points_queried = 0
        self.segments_queried = 0

    @property
    def bounds(self):
        top = max([self.ground] + [b[4] for b in self.boxes])
        return np.array([[0.0, 0.0, self.ground], [self.size, self.size, top]])

    def _in_hole(self, x, y):
        return any(h[0] <= x <= h[2] and h[1] <= y <= h[3] for h in self.holes)

    def _column_top(self, x, y):
        if not (0.0 <= x <= self.size and 0.0 <= y <= self.size) or self._in_hole(x, y):
            return math.nan
        top = self.ground
        for b in self.boxes:
            if b[0] <= x <= b[2] and b[1] <= y <= b[3]:
                top = max(top, b[4])
        return top

    def ground_height(self, xy):
        self.calls["ground_height"] += 1
        xy = np.asarray(xy, dtype=float)
        return np.array([self._column_top(x, y) for x, y in xy[:, :2]])

    def clearance(self, points):
        self.calls["clearance"] += 1
        points = np.asarray(points, dtype=float)
        self.points_queried += len(points)
        out = np.empty(len(points))
        for k, (x, y, z) in enumerate(points):
            top = self._column_top(x, y)
            if math.isnan(top):
                out[k] = math.inf
                continue
            # surfaces below the point in this column: the ground and every box top under it
            below = [self.ground] if z >= self.ground else []
            below.extend(b[4] for b in self.boxes if b[0] <= x <= b[2] and b[1] <= y <= b[3] and b[4] <= z)
            out[k] = z - max(below) if below else math.inf
        return out

    def segments_clear(self, a, b):
        self.calls["segments_clear"] += 1
        a = np.asarray(a, dtype=float)
        b = np.asarray(b, dtype=float)
        self.segments_queried += len(a)
        out = np.empty(len(a), dtype=bool)
        for k in range(len(a)):
            out[k] = not self._segment_hits(a[k], b[k])
        return out

    def _segment_hits(self, p, q):
        if min(p[2], q[2]) <= self.ground:
            return True
        for b in self.boxes:
            lo = np.array([b[0], b[1], self.ground])
            hi = np.array([b[2], b[3], b[4]])
            t0, t1 = 0.0, 1.0
            d = q - p
            hit = True
            for axis in range(3):
                if d[axis] == 0.0:
                    if p[axis] < lo[axis] or p[axis] > hi[axis]:
                        hit = False
                        break
                else:
                    u = (lo[axis] - p[axis]) / d[axis]
                    v = (hi[axis] - p[axis]) / d[axis]
                    t0, t1 = max(t0, min(u, v)), min(t1, max(u, v))
                    if t0 > t1:
                        hit = False
                        break
            if hit:
                return True
        return False


def reference_ok(c: Constraints, world: BoxWorld, current, config) -> bool:  # noqa: PLR0911 - one return per constraint
    """The definition, one UAV and one pair at a time."""
    n = len(config)
    xmin, ymin, xmax, ymax = c.bounds
    for i in range(n):
        x, y, z = config[i]
        if not (xmin <= x <= xmax and ymin <= y <= ymax) or z > c.z_max:
            return False
        top = world._column_top(x, y)
        if math.isnan(top):
            return False
        # clearance to the highest surface below z
        surfaces = [world.ground] + [b[4] for b in world.boxes if b[0] <= x <= b[2] and b[1] <= y <= b[3]]
        below = [s for s in surfaces if s <= z]
        if not below or z - max(below) < c.h_min:
            return False
        if c.h_max is not None and z - max(below) > c.h_max:
            return False
        for j in range(i + 1, n):
            if np.linalg.norm(np.asarray(config[i]) - np.asarray(config[j])) < c.d_safe:
                return False
        moved = c.check_moves and not np.array_equal(current[i], config[i])
        if moved and world._segment_hits(np.asarray(current[i], float), np.asarray(config[i], float)):
            return False
    return True


BUILDINGS = [(5, 5, 10, 12, 8.0), (18, 15, 24, 20, 14.0)]


@pytest.fixture
def town() -> BoxWorld:
    return BoxWorld(30.0, 0.0, boxes=BUILDINGS)


# ---------------------------------------------------------------------------------------------
# Settings
# ---------------------------------------------------------------------------------------------


def test_defaults_and_bounds_forms():
    c = Constraints((0, 0, 10, 20))
    assert (c.h_min, c.z_max, c.d_safe, c.check_moves) == (2.0, 50.0, 2.0, False)
    assert c.bounds == (0.0, 0.0, 10.0, 20.0)
    c2 = Constraints(np.array([[0.0, 0.0, -3.0], [10.0, 20.0, 7.0]]))
    assert c2.bounds == c.bounds
    assert pickle.loads(pickle.dumps(c)) == c


@pytest.mark.parametrize(
    "kwargs, error",
    [
        (dict(bounds=(0, 0, 10, math.nan)), InvalidInputError),
        (dict(bounds=(0, 0, 10, math.inf)), InvalidInputError),
        (dict(bounds=(10, 0, 0, 10)), InvalidInputError),
        (dict(bounds=(0, 0, 10, 0)), InvalidInputError),
        (dict(bounds=(0, 0, 10)), InvalidInputError),
        (dict(bounds="0 0 10 10"), InvalidTypeError),
        (dict(bounds=(0, 0, 10, 10), h_min=-1.0), InvalidInputError),
        (dict(bounds=(0, 0, 10, 10), h_min=math.nan), InvalidInputError),
        (dict(bounds=(0, 0, 10, 10), z_max=math.inf), InvalidInputError),
        (dict(bounds=(0, 0, 10, 10), d_safe=-0.5), InvalidInputError),
        (dict(bounds=(0, 0, 10, 10), d_safe=math.nan), InvalidInputError),
        (dict(bounds=(0, 0, 10, 10), check_moves="yes"), InvalidTypeError),
        (dict(bounds=(0, 0, 10, 10), h_min=10.0, z_max=5.0), InfeasibleError),
        (dict(bounds=(0, 0, 10, 10), h_min=3.0, h_max=2.0), InfeasibleError),
        (dict(bounds=(0, 0, 10, 10), h_max=math.nan), InvalidInputError),
        (dict(bounds=(0, 0, 10, 10), h_max=math.inf), InvalidInputError),
        (dict(bounds=(0, 0, 10, 10), h_max="high"), InvalidTypeError),
    ],
)
def test_bad_settings_raise(kwargs, error):
    with pytest.raises(error):
        Constraints(**kwargs)


def test_h_min_above_z_max_is_an_infeasible_error_and_a_value_error():
    with pytest.raises(ValueError, match="h_min"):
        Constraints((0, 0, 10, 10), h_min=60.0, z_max=50.0)


def test_packing_bound():
    world = BoxWorld(10.0)
    c = Constraints((0, 0, 10, 10), h_min=2.0, z_max=4.0, d_safe=3.0)
    # box (10 + 3)^2 (2 + 3) = 845 m^3; one ball 4/3 pi 1.5^3 = 14.14 m^3 -> at most 59 UAVs
    c.check_team(59, world)
    with pytest.raises(InfeasibleError, match="cannot fit"):
        c.check_team(60, world)
    # the ground of the world counts: raising it past z_max - h_min leaves no room at all
    with pytest.raises(InfeasibleError, match="no altitude"):
        c.check_team(1, BoxWorld(10.0, ground=3.0))
    # and the refusal says what to change: a ceiling 50 m above the world's highest point
    high = BoxWorld(10.0, ground=300.0, boxes=[(2.0, 2.0, 4.0, 4.0, 312.5)])
    with pytest.raises(
        InfeasibleError, match=r"z = 300 m.*absolute altitude.*Constraints\(z_max=363\).*z_max = 363 under \[constraints\] in a sweep"
    ):
        Constraints(h_min=2.0).check_team(1, high)
    Constraints(h_min=2.0, z_max=363.0).check_team(1, high)  # and the value it suggests is admitted
    with pytest.raises(InvalidInputError):
        c.check_team(0, world)
    with pytest.raises(InvalidTypeError):
        c.check_team(2.5, world)


def test_the_ceiling_above_ground_bounds_clearance_and_thins_the_packing():
    world = BoxWorld(10.0, boxes=[(0, 0, 5, 10, 6.0)])  # a 6 m block over the west half
    c = Constraints((0, 0, 10, 10), h_min=1.0, z_max=40.0, h_max=3.0, d_safe=0.0)
    # the ceiling follows the ground: 7 m is legal over the block (1 m up), not east of it
    over_block, east = [2.5, 5.0, 7.0], [7.5, 5.0, 7.0]
    np.testing.assert_array_equal(feasible_mask(c, world, [over_block], [[over_block], [east]]), [True, False])
    assert feasible_mask(c, world, [east], [[[7.5, 5.0, 3.0]], [[7.5, 5.0, 3.0 + 1e-9]]]).tolist() == [True, False]
    # the packing bound counts the 2 m band between h_min and h_max, not the 39 m up to z_max
    packed = Constraints((0, 0, 10, 10), h_min=1.0, z_max=40.0, h_max=3.0, d_safe=3.0)
    packed.check_team(59, world)  # (10 + 3)^2 (2 + 3) = 845 m^3 holds 59 balls of 14.14 m^3
    with pytest.raises(InfeasibleError, match="cannot fit"):
        packed.check_team(60, world)
    Constraints((0, 0, 10, 10), h_min=1.0, z_max=40.0, d_safe=3.0).check_team(60, world)


def test_closest_admissible_lowers_to_the_ceiling_and_caps_the_climb():
    world = BoxWorld(10.0, boxes=[(0, 0, 5, 10, 6.0)])
    c = Constraints((0, 0, 10, 10), h_min=1.0, z_max=40.0, h_max=3.0, d_safe=0.0)
    start = np.array([[7.5, 5.0, 30.0], [2.5, 5.0, 2.0], [7.5, 2.0, 0.5]])
    out = closest_admissible(c, world, start, climb=5.0)
    assert feasible_mask(c, world, out, out[None])[0]
    np.testing.assert_allclose(out[:, 2], [3.0, 9.0, 3.0], atol=1e-5)  # every one just under its ceiling
    assert (out[:, 2] <= world.ground_height(out[:, :2]) + 3.0).all()
    np.testing.assert_array_equal(out[:, :2], start[:, :2])
    # a climb inside the band is kept; a UAV already between floor and ceiling stays put
    mid = closest_admissible(c, world, [[7.5, 5.0, 0.5], [2.0, 2.0, 8.0]], climb=1.0)
    np.testing.assert_allclose(mid, [[7.5, 5.0, 2.0], [2.0, 2.0, 8.0]])


def test_packing_bound_is_only_necessary_and_closest_admissible_reports_the_rest():
    # 3 UAVs in a 2 m x 2 m x 0 m slab with d_safe = 2.5: passes the volume bound (3 balls of
    # 8.18 m^3 < 4.5^2 * 2.5 = 50.6 m^3) but only 2 fit in reality (the diagonal is 2.83 m).
    world = BoxWorld(2.0)
    c = Constraints((0, 0, 2, 2), h_min=1.0, z_max=1.0, d_safe=2.5)
    c.check_team(3, world)
    with pytest.raises(InfeasibleError):
        closest_admissible(c, world, np.full((3, 3), 1.0), max_sweeps=200)


# ---------------------------------------------------------------------------------------------
# Feasibility masks
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("check_moves, h_max", [(False, None), (True, None), (False, 6.0), (True, 6.0)])
def test_mask_matches_the_definition(town, check_moves, h_max):
    rng = np.random.default_rng(3)
    c = Constraints((1, 1, 29, 29), h_min=2.0, z_max=20.0, d_safe=2.5, check_moves=check_moves, h_max=h_max)
    current = np.array([[3.0, 3.0, 4.0], [15.0, 8.0, 3.0], [21.0, 17.0, 17.0], [26.0, 26.0, 2.5]])
    assert reference_ok(c, town, current, current)
    # candidates around the current state at several scales: inside buildings, over roofs,
    # below h_min, out of bounds, above z_max, too close to a neighbour
    scales = np.repeat([0.5, 2.0, 6.0], 200)
    candidates = current[None] + scales[:, None, None] * rng.standard_normal((600, 4, 3))
    candidates[:5] = current  # the team staying
    mask = feasible_mask(c, town, current, candidates)
    expected = np.array([reference_ok(c, town, current, cand) for cand in candidates])
    assert mask.dtype == np.bool_ and mask.shape == (600,)
    np.testing.assert_array_equal(mask, expected)
    assert 50 < mask.sum() < 550  # both outcomes are well represented
    assert mask[:5].all()


def test_a_candidate_inside_a_building_needs_the_move_check(town):
    c_free = Constraints((0, 0, 30, 30), h_min=2.0, z_max=20.0, d_safe=0.0)
    c_moves = Constraints((0, 0, 30, 30), h_min=2.0, z_max=20.0, d_safe=0.0, check_moves=True)
    current = np.array([[3.0, 8.0, 4.0]])  # beside the first building (x 5-10, top 8)
    inside = np.array([[[7.0, 8.0, 4.0]]])  # 4 m above the ground, inside the walls
    assert feasible_mask(c_free, town, current, inside)[0]  # the clearance alone is fine
    assert not feasible_mask(c_moves, town, current, inside)[0]  # the wall is in the way
    over_roof = np.array([[[7.0, 8.0, 11.0]]])  # 3 m over the roof, but the path cuts the wall
    assert not feasible_mask(c_moves, town, current, over_roof)[0]
    from_above = np.array([[3.0, 8.0, 12.0]])
    assert feasible_mask(c_moves, town, from_above, over_roof)[0]


def test_under_the_ground_outside_the_surface_and_over_holes_are_refused():
    world = BoxWorld(20.0, ground=1.0, holes=[(8, 8, 12, 12)])
    c = Constraints((-5, -5, 25, 25), h_min=0.5, z_max=30.0, d_safe=0.0)
    current = np.array([[2.0, 2.0, 5.0]])
    cands = np.array(
        [
            [[2.0, 2.0, 5.0]],  # fine
            [[2.0, 2.0, 0.5]],  # below the ground: nothing below it, clearance inf
            [[10.0, 10.0, 5.0]],  # over the hole
            [[-2.0, 3.0, 5.0]],  # inside the bounds but off the surface
            [[4.0, 4.0, 1.4]],  # 0.4 m over the ground < h_min
            [[4.0, 4.0, 1.5]],  # exactly h_min: allowed (closed constraint)
        ]
    )
    np.testing.assert_array_equal(feasible_mask(c, world, current, cands), [True, False, False, False, False, True])


def test_exact_boundaries_are_admissible():
    world = BoxWorld(10.0)
    c = Constraints((0, 0, 10, 10), h_min=2.0, z_max=9.0, d_safe=3.0)
    config = np.array([[0.0, 0.0, 9.0], [10.0, 10.0, 2.0], [3.0, 0.0, 9.0]])  # pair (0, 2) exactly d_safe
    assert feasible_mask(c, world, config, config[None])[0]
    nudged = config.copy()
    nudged[2, 0] = 3.0 - 1e-9
    assert not feasible_mask(c, world, config, nudged[None])[0]


def test_the_surface_is_queried_once_per_mask_and_only_for_survivors(town):
    c = Constraints((0, 0, 30, 30), h_min=2.0, z_max=20.0, d_safe=2.0, check_moves=True)
    current = np.array([[2.0, 2.0, 3.0], [25.0, 3.0, 3.0], [3.0, 25.0, 3.0]])
    rng = np.random.default_rng(0)
    cands = current[None] + rng.normal(scale=1.0, size=(300, 3, 3))
    cands[:100, 0, 0] = -1.0  # out of bounds: must not reach the surface queries
    cands[100:150] = current  # staying: no segment to test
    feasible_mask(c, town, current, cands)
    assert town.calls["clearance"] == 1 and town.calls["segments_clear"] == 1
    assert town.points_queried <= 200 * 3
    assert town.segments_queried <= 150 * 3


def test_mask_input_checks(town):
    c = Constraints((0, 0, 30, 30))
    cur = np.array([[2.0, 2.0, 3.0], [8.0, 2.0, 3.0]])
    with pytest.raises(InvalidInputError):
        feasible_mask(c, town, cur, np.zeros((5, 3, 3)))
    with pytest.raises(InvalidInputError):
        feasible_mask(c, town, cur, np.full((5, 2, 3), np.nan))
    with pytest.raises(InvalidInputError):
        feasible_mask(c, town, cur[:, :2], np.zeros((5, 2, 3)))
    with pytest.raises(InvalidTypeError):
        feasible_mask("constraints", town, cur, cur[None])
    with pytest.raises(InvalidTypeError):
        feasible_mask(c, object(), cur, cur[None])
    with pytest.raises(InvalidTypeError):
        feasibility(c, object())
    # a single configuration (N, 3) is read as one candidate
    assert feasible_mask(c, town, cur, cur).shape == (1,)


def test_feasibility_closure_and_trajectory_check(town):
    c = Constraints((0, 0, 30, 30), h_min=2.0, z_max=20.0, d_safe=2.0, check_moves=True)
    feasible = feasibility(c, town)
    start = np.array([[3.0, 8.0, 4.0], [3.0, 14.0, 4.0]])
    cands = np.stack([start, start + [1.0, 0.0, 0.0], start + [4.0, 0.0, 0.0]])  # last enters a wall
    np.testing.assert_array_equal(feasible(start, cands), [True, True, False])
    traj = np.stack([start, start + [1.0, 0.0, 0.0], start + [1.0, 0.0, 20.0], start + [5.0, 0.0, 15.0]])
    np.testing.assert_array_equal(trajectory_feasible(c, town, traj), [True, True, False, True])
    with pytest.raises(InvalidInputError):
        trajectory_feasible(c, town, start)


# ---------------------------------------------------------------------------------------------
# Closest admissible starts
# ---------------------------------------------------------------------------------------------


def test_an_admissible_start_is_left_exactly_alone(town):
    c = Constraints((0, 0, 30, 30), h_min=2.0, z_max=20.0, d_safe=2.0)
    start = np.array([[3.0, 3.0, 4.0], [15.0, 8.0, 3.0], [21.0, 17.0, 17.0]])
    np.testing.assert_array_equal(closest_admissible(c, town, start), start)


def test_each_uav_goes_to_its_own_closest_admissible_point(town):
    c = Constraints((0, 0, 30, 30), h_min=2.0, z_max=20.0, d_safe=2.0)
    start = np.array(
        [
            [3.0, 3.0, -4.0],  # under the ground -> 2 m above it
            [7.0, 8.0, 5.0],  # inside the first building -> over its roof (8 + 2)
            [20.0, 17.0, 15.0],  # 1 m over the second roof (14) -> 16
            [-3.0, 35.0, 40.0],  # outside the region and too high -> clamped into the corner, z_max
            [27.0, 3.0, 5.0],  # already fine
        ]
    )
    out = closest_admissible(c, town, start)
    expected = np.array(
        [
            [3.0, 3.0, 2.0],
            [7.0, 8.0, 10.0],
            [20.0, 17.0, 16.0],
            [0.0, 30.0, 20.0],
            [27.0, 3.0, 5.0],
        ]
    )
    np.testing.assert_allclose(out, expected, atol=1e-5)
    assert np.all(out[:3, 2] >= expected[:3, 2])  # lifted to h_min or just above, never below
    assert feasible_mask(c, town, out, out[None])[0]


def test_close_uavs_are_pushed_apart_symmetrically_and_deterministically():
    world = BoxWorld(30.0)
    c = Constraints((0, 0, 30, 30), h_min=2.0, z_max=20.0, d_safe=2.0)
    start = np.array([[10.0, 10.0, 5.0], [10.5, 10.0, 5.0], [20.0, 20.0, 5.0]])
    out = closest_admissible(c, world, start)
    # the pair moves apart along x by (2 - 0.5) / 2 each; the third does not move
    np.testing.assert_allclose(out[0], [9.25, 10.0, 5.0], atol=1e-5)
    np.testing.assert_allclose(out[1], [11.25, 10.0, 5.0], atol=1e-5)
    np.testing.assert_array_equal(out[2], start[2])
    assert np.linalg.norm(out[0] - out[1]) >= 2.0


def test_coincident_and_crowded_starts_are_separated():
    world = BoxWorld(30.0)
    c = Constraints((0, 0, 30, 30), h_min=2.0, z_max=20.0, d_safe=2.0)
    start = np.tile([[1.0, 1.0, 0.0]], (9, 1))  # nine UAVs at one point in a corner, underground
    out = closest_admissible(c, world, start)
    again = closest_admissible(c, world, start)
    np.testing.assert_array_equal(out, again)
    assert feasible_mask(c, world, out, out[None])[0]
    d = np.linalg.norm(out[:, None] - out[None], axis=2)[np.triu_indices(9, 1)]
    assert d.min() >= 2.0
    # closeness: nobody is sent far away (nine 2 m balls fit well within 6 m of the corner)
    assert np.linalg.norm(out - [1.0, 1.0, 2.0], axis=1).max() < 8.0


def test_impossible_starts_raise(town):
    c = Constraints((0, 0, 30, 30), h_min=2.0, z_max=15.0, d_safe=2.0)
    with pytest.raises(InfeasibleError, match="exceeds z_max"):
        closest_admissible(c, town, np.array([[20.0, 17.0, 5.0]]))  # roof 14 + 2 > 15
    holes = BoxWorld(20.0, holes=[(5, 5, 15, 15)])
    with pytest.raises(InfeasibleError, match="no surface"):
        closest_admissible(Constraints((0, 0, 20, 20)), holes, np.array([[10.0, 10.0, 5.0]]))
    with pytest.raises(InfeasibleError, match="cannot fit"):
        closest_admissible(Constraints((0, 0, 5, 5), z_max=3.0, d_safe=4.0), BoxWorld(5.0), np.ones((20, 3)))
    with pytest.raises(InvalidInputError):
        closest_admissible(c, town, np.ones((3, 2)))
    with pytest.raises(InvalidInputError):
        closest_admissible(c, town, np.array([[1.0, np.nan, 3.0]]))


# ---------------------------------------------------------------------------------------------
# On real terrains (the Rust engine)
# ---------------------------------------------------------------------------------------------


def _terrain_or_skip():
    try:
        from uavcov import Terrain
    except ImportError as exc:  # the extension is not built in this environment
        pytest.skip(f"uavcov engine not available: {exc}")
    return Terrain


def test_closest_admissible_and_masks_on_a_real_grid_terrain(hill_grid):
    Terrain = _terrain_or_skip()
    from reference import grid_height

    terrain = Terrain.from_grid(hill_grid.z, hill_grid.spacing, origin=hill_grid.origin)
    c = Constraints.for_world(terrain, h_min=1.5, z_max=25.0, d_safe=1.0)
    rng = np.random.default_rng(11)
    lo = terrain.bounds[0, :2]
    hi = terrain.bounds[1, :2]
    start = np.column_stack([rng.uniform(lo, hi, size=(12, 2)), rng.uniform(-2.0, 12.0, size=12)])
    out = closest_admissible(c, terrain, start)
    ground = grid_height(out[:, :2], hill_grid.z, hill_grid.spacing, hill_grid.origin)
    assert np.all(out[:, 2] >= ground + 1.5 - 1e-9)
    low = start[:, 2] < grid_height(start[:, :2], hill_grid.z, hill_grid.spacing, hill_grid.origin) + 1.5
    # the ones that were too low now sit at h_min (plus the tiny margin), the others kept z
    np.testing.assert_allclose(out[low, 2], ground[low] + 1.5, atol=1e-5)
    np.testing.assert_array_equal(out[~low], start[~low])
    # masks against the definition, with the analytic ground of the grid, for 4 UAVs 1-3 m
    # above h_min and perturbations of 1 m
    current = out[:4] + [0.0, 0.0, 1.0]
    current[:, 2] += rng.uniform(0.0, 2.0, size=4)
    cands = current[None] + rng.normal(scale=1.0, size=(400, 4, 3))
    mask = feasible_mask(c, terrain, current, cands)
    z = cands[..., 2]
    g = grid_height(cands.reshape(-1, 3)[:, :2], hill_grid.z, hill_grid.spacing, hill_grid.origin).reshape(z.shape)
    inside = (cands[..., 0] >= lo[0]) & (cands[..., 0] <= hi[0]) & (cands[..., 1] >= lo[1]) & (cands[..., 1] <= hi[1])
    with np.errstate(invalid="ignore"):
        clear_ok = inside & (z - g >= 1.5) & (z <= 25.0)
    i, j = np.triu_indices(4, 1)
    far = (np.linalg.norm(cands[:, i] - cands[:, j], axis=2) >= 1.0).all(axis=1)
    # leave out candidates within round-off of a boundary of the analytic ground
    decided = (np.isnan(g) | (np.abs(z - g - 1.5) > 1e-7)).all(axis=1)
    expected = clear_ok.all(axis=1) & far
    np.testing.assert_array_equal(mask[decided], expected[decided])
    assert decided.sum() > 390
    assert 40 < mask.sum() < 360


def test_on_a_real_buildings_scene():
    _terrain_or_skip()
    from uavcov.terrain._buildings import Building, buildings_terrain

    scene = buildings_terrain([Building(8.0, 8.0, 14.0, 12.0, 6.0)], size=24.0, spacing=0.5)
    c = Constraints.for_world(scene, h_min=1.0, z_max=20.0, d_safe=1.0, check_moves=True)
    start = np.array([[10.0, 10.0, 3.0], [4.0, 10.0, -1.0], [20.0, 20.0, 4.0]])
    out = closest_admissible(c, scene, start)
    np.testing.assert_allclose(out, [[10.0, 10.0, 7.0], [4.0, 10.0, 1.0], [20.0, 20.0, 4.0]], atol=1e-5)
    current = np.array([[6.0, 10.0, 3.0]])  # 2 m west of the west wall (x = 8)
    cands = np.array(
        [
            [[7.0, 10.0, 3.0]],  # closer to the wall: fine
            [[9.0, 10.0, 3.0]],  # inside the building
            [[9.0, 10.0, 7.2]],  # over the roof, but the move hits the wall (z = 5.8 at x = 8)
            [[6.0, 10.0, 8.0]],  # straight up: fine
        ]
    )
    np.testing.assert_array_equal(feasible_mask(c, scene, current, cands), [True, False, False, True])
    loose = Constraints.for_world(scene, h_min=1.0, z_max=20.0, d_safe=1.0)
    np.testing.assert_array_equal(feasible_mask(loose, scene, current, cands), [True, False, True, True])


class _Unfused:
    """A Terrain seen through the World protocol only: feasible_mask takes its Python path."""

    def __init__(self, terrain):
        self._terrain = terrain
        self.bounds = terrain.bounds

    def ground_height(self, xy, **kwargs):
        return self._terrain.ground_height(xy, **kwargs)

    def clearance(self, points, **kwargs):
        return self._terrain.clearance(points, **kwargs)

    def segments_clear(self, a, b, **kwargs):
        return self._terrain.segments_clear(a, b, **kwargs)


@pytest.mark.parametrize("scene", ["hills", "buildings"])
@pytest.mark.parametrize("h_max, check_moves", [(None, False), (4.0, True), (6.0, False)])
def test_the_fused_rust_check_gives_the_python_checks_answers(scene, h_max, check_moves):
    """Terrain.admissible_mask (one Rust pass) against the separate queries, candidate by candidate."""
    _terrain_or_skip()
    import uavcov
    from uavcov.terrain._buildings import Building, buildings_terrain

    if scene == "hills":
        world = uavcov.gaussian_hills(spacing=2.0, rng=1001)
    else:
        world = buildings_terrain([Building(8.0, 8.0, 14.0, 12.0, 6.0), Building(16.0, 2.0, 20.0, 6.0, 4.0)], size=24.0, spacing=0.5)
    c = Constraints.for_world(world, h_min=1.0, h_max=h_max, z_max=30.0, d_safe=1.5, check_moves=check_moves)
    rng = np.random.default_rng(5)
    lo, hi = world.bounds[0, :2], world.bounds[1, :2]
    start = np.column_stack([rng.uniform(lo, hi, size=(6, 2)), np.full(6, 40.0)])
    start[:, 2] = world.ground_height(start[:, :2]) + 2.5
    current = closest_admissible(c, world, start)
    scales = np.repeat([0.3, 1.5, 4.0, 20.0], 150)[:, None, None]
    cands = current[None] + scales * rng.standard_normal((600, 6, 3))
    cands[:3] = current  # staying
    cands[3, 0, 0] = 1e300  # far outside: refused, not an error
    fused = feasible_mask(c, world, current, cands, n_threads=1)
    separate = feasible_mask(c, _Unfused(world), current, cands, n_threads=1)
    np.testing.assert_array_equal(fused, separate)
    assert 30 < fused.sum() < 570 and fused[:3].all() and not fused[3]
    np.testing.assert_array_equal(feasible_mask(c, world, current, cands, n_threads=2), fused)
    # the optimisers' callable: the limits bound once, the same answers
    np.testing.assert_array_equal(feasibility(c, world, n_threads=1)(current, cands), fused)
    np.testing.assert_array_equal(feasibility(c, _Unfused(world), n_threads=1)(current, cands), fused)


def test_the_fused_check_refuses_bad_limits_with_clear_errors():
    _terrain_or_skip()
    import uavcov

    world = uavcov.gaussian_hills(spacing=5.0, rng=3)
    current = [[50.0, 50.0, 60.0]]
    good = dict(bounds=(0, 0, 100, 100), h_min=1.0, h_max=None, z_max=80.0, d_safe=1.0, check_moves=True)
    assert world.admissible_mask(current, [[50.0, 50.0, 60.0]], **good).dtype == np.bool_
    for change, error in (
        ({"bounds": (0, 0, 100)}, InvalidInputError),
        ({"h_min": math.nan}, InvalidInputError),
        ({"h_max": "high"}, InvalidTypeError),
        ({"z_max": math.inf}, InvalidInputError),
    ):
        with pytest.raises(error):
            world.admissible_mask(current, [[50.0, 50.0, 60.0]], **(good | change))
    with pytest.raises(InvalidInputError):
        world.admissible_mask(current, np.zeros((3, 2)), **good)
    with pytest.raises(InvalidInputError):
        world.admissible_mask([[50.0, 50.0, math.nan]], [[50.0, 50.0, 60.0]], **good)
    # bound once: bad limits fail at binding, bad positions at each call
    with pytest.raises(InvalidInputError):
        world.admissible_check(**(good | {"d_safe": -math.inf}))
    check = world.admissible_check(**good)
    assert check(current, [[50.0, 50.0, 60.0], [50.0, 50.0, 200.0]]).tolist() == [True, False]
    for cur, cand in (([[50.0, 50.0, 60.0]], [[50.0, math.nan, 60.0]]), ([], [[50.0, 50.0, 60.0]]), (current, np.zeros((1, 2, 3)))):
        with pytest.raises(InvalidInputError):
            check(cur, cand)
    with pytest.raises(InvalidTypeError):
        check(current, "candidates")
