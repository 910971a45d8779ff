"""Metric facts of the track geometry (no rendering)."""

import math
import os

import numpy as np
import pytest
import yaml

from conde_worlds import track_geometry as tg
from conde_worlds.track_files import GEOMETRY_FILE, geometry_yaml

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOL = 1e-9


@pytest.fixture(scope="module")
def track():
    return tg.build_track()


@pytest.fixture(scope="module")
def lanes(track):
    return track.lane_centres(spacing=0.01)


def angle_diff(a, b):
    return abs((a - b + math.pi) % (2 * math.pi) - math.pi)


# --- measured dimensions of the straight ------------------------------------------------------

def test_straight_lines_as_measured():
    west = (tg.X_REF - tg.LINE_SPACING - tg.SOLID_WIDTH / 2, tg.X_REF - tg.LINE_SPACING + tg.SOLID_WIDTH / 2)
    centre = (tg.X_REF - tg.DASHED_WIDTH / 2, tg.X_REF + tg.DASHED_WIDTH / 2)
    east = (tg.X_REF + tg.LINE_SPACING - tg.SOLID_WIDTH / 2, tg.X_REF + tg.LINE_SPACING + tg.SOLID_WIDTH / 2)
    np.testing.assert_allclose(west, (0.929, 1.014), atol=1e-3)
    np.testing.assert_allclose(centre, (1.760, 1.796), atol=1e-3)
    np.testing.assert_allclose(east, (2.542, 2.626), atol=1e-3)
    assert tg.LANE_WIDTH == pytest.approx(0.746, abs=1e-6)
    assert tg.X_REF + tg.LANE_OFFSET == pytest.approx(2.169, abs=1e-3)  # northbound lane centre
    assert tg.X_REF - tg.LANE_OFFSET == pytest.approx(1.387, abs=1e-3)  # southbound lane centre
    assert tg.DASH_ON + tg.DASH_OFF == pytest.approx(0.348)


# --- loops -----------------------------------------------------------------------------------

def test_loop_dimensions():
    outer = tg.LOOP_RADIUS + tg.LINE_SPACING + tg.SOLID_WIDTH / 2
    assert 2.9 <= outer <= 3.2
    assert -0.4 <= tg.LOOP_CENTRE_X <= -0.2
    assert 5.1 <= tg.LOOP_CENTRE_Y <= 5.3
    # West side at y = loop centre: outer line -3.429..-3.338, dashed -2.598..-2.556,
    # island line -1.817..-1.725 (measured).
    cx = tg.LOOP_CENTRE_X
    assert cx - tg.LOOP_RADIUS - tg.LINE_SPACING == pytest.approx((-3.429 - 3.338) / 2, abs=0.01)
    assert cx - tg.LOOP_RADIUS == pytest.approx((-2.598 - 2.556) / 2, abs=0.01)
    assert cx - tg.LOOP_RADIUS + tg.LINE_SPACING == pytest.approx((-1.817 - 1.725) / 2, abs=0.01)
    # Island x extent (outer edges of its line): -1.817 .. 1.014; top 6.607 (north loop).
    island_r = tg.LOOP_RADIUS - tg.LINE_SPACING + tg.SOLID_WIDTH / 2
    assert cx - island_r == pytest.approx(-1.817, abs=0.01)
    assert tg.X_REF - tg.LINE_SPACING + tg.SOLID_WIDTH / 2 == pytest.approx(1.014, abs=1e-3)
    assert tg.LOOP_CENTRE_Y + island_r == pytest.approx(6.607, abs=0.07)
    # Drawing extent: x -3.429, y +-8.3 (within the 16.7 m floor).
    assert cx - outer == pytest.approx(-3.429, abs=0.01)
    assert tg.LOOP_CENTRE_Y + outer == pytest.approx(8.3, abs=0.03)
    assert tg.LOOP_CENTRE_Y + outer < 8.35


def test_forks_merge_at_about_two_metres():
    assert 2.0 < tg.FORK_Y < 2.2


def _check_g1(prims, closed=False):
    pairs = list(zip(prims[:-1], prims[1:]))
    if closed:
        pairs.append((prims[-1], prims[0]))
    for a, b in pairs:
        np.testing.assert_allclose(a.point(a.length), b.point(0.0), atol=1e-9)
        assert angle_diff(float(a.heading(a.length)), float(b.heading(0.0))) < 1e-9


