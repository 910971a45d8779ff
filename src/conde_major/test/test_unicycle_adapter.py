"""The unicycle -> Ackermann adapter (conde_major/unicycle_adapter.py): the bicycle model's
steering angle forwards and backwards, the steering limit and rate limit, standing still, bad
input, and a closed loop: integrating the commanded car reproduces the asked yaw rate."""

import math

import pytest

from conde_major.unicycle_adapter import SteeringLimits, UnicycleToAckermann, steering_for

L_M = 0.32  # Major Alvega's wheelbase
MAX_RAD = 0.6230  # its centre steering limit (inner hinge at 45 degrees)
RATE_RADPS = 4.553  # its hinges' velocity limit


def adapter(rate=0.0):
    return UnicycleToAckermann(SteeringLimits(L_M, MAX_RAD, rate))


@pytest.mark.parametrize('v, omega', [(0.5, 0.5), (0.5, -0.5), (1.0, 0.2), (-0.3, 0.4), (-0.3, -0.4)])
def test_the_yaw_rate_asked_is_the_yaw_rate_commanded(v, omega):
    cmd = adapter().convert(v, omega, 0.0)
    assert cmd.speed_mps == v
    # omega = v tan(delta) / L: R = v / omega, delta = atan(L / R)
    assert cmd.steering_rad == pytest.approx(math.atan(L_M * omega / v), abs=1e-12)
    assert cmd.yaw_rate_radps == pytest.approx(omega, rel=1e-12)


def test_backwards_the_wheels_turn_the_other_way_for_the_same_yaw_rate():
    forward, backward = adapter().convert(0.4, 0.5, 0.0), adapter().convert(-0.4, 0.5, 0.0)
    assert forward.steering_rad > 0 > backward.steering_rad
    assert forward.steering_rad == pytest.approx(-backward.steering_rad)


def test_the_numbers_for_a_one_metre_circle():
    # v 0.5 m/s, omega 0.5 rad/s: R = 1 m, delta = atan(0.32) = 0.309703 rad
    assert adapter().convert(0.5, 0.5, 0.0).steering_rad == pytest.approx(0.309703, abs=1e-6)
    assert steering_for(0.5, 0.5, L_M) == pytest.approx(0.309703, abs=1e-6)


@pytest.mark.parametrize('omega', [3.0, -3.0])
def test_a_turn_tighter_than_the_car_can_is_limited(omega):
    cmd = adapter().convert(0.3, omega, 0.0)
    assert cmd.steering_rad == pytest.approx(math.copysign(MAX_RAD, omega))
    assert abs(cmd.yaw_rate_radps) == pytest.approx(0.3 * math.tan(MAX_RAD) / L_M)
    assert abs(cmd.yaw_rate_radps) < abs(omega)


def test_the_steering_rate_is_limited_from_straight_wheels():
    a = adapter(RATE_RADPS)
    assert a.convert(0.5, 1.0, 10.0).steering_rad == 0.0  # no time yet to turn the wheels
    assert a.convert(0.5, 1.0, 10.02).steering_rad == pytest.approx(RATE_RADPS * 0.02)
    assert a.convert(0.5, 1.0, 10.04).steering_rad == pytest.approx(RATE_RADPS * 0.04)
    target = math.atan(L_M * 1.0 / 0.5)
    assert a.convert(0.5, 1.0, 11.0).steering_rad == pytest.approx(target)  # reached, not overshot
    assert a.convert(0.5, -1.0, 11.01).steering_rad == pytest.approx(target - RATE_RADPS * 0.01)


def test_time_going_back_counts_as_none():
    a = adapter(RATE_RADPS)
    a.convert(0.5, 0.0, 5.0)
    assert a.convert(0.5, 1.0, 1.0).steering_rad == 0.0
    assert a.convert(0.5, 1.0, 1.1).steering_rad == pytest.approx(RATE_RADPS * 0.1)


def test_standing_still_holds_the_steering_angle():
    a = adapter()
    turned = a.convert(0.5, 0.5, 0.0).steering_rad
    for omega in (0.0, 2.0, -2.0):  # a turn on the spot cannot be driven: the speed 0 is passed on
        cmd = a.convert(0.0, omega, 0.1)
        assert (cmd.speed_mps, cmd.steering_rad, cmd.yaw_rate_radps) == (0.0, turned, 0.0)
    assert a.convert(0.005, 1.0, 0.2).steering_rad == turned  # below min_speed_mps


@pytest.mark.parametrize('bad', [float('nan'), float('inf'), -float('inf')])
def test_non_finite_input_is_refused_and_changes_nothing(bad):
    a = adapter(RATE_RADPS)
    a.convert(0.5, 0.3, 0.0)
    before = a.convert(0.5, 0.3, 1.0).steering_rad
    assert a.convert(bad, 0.3, 2.0) is None
    assert a.convert(0.5, bad, 2.0) is None
    assert a.convert(0.5, 0.3, bad) is None
    assert a.convert(0.5, 0.3, 1.0).steering_rad == before


@pytest.mark.parametrize('kwargs, message', [
    (dict(wheelbase_m=0.0, max_steering_rad=0.5), 'wheelbase_m'),
    (dict(wheelbase_m=float('nan'), max_steering_rad=0.5), 'wheelbase_m'),
    (dict(wheelbase_m=0.3, max_steering_rad=math.pi / 2), 'max_steering_rad'),
    (dict(wheelbase_m=0.3, max_steering_rad=0.0), 'max_steering_rad'),
    (dict(wheelbase_m=0.3, max_steering_rad=0.5, max_steering_rate_radps=-1.0), 'max_steering_rate_radps'),
    (dict(wheelbase_m=0.3, max_steering_rad=0.5, min_speed_mps=0.0), 'min_speed_mps'),
])
def test_bad_limits_are_refused_naming_the_field(kwargs, message):
    with pytest.raises(ValueError, match=message):
        SteeringLimits(**kwargs)


def test_the_bicycle_model_driven_by_the_adapter_follows_the_asked_heading():
    """A kinematic bicycle (rear-axle reference) integrated at 1 ms under the adapter's commands at
    30 Hz, with the steering rate limit: asked for 0.8 rad/s for 2 s, it turns 1.6 rad within the
    rate limit's lag (a few degrees)."""
    a = adapter(RATE_RADPS)
    heading_rad, t_s, dt_s, delta = 0.0, 0.0, 0.001, 0.0
    for frame in range(60):
        cmd = a.convert(0.5, 0.8, frame / 30.0)
        delta = cmd.steering_rad
        for _ in range(round(1000 / 30) if frame % 3 else 34):
            heading_rad += 0.5 * math.tan(delta) / L_M * dt_s
            t_s += dt_s
    assert heading_rad == pytest.approx(0.8 * t_s, abs=math.radians(5))
