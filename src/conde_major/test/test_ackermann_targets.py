"""The Ackermann targets of major_ackermann_controller (conde_major/ackermann_targets.py): the
hinge angles and wheel speeds against the original's formulas written with the turning radius R
(the original ackermann_controller's), the geometry behind them, the rate limits and the timeout."""

import math

import pytest

from conde_major.ackermann_targets import (AckermannFollower, CarGeometry, limit_rate, max_centre_steering_rad,
                                           wheel_targets)

L_M, D_M, R_WHEEL_M = 0.32, 0.125, 0.05  # Major Alvega
HINGE_LIMIT_RAD = 0.785398
MAJOR = CarGeometry(L_M, D_M, R_WHEEL_M, R_WHEEL_M, R_WHEEL_M, R_WHEEL_M,
                    max_steering_rad=max_centre_steering_rad(L_M, D_M, HINGE_LIMIT_RAD))


def original_formulas(v, delta, L=L_M, d=D_M, r=R_WHEEL_M):
    """§2.5, with R = L / tan(delta) (delta != 0)."""
    R = L / math.tan(delta)
    return (math.atan(L / (R - d)), math.atan(L / (R + d)),
            v * math.sqrt((R - d) ** 2 + L ** 2) / (abs(R) * r), v * math.sqrt((R + d) ** 2 + L ** 2) / (abs(R) * r),
            v * (R - d) / (R * r), v * (R + d) / (R * r))


def as_tuple(t):
    return (t.left_steering_rad, t.right_steering_rad, t.left_front_radps, t.right_front_radps, t.left_rear_radps,
            t.right_rear_radps)


@pytest.mark.parametrize('v', [0.5, -0.3, 1.2])
@pytest.mark.parametrize('delta', [0.3, -0.3, 0.05, -0.6, 0.6])
def test_targets_are_the_originals_formulas(v, delta):
    assert as_tuple(wheel_targets(MAJOR, v, delta)) == pytest.approx(original_formulas(v, delta), rel=1e-12)


def test_the_numbers_for_half_a_metre_per_second_at_0_3_rad():
    t = wheel_targets(MAJOR, 0.5, 0.3)
    # R = 0.32 / tan(0.3) = 1.034473 m
    assert t.left_steering_rad == pytest.approx(0.338324, abs=1e-6)
    assert t.right_steering_rad == pytest.approx(0.269284, abs=1e-6)
    assert t.left_rear_radps == pytest.approx(10 * (1.034473 - 0.125) / 1.034473, abs=1e-5)
    assert t.right_rear_radps == pytest.approx(10 * (1.034473 + 0.125) / 1.034473, abs=1e-5)
    assert t.left_front_radps == pytest.approx(10 * math.hypot(1.034473 - 0.125, 0.32) / 1.034473, abs=1e-5)


def test_straight_ahead_all_wheels_at_v_over_r_and_no_steering():
    t = wheel_targets(MAJOR, 0.4, 0.0)
    assert as_tuple(t) == pytest.approx((0, 0, 8, 8, 8, 8))
    assert as_tuple(wheel_targets(MAJOR, 0.0, 0.3))[2:] == (0, 0, 0, 0)  # standing, wheels turned


def test_each_wheel_points_at_the_turning_centre_and_rolls_at_its_distance_from_it():
    delta = 0.4
    R = L_M / math.tan(delta)  # centre at (0, R) from the rear-axle centre
    t = wheel_targets(MAJOR, 0.5, delta)
    yaw_rate = 0.5 / R
    front = {'left': (L_M, D_M, t.left_steering_rad, t.left_front_radps),
             'right': (L_M, -D_M, t.right_steering_rad, t.right_front_radps)}
    for x, y, angle, speed in front.values():
        # The wheel's axle line through (x, y) at `angle` meets the rear-axle line at y = R.
        assert y + x / math.tan(angle) == pytest.approx(R)
        assert speed * R_WHEEL_M == pytest.approx(yaw_rate * math.hypot(x, R - y))
    assert t.left_rear_radps * R_WHEEL_M == pytest.approx(yaw_rate * (R - D_M))
    assert t.right_rear_radps * R_WHEEL_M == pytest.approx(yaw_rate * (R + D_M))
    assert t.left_steering_rad > t.right_steering_rad > 0  # the inner wheel turns more


def test_mirror_and_reverse():
    left, right = wheel_targets(MAJOR, 0.5, 0.3), wheel_targets(MAJOR, 0.5, -0.3)
    assert (right.left_steering_rad, right.right_steering_rad) == pytest.approx(
        (-left.right_steering_rad, -left.left_steering_rad))
    assert (right.left_rear_radps, right.left_front_radps) == pytest.approx(
        (left.right_rear_radps, left.right_front_radps))
    back = wheel_targets(MAJOR, -0.5, 0.3)
    assert as_tuple(back)[:2] == as_tuple(left)[:2]
    assert as_tuple(back)[2:] == pytest.approx([-s for s in as_tuple(left)[2:]])


def test_steering_is_limited_so_that_the_inner_hinge_stays_within_its_limit():
    # 45 degree hinges, L 0.32, d 0.125: the centre angle tops at atan(0.32 / 0.445)
    assert MAJOR.max_steering_rad == pytest.approx(math.atan(L_M / (L_M / math.tan(HINGE_LIMIT_RAD) + D_M)))
    assert MAJOR.max_steering_rad == pytest.approx(0.623431, abs=1e-6)
    at_limit = wheel_targets(MAJOR, 0.5, MAJOR.max_steering_rad)
    assert at_limit.left_steering_rad == pytest.approx(HINGE_LIMIT_RAD)
    assert as_tuple(wheel_targets(MAJOR, 0.5, 1.2)) == pytest.approx(as_tuple(at_limit))
    assert wheel_targets(MAJOR, 0.5, -1.2).right_steering_rad == pytest.approx(-HINGE_LIMIT_RAD)