def test_roads_are_g1_and_join_the_straight(track):
    central = track.roads["central"].path
    for name, sign in (("north_loop", 1), ("south_loop", -1)):
        path = track.roads[name].path
        _check_g1(path.prims)
        start, end = path.prims[0], path.prims[-1]
        # Starts where the straight ends, continuing it.
        np.testing.assert_allclose(start.point(0.0), (tg.X_REF, sign * tg.LOOP_CENTRE_Y), atol=TOL)
        assert angle_diff(float(start.heading(0.0)), sign * math.pi / 2) < TOL
        # Ends tangentially on the straight at the fork, heading back toward the crosswalk.
        np.testing.assert_allclose(end.point(end.length), (tg.X_REF, sign * tg.FORK_Y), atol=TOL)
        assert angle_diff(float(end.heading(end.length)), -sign * math.pi / 2) < TOL
    np.testing.assert_allclose(central.point(np.array([central.length]))[0], (tg.X_REF, tg.LOOP_CENTRE_Y), atol=TOL)


def test_south_loop_is_the_mirror_of_the_north_loop(track):
    n, s = track.roads["north_loop"].path, track.roads["south_loop"].path
    t = np.linspace(0, n.length, 500)
    np.testing.assert_allclose(s.point(t), n.point(t) * [1, -1], atol=1e-9)


def test_radii_leave_room_for_constant_width_lines(track):
    for road in track.roads.values():
        for p in road.path.prims:
            if p.kind == "arc":
                assert p.radius - tg.LINE_SPACING - tg.SOLID_WIDTH / 2 > 0.1


# --- lane centres ----------------------------------------------------------------------------

def test_lane_centres_closed_and_continuous(lanes):
    assert set(lanes) == {"north_ccw", "north_cw"}
    for name, lc in lanes.items():
        xy = lc["xy"]
        steps = np.hypot(*np.diff(np.vstack([xy, xy[:1]]), axis=0).T)  # includes the closing step
        assert steps.max() <= 0.06, name
        assert steps.max() <= 0.0100001
        assert lc["length"] == pytest.approx(steps.sum(), rel=1e-4)
        # Smooth: heading changes at most by step / smallest lane radius between samples.
        dh = [angle_diff(a, b) for a, b in zip(lc["heading"], np.roll(lc["heading"], -1))]
        assert max(dh) < 0.0100001 / (tg.FORK_RADIUS - tg.LANE_OFFSET) + 1e-6


def test_lane_centres_inside_the_road(track, lanes):
    clear = tg.LINE_SPACING - tg.SOLID_WIDTH / 2
    for lc in lanes.values():
        assert track.on_road(lc["xy"]).all()
        assert track.on_road(lc["xy"], half_width=clear).all()
        assert not track.in_parallel_parking(lc["xy"]).any()


def test_lane_centres_start_northbound_in_the_east_lane(lanes):
    for lc in lanes.values():
        np.testing.assert_allclose(lc["xy"][0], (tg.X_REF + tg.LANE_OFFSET, 0.0), atol=1e-9)
        assert lc["heading"][0] == pytest.approx(math.pi / 2)


def test_lane_routes_drive_the_loops_in_opposite_senses(lanes):
    def signed_area(xy):
        m = xy[:, 1] > tg.FORK_Y  # the part in the north loop
        p = xy[m]
        return 0.5 * np.sum(p[:-1, 0] * p[1:, 1] - p[1:, 0] * p[:-1, 1])
    # Traversal of the north loop: counter-clockwise for north_ccw, clockwise for north_cw.
    ccw = lanes["north_ccw"]
    cw = lanes["north_cw"]

    def in_loop(lc):  # west side of north loop
        return (lc["xy"][:, 0] < 0.5) & (lc["xy"][:, 1] > 5.0)

    h_ccw = np.mean(np.sin(ccw["heading"][in_loop(ccw)]))
    h_cw = np.mean(np.sin(cw["heading"][in_loop(cw)]))
    assert h_ccw < -0.2 and h_cw > 0.2  # CCW goes south on the west side, CW goes north
    assert ccw["length"] == pytest.approx(cw["length"], abs=1e-6)


def test_section_labels(track, lanes):
    for lc in lanes.values():
        sec = np.array(lc["section"])
        assert set(sec) == {"straight", "curve", "crosswalk"}
        xy = lc["xy"]
        cw = sec == "crosswalk"
        assert np.all((xy[cw, 1] >= -0.340) & (xy[cw, 1] <= 0.252))
        # Both lanes cross the crosswalk once: 2 x 0.592 m.
        assert cw.sum() * 0.01 == pytest.approx(2 * 0.592, abs=0.03)
        # Curves: the loop arcs and the fork arcs; the straight is straight.
        on_straight = (np.abs(xy[:, 0] - tg.X_REF) < 0.5) & (np.abs(xy[:, 1]) < tg.FORK_Y - 0.01)
        assert np.all(sec[on_straight] != "curve")
        r = np.hypot(xy[:, 0] - tg.LOOP_CENTRE_X, np.abs(xy[:, 1]) - tg.LOOP_CENTRE_Y)
        west_half = xy[:, 0] < tg.LOOP_CENTRE_X
        assert np.all(sec[west_half] == "curve")
        assert np.all(np.isclose(r[west_half], tg.LOOP_RADIUS + tg.LANE_OFFSET)
                      | np.isclose(r[west_half], tg.LOOP_RADIUS - tg.LANE_OFFSET))


