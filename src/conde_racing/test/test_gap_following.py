"""The follow-the-gap driver (conde_racing.gap_following) on synthetic scans cast in small 2D
worlds, and around the racetrack with a kinematic bicycle."""

import math

import numpy as np
import pytest

from conde_racing import racetrack as rt
from conde_racing.gap_following import Decision, GapFollower, GapFollowerConfig
from planar_world import Bicycle, box_segments, cast, racetrack_segments

CONFIG = GapFollowerConfig()
ANGLE_MIN = -2.35619449
ANGLES = np.linspace(ANGLE_MIN, -ANGLE_MIN, 1081)
INCREMENT = ANGLES[1] - ANGLES[0]


def corridor(half_width=0.7, length=20.0, x0=-2.0):
    """Walls along x at y = +-half_width."""
    return np.array([[x0, half_width, x0 + length, half_width], [x0, -half_width, x0 + length, -half_width]])


def scan_from(segments, x=0.0, y=0.0, yaw=0.0):
    """The LiDAR's ranges for a car whose base_footprint is at (x, y, yaw)."""
    return cast(segments, (x + CONFIG.laser_x_m * math.cos(yaw), y + CONFIG.laser_x_m * math.sin(yaw)), yaw, ANGLES)


def decide(ranges, time_s=0.0, driver=None):
    return (driver or GapFollower()).decide(ranges, ANGLE_MIN, INCREMENT, time_s)


def test_straight_corridor_full_speed_straight_ahead():
    d = decide(scan_from(corridor()))
    assert abs(d.steering_rad) < 0.01
    assert d.speed_mps == pytest.approx(CONFIG.max_speed_mps)
    assert not d.reversing


@pytest.mark.parametrize("offset_m", [0.3, -0.3])
def test_off_centre_steers_back_to_the_middle(offset_m):
    d = decide(scan_from(corridor(), y=offset_m))
    assert -math.copysign(1, offset_m) * d.steering_rad > 0.005, d


def test_open_space_drives_straight():
    d = decide(np.full(1081, np.inf))
    assert d.steering_rad == pytest.approx(0.0, abs=1e-9) and d.speed_mps == CONFIG.max_speed_mps
    assert d.clearance_m == pytest.approx(CONFIG.max_range_m + CONFIG.laser_x_m - CONFIG.nose_x_m, abs=0.01)


@pytest.mark.parametrize("side", [1, -1])
def test_corner_turns_into_the_open_side_and_slows(side):
    # a corridor along +x that ends in a wall at x = 2.5 and turns to the left (side 1) or right
    w = 0.7
    walls = [[-2, -side * w, 2.5, -side * w],        # outer wall, continues into the end wall
             [2.5, -side * w, 2.5, side * 10],
             [-2, side * w, 1.1, side * w],          # inner wall ends at the corner
             [1.1, side * w, 1.1, side * 10]]
    d = decide(scan_from(np.array(walls, dtype=float), x=0.5))
    assert side * d.steering_rad > 0.1, d
    assert side * d.target_angle_rad > 0.3
    straight = decide(scan_from(corridor(), x=0.5))
    assert d.speed_mps < straight.speed_mps


def test_disparity_extension_keeps_clear_of_an_edge():
    # a box in the corridor, on the right: the target passes it on the left with the car's
    # half width plus the margin between the target beam and the box's edge
    walls = np.vstack([corridor(1.2), box_segments(3.0, -0.5, 0.4, 1.4)])
    driver = GapFollower()
    ranges = driver.clean_ranges(scan_from(walls))
    extended = driver.extend_disparities(ranges, INCREMENT)
    assert (extended <= ranges + 1e-12).all()
    assert (extended < ranges - 0.1).sum() > 10
    d = driver.decide(scan_from(walls), ANGLE_MIN, INCREMENT, 0.0)
    assert d.steering_rad > 0.02
    # the target beam passes the box's near left corner (3 - 0.2 - 0.27, 0.2) at a lateral
    # distance of at least the car's half width
    corner = np.array([3.0 - 0.2 - CONFIG.laser_x_m, 0.2])
    direction = np.array([math.cos(d.target_angle_rad), math.sin(d.target_angle_rad)])
    lateral = abs(np.cross(direction, corner))
    assert lateral >= CONFIG.car_half_width_m


def test_blocked_backs_up_steering_away_then_drives_again():
    driver = GapFollower()
    # a wall 0.05 m ahead of the nose, the open side to the left
    wall_x = CONFIG.nose_x_m + 0.05
    walls = np.array([[wall_x, -5.0, wall_x, 0.3], [wall_x, 0.3, 10.0, 0.3], [-2.0, -0.7, wall_x, -0.7]])
    ranges = scan_from(walls)
    first = driver.decide(ranges, ANGLE_MIN, INCREMENT, 10.0)
    assert first.reversing and first.speed_mps == -CONFIG.reverse_speed_mps
    assert first.clearance_m == pytest.approx(0.05, abs=0.01)
    assert first.steering_rad == -CONFIG.max_steering_rad       # open on the left: wheels right
    # it keeps backing up for reverse_time_s, whatever it sees
    assert driver.decide(np.full(1081, np.inf), ANGLE_MIN, INCREMENT, 10.0 + CONFIG.reverse_time_s - 0.01).reversing
    after = driver.decide(np.full(1081, np.inf), ANGLE_MIN, INCREMENT, 10.0 + CONFIG.reverse_time_s)
    assert not after.reversing and after.speed_mps > 0


