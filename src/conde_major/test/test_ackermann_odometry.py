"""Wheel odometry from joint states (conde_major/ackermann_odometry.py): the curvature from the
hinges inverts ackermann_targets' geometry; a circle, a straight line and reverse driving are
integrated exactly; bad input and a clock reset."""

import math

import pytest

from conde_major.ackermann_odometry import AckermannOdometry, curvature_from_hinges
from conde_major.ackermann_targets import CarGeometry, wheel_targets

L_M, D_M, R_M = 0.32, 0.125, 0.05
MAJOR = CarGeometry(L_M, D_M, R_M, R_M, R_M, R_M, max_steering_rad=0.623)


@pytest.mark.parametrize('delta', [0.0, 0.3, -0.3, 0.6, -0.05])
def test_the_curvature_of_the_hinges_is_the_commanded_one(delta):
    t = wheel_targets(MAJOR, 0.5, delta)
    assert curvature_from_hinges(t.left_steering_rad, t.right_steering_rad, L_M, D_M) == \
        pytest.approx(math.tan(delta) / L_M, abs=1e-12)


def drive(odometry, speed_mps, delta, seconds, dt_s=1 / 30, start_s=0.0):
    """Feeds joint states of the car driving the rear-axle centre at speed_mps with steering delta."""
    t = wheel_targets(MAJOR, speed_mps, delta)
    left = right = 0.0
    steps = round(seconds / dt_s)
    for i in range(steps + 1):
        odometry.update(start_s + i * dt_s, left, right, t.left_steering_rad, t.right_steering_rad)
        left += t.left_rear_radps * dt_s
        right += t.right_rear_radps * dt_s
    return steps * dt_s


@pytest.mark.parametrize('speed', [0.5, -0.3])
def test_a_circle(speed):
    odo = AckermannOdometry(L_M, D_M, R_M)
    delta = 0.3
    k = math.tan(delta) / L_M
    seconds = drive(odo, speed, delta, 3.0)
    s = speed * seconds
    assert odo.pose.yaw_rad == pytest.approx(math.atan2(math.sin(s * k), math.cos(s * k)), abs=1e-9)
    assert odo.pose.x_m == pytest.approx(math.sin(s * k) / k, abs=1e-9)
    assert odo.pose.y_m == pytest.approx((1 - math.cos(s * k)) / k, abs=1e-9)
    assert odo.travelled_m == pytest.approx(abs(s))
    assert odo.speed_mps == pytest.approx(speed)
    assert odo.yaw_rate_radps == pytest.approx(speed * k)


def test_a_straight_line():
    odo = AckermannOdometry(L_M, D_M, R_M)
    drive(odo, 0.4, 0.0, 2.0)
    assert (odo.pose.x_m, odo.pose.y_m, odo.pose.yaw_rad) == pytest.approx((0.8, 0.0, 0.0), abs=1e-12)


def test_bad_values_are_refused_and_a_clock_reset_restarts():
    odo = AckermannOdometry(L_M, D_M, R_M)
    drive(odo, 0.5, 0.2, 1.0, start_s=10.0)
    assert odo.update(12.0, float('nan'), 0.0, 0.0, 0.0) is False
    moved = odo.pose.x_m
    assert moved > 0.4
    assert odo.update(1.0, 0.0, 0.0, 0.0, 0.0) is True  # time went back: a reset
    assert (odo.pose.x_m, odo.pose.y_m, odo.travelled_m) == (0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match='wheelbase_m'):
        AckermannOdometry(0.0, D_M, R_M)