# --- lateral distance ------------------------------------------------------------------------

def test_lateral_zero_on_lane_centres(track, lanes):
    for lc in lanes.values():
        res = track.locate(lc["xy"])
        assert np.abs(res["lateral"]).max() < 1e-9
        assert res["on_road"].all()
        ok = [angle_diff(a, b) < 1e-6 for a, b in zip(res["heading"], lc["heading"])]
        assert all(ok)


def test_lateral_near_the_lines_on_the_straight(track):
    y = -2.0
    e, w = tg.X_REF + tg.LANE_OFFSET, tg.X_REF - tg.LANE_OFFSET
    cases = [
        ((e + 0.375, y), -0.375),  # northbound, toward the east line (right of travel)
        ((e - 0.375, y), +0.375),  # northbound, toward the dashed line (left)
        ((w - 0.375, y), -0.375),  # southbound, toward the west line (its right)
        ((w + 0.375, y), +0.375),  # southbound, toward the dashed line (its left)
        ((tg.X_REF, y), tg.LANE_OFFSET),  # on the centre line: left of both lanes
        ((tg.X_REF + tg.LINE_SPACING, y), tg.LANE_OFFSET - tg.LINE_SPACING),
    ]
    for (x, yy), expected in cases:
        lat, on = track.lateral_offset(x, yy)
        assert lat == pytest.approx(expected, abs=1e-9), (x, yy)
        assert on


def test_lateral_near_the_lines_on_a_loop(track):
    cx, cy = tg.LOOP_CENTRE_X, tg.LOOP_CENTRE_Y
    for sign in (1, -1):
        for r, expected in ((tg.LOOP_RADIUS + tg.LANE_OFFSET + 0.375, -0.375),
                            (tg.LOOP_RADIUS + tg.LANE_OFFSET - 0.375, 0.375),
                            (tg.LOOP_RADIUS - tg.LANE_OFFSET - 0.375, -0.375),
                            (tg.LOOP_RADIUS - tg.LANE_OFFSET + 0.375, 0.375)):
            res = track.locate([[cx - r, sign * cy]])
            assert res["lateral"][0] == pytest.approx(expected, abs=1e-9)
            assert res["section"][0] == "curve"
            assert res["on_road"][0]


def test_locate_reports_heading_and_section(track):
    res = track.locate([[2.169, -1.0], [1.387, -1.0], [2.169, 0.0], [1.387, 3.0]])
    assert angle_diff(res["heading"][0], math.pi / 2) < 1e-9
    assert angle_diff(res["heading"][1], -math.pi / 2) < 1e-9
    assert list(res["section"]) == ["straight", "straight", "crosswalk", "straight"]


def test_on_road_and_areas(track):
    off = [(-0.4, 5.25), (-0.4, -5.25), (-3.3, 0.0), (0.5, 0.0), (3.4, -2.3), (3.0, 2.5), (0.0, 8.34)]
    assert not track.on_road(off).any()
    on = [(1.778, 0.0), (0.93, -1.0), (2.62, 3.0), (-3.38, 5.25), (-0.4, 3.07), (0.9, 2.5)]
    assert track.on_road(on).all()
    assert track.in_parallel_parking([(3.0, 2.5), (3.0, 1.0), (3.0, 4.5)]).all()
    assert not track.in_parallel_parking([(3.0, 0.5), (3.0, 4.9), (2.5, 2.5), (3.45, 2.5)]).any()
    assert track.in_bay([(3.4, -1.9)], "north")[0] and track.in_bay([(3.4, -2.7)], "south")[0]
    assert not track.in_bay([(3.4, -2.7)], "north")[0]