def test_each_wheel_uses_its_own_radius():
    g = CarGeometry(L_M, D_M, 0.05, 0.1, 0.025, 0.05)
    t = wheel_targets(g, 1.0, 0.0)
    assert (t.left_front_radps, t.right_front_radps, t.left_rear_radps, t.right_rear_radps) == pytest.approx(
        (20, 10, 40, 20))


@pytest.mark.parametrize('field, value', [('wheelbase_m', 0.0), ('half_track_m', -0.1),
                                          ('left_rear_radius_m', math.nan),
                                          ('max_steering_rad', 2.0)])
def test_geometry_rejects_impossible_values_naming_the_field(field, value):
    values = dict(wheelbase_m=L_M, half_track_m=D_M, left_front_radius_m=0.05, right_front_radius_m=0.05,
                  left_rear_radius_m=0.05, right_rear_radius_m=0.05)
    values[field] = value
    with pytest.raises(ValueError, match=field):
        CarGeometry(**values)


def test_limit_rate():
    assert limit_rate(0.0, 1.0, 0.0, 0.1) == 1.0      # no limit
    assert limit_rate(0.0, 1.0, 2.0, 0.1) == pytest.approx(0.2)
    assert limit_rate(0.0, -1.0, 2.0, 0.1) == pytest.approx(-0.2)
    assert limit_rate(0.9, 1.0, 2.0, 0.1) == 1.0      # does not overshoot
    assert limit_rate(0.5, 1.0, 2.0, -1.0) == 0.5     # no time, no change


class TestFollower:
    def test_stands_still_until_the_first_command(self):
        f = AckermannFollower(MAJOR, 0.5)
        assert as_tuple(f.update(10.0)) == (0, 0, 0, 0, 0, 0)

    def test_follows_the_command_and_brakes_after_the_timeout_holding_the_steering(self):
        f = AckermannFollower(MAJOR, 0.5)
        assert f.set_command(0.5, 0.3, 0.0, 0.0, time_s=1.0)
        driving = wheel_targets(MAJOR, 0.5, 0.3)
        assert f.update(1.0) == driving
        assert f.update(1.5) == driving          # exactly the timeout: still driving
        stopped = f.update(1.51)
        assert as_tuple(stopped)[:2] == as_tuple(driving)[:2]
        assert as_tuple(stopped)[2:] == (0, 0, 0, 0)
        assert f.timed_out(1.51)
        assert f.set_command(0.2, 0.0, 0.0, 0.0, time_s=3.0)
        assert f.update(3.0) == wheel_targets(MAJOR, 0.2, 0.0)

    def test_a_timeout_of_zero_never_brakes(self):
        f = AckermannFollower(MAJOR, 0.0)
        f.set_command(0.5, 0.3, 0.0, 0.0, time_s=1.0)
        assert f.update(1000.0) == wheel_targets(MAJOR, 0.5, 0.3)

    def test_rate_limits_from_the_command(self):
        f = AckermannFollower(MAJOR, 0.5)
        f.update(0.0)
        f.set_command(1.0, 0.4, 1.0, 2.0, time_s=0.0)   # 1 rad/s, 2 m/s^2
        assert f.update(0.1) == wheel_targets(MAJOR, 0.2, 0.1)
        assert f.update(0.2) == wheel_targets(MAJOR, 0.4, 0.2)
        f.set_command(1.0, 0.4, 1.0, 2.0, time_s=0.2)
        assert f.update(0.45) == wheel_targets(MAJOR, 0.9, 0.4)
        f.set_command(1.0, 0.4, 1.0, 2.0, time_s=0.45)
        assert f.update(0.9) == wheel_targets(MAJOR, 1.0, 0.4)

    def test_non_finite_commands_are_ignored(self):
        f = AckermannFollower(MAJOR, 0.5)
        f.set_command(0.5, 0.3, 0.0, 0.0, time_s=1.0)
        assert not f.set_command(math.nan, 0.3, 0.0, 0.0, time_s=1.1)
        assert not f.set_command(0.5, math.inf, 0.0, 0.0, time_s=1.1)
        assert f.update(1.2) == wheel_targets(MAJOR, 0.5, 0.3)
        assert as_tuple(f.update(1.55))[2:] == (0, 0, 0, 0)  # the ignored ones did not renew the command

    def test_steering_beyond_the_limit_is_held_at_the_limit(self):
        f = AckermannFollower(MAJOR, 0.5)
        f.set_command(0.5, 1.5, 0.0, 0.0, time_s=0.0)
        assert f.update(0.0) == wheel_targets(MAJOR, 0.5, MAJOR.max_steering_rad)

    def test_a_clock_that_jumps_back_does_not_brake_or_jump(self):
        f = AckermannFollower(MAJOR, 0.5)
        f.set_command(0.5, 0.3, 0.0, 0.0, time_s=100.0)
        assert f.update(100.0) == wheel_targets(MAJOR, 0.5, 0.3)
        assert f.update(0.2) == wheel_targets(MAJOR, 0.5, 0.3)   # reset: the command counts as new
        assert as_tuple(f.update(0.8))[2:] == (0, 0, 0, 0)      # and times out 0.5 s later

    def test_bad_timeout(self):
        with pytest.raises(ValueError, match='cmd_timeout_s'):
            AckermannFollower(MAJOR, -1.0)