def test_a_wall_close_beside_the_car_is_not_an_obstacle_ahead():
    # 0.02 m from the car's right side, along its whole length and beyond
    walls = np.array([[-1.0, -CONFIG.car_half_width_m - 0.02, 0.3, -CONFIG.car_half_width_m - 0.02]])
    d = decide(scan_from(walls))
    assert not d.reversing and d.clearance_m > 1.0
    # the same wall reaching ahead of the nose, turning across the path 0.3 m ahead, is one
    across = np.vstack([walls, [[0.3, -CONFIG.car_half_width_m - 0.02, CONFIG.nose_x_m + 0.3, 0.5]]])
    d = decide(scan_from(across))
    assert d.clearance_m < 0.3


def test_speed_limits():
    driver = GapFollower()
    assert driver.speed_for(0.0, 10.0) == CONFIG.max_speed_mps
    # full lock: lateral acceleration limit
    curvature = math.tan(CONFIG.max_steering_rad) / CONFIG.wheelbase_m
    assert driver.speed_for(CONFIG.max_steering_rad, 10.0) == pytest.approx(
        math.sqrt(CONFIG.max_lateral_accel_mps2 / curvature))
    # braking distance to an obstacle ahead, never below the minimum speed
    assert driver.speed_for(0.0, CONFIG.stop_distance_m + 0.3) == pytest.approx(
        math.sqrt(2 * CONFIG.braking_decel_mps2 * 0.3))
    assert driver.speed_for(0.0, CONFIG.stop_distance_m) == CONFIG.min_speed_mps


def test_pure_pursuit_geometry():
    driver = GapFollower()
    # a point straight to the left of the rear axle at the lookahead distance needs the
    # circle through it: radius R = (x^2 + y^2) / (2 y)
    steering = driver.steering_to(math.pi / 2, 10.0)
    x, y = CONFIG.laser_x_m, CONFIG.lookahead_m
    expected = math.atan(CONFIG.wheelbase_m * 2 * y / (x * x + y * y))
    assert steering == pytest.approx(min(expected, CONFIG.max_steering_rad))
    assert driver.steering_to(-0.2, 10.0) == pytest.approx(-driver.steering_to(0.2, 10.0))


def test_nan_and_negative_ranges():
    ranges = scan_from(corridor())
    ranges[::7] = np.nan
    ranges[3] = -np.inf
    d = decide(ranges)
    assert isinstance(d, Decision) and math.isfinite(d.steering_rad) and abs(d.steering_rad) < 0.05


@pytest.mark.parametrize("field, value", [("max_speed_mps", 0.0), ("lookahead_m", -1.0),
                                          ("wheelbase_m", math.nan), ("min_speed_mps", 5.0)])
def test_bad_config(field, value):
    with pytest.raises(ValueError, match=field):
        GapFollowerConfig(**{field: value})


def test_laps_the_racetrack_with_a_kinematic_car():
    """From the pole, the driver laps the racetrack in a kinematic simulation (a bicycle whose
    speed and steering lag their commands, a 541-beam scan at 40 Hz cast against the walls)
    without touching a wall and without backing up."""
    line = rt.CentreLine()
    walls = racetrack_segments(line, 0.2)
    angles = np.linspace(ANGLE_MIN, -ANGLE_MIN, 541)
    driver = GapFollower()
    pole = rt.grid_poses(line)[0]
    car = Bicycle(pole.x_m, pole.y_m, pole.yaw_rad)
    dt, scan_period_steps = 0.001, 25
    s_last, travelled, closest_wall_m, reversing = line.project(car.x, car.y)[0], 0.0, math.inf, 0
    for k in range(int(30.0 / dt)):
        if k % scan_period_steps == 0:
            lx, ly = car.x + CONFIG.laser_x_m * math.cos(car.yaw), car.y + CONFIG.laser_x_m * math.sin(car.yaw)
            d = driver.decide(cast(walls, (lx, ly), car.yaw, angles), ANGLE_MIN, angles[1] - angles[0], k * dt)
            reversing += d.reversing
            s, _ = line.project(car.x, car.y)
            travelled += (s - s_last + line.length_m / 2) % line.length_m - line.length_m / 2
            s_last = s
            for corner in car.corners():
                closest_wall_m = min(closest_wall_m, rt.HALF_WIDTH_M - abs(line.project(*corner)[1]))
            if travelled > line.length_m:
                break
        car.step(d.speed_mps, d.steering_rad, dt)
    lap_time_s = k * dt
    assert travelled > line.length_m, "travelled %.1f m in %.1f s" % (travelled, lap_time_s)
    assert reversing == 0
    assert closest_wall_m > 0.02
    # at most 2 m/s, a little slower in the turns; on the inside of every turn (4 pi of turning
    # in all), 0.55 m from the centre line, a lap is 0.55 m x 4 pi shorter than the centre line
    assert (line.length_m - 0.55 * 4 * math.pi) / CONFIG.max_speed_mps < lap_time_s < 25.0