def test_on_road_skipping_far_primitives_decides_as_every_primitive(track):
    """Road.contains skips the primitives whose box is away from the points: footprint-sized
    clusters all over the track, many across the road's edges, get the answers of a check that
    projects on every primitive."""
    rng = np.random.default_rng(3)
    half = track.dims.road_half_width_m
    for _ in range(400):
        centre = rng.uniform((-4.0, -9.0), (4.0, 9.0))
        pts = centre + rng.uniform(-0.3, 0.3, size=(60, 2))
        every = np.zeros(len(pts), dtype=bool)
        for road in track.roads.values():
            for prim in road.path.prims:
                s, lat = prim.project(pts)
                every |= (s >= -1e-9) & (s <= prim.length + 1e-9) & (np.abs(lat) <= half)
        assert np.array_equal(track.on_road(pts), every)


def test_spawns_in_the_northbound_lane(track):
    for name, (x, y, z, yaw) in tg.SPAWNS.items():
        res = track.locate([[x, y]])
        assert res["on_road"][0], name
        assert abs(res["lateral"][0]) < 0.05, name
        assert angle_diff(res["heading"][0], yaw) < 1e-3, name
    # Conde: model origin (2.14, -0.5) + 0.17 m to the axle.
    assert tg.SPAWNS["conde"][:2] == (2.14, -0.33)


# --- painted strokes -------------------------------------------------------------------------

def test_dash_intervals():
    d = tg.dash_intervals(0.0, 1.0)
    assert d[0] == (0.0, 0.2) and d[1] == pytest.approx((0.348, 0.548))
    g = tg.dash_intervals(0.0, 1.0, phase=tg.DASH_ON)  # gap first
    assert g[0] == pytest.approx((0.148, 0.348))


def test_no_line_crosses_a_lane_centre(track, lanes):
    """Painted strokes other than the crosswalk keep > 0.3 m away from the lane centres."""
    for lc in lanes.values():
        pts = lc["xy"]
        for st in track.strokes:
            if st.name.startswith("crosswalk"):
                continue
            s, lat = st.prim.project(pts)
            vis = np.zeros(len(pts), dtype=bool)
            for a, b in st.intervals:
                vis |= (s >= a - st.width / 2) & (s <= b + st.width / 2)
            clearance = np.abs(lat[vis]) - st.width / 2
            if clearance.size:
                assert clearance.min() > 0.3, st.name


def test_island_tip_is_where_the_lines_meet(track):
    tips = [d for d in track.dots if "island_tip" in d.name]
    assert len(tips) == 2
    for d in tips:
        # On the straight's west line and on the fork arc's island-side line.
        assert d.centre[0] == pytest.approx(tg.X_REF - tg.LINE_SPACING)
        c2 = (tg.X_REF - tg.FORK_RADIUS, math.copysign(tg.FORK_Y, d.centre[1]))
        assert math.hypot(d.centre[0] - c2[0], d.centre[1] - c2[1]) == pytest.approx(tg.FORK_RADIUS + tg.LINE_SPACING)


# --- the committed geometry file -------------------------------------------------------------

def test_geometry_file_is_up_to_date(track):
    with open(os.path.join(PACKAGE_DIR, GEOMETRY_FILE)) as f:
        committed = f.read()
    assert committed == geometry_yaml(track), "run scripts/generate_track and commit the result"
    assert geometry_yaml(tg.build_track()) == committed  # deterministic


def test_geometry_file_contents():
    with open(os.path.join(PACKAGE_DIR, GEOMETRY_FILE)) as f:
        data = yaml.safe_load(f)
    assert data["format"] == "conde_track_geometry/1"
    assert {lane["name"] for lane in data["lane_centres"]} == {"north_ccw", "north_cw"}
    for lc in data["lane_centres"]:
        xy = np.array(lc["xy"])
        assert len(xy) == len(lc["section"]) == len(lc["heading_rad"])
        steps = np.hypot(*np.diff(np.vstack([xy, xy[:1]]), axis=0).T)
        assert steps.max() <= 0.0502 and steps.min() >= 0.0497
    assert data["crosswalk"]["stripe_centres_x_m"] == list(tg.CROSSWALK_STRIPE_X)
    assert [b["name"] for b in data["bay_parking"]["bays"]] == ["north", "south"]
    assert data["spawn"]["conde"] == {"xyz": [2.14, -0.33, 0.0], "yaw": 1.5708}
    assert data["texture"]["x_range_m"] == [-3.475, 3.975]


def test_on_road_of_points_with_nan_keeps_the_finite_ones(track):
    """A point with a NaN coordinate is on no road; the others are judged as without it."""
    x = track.dims.road_half_width_m * 0.0 + 1.778
    pts = np.array([[x, 0.0], [np.nan, np.nan], [x + 0.1, 1.0], [np.nan, 0.0]])
    assert track.on_road(pts).tolist() == [True, False, True, False]
    assert not track.on_road(np.full((3, 2), np.nan)).any()
