"""The lane-following law: its limits, its signs, and convergence on a simulated unicycle."""

import math
import random

import pytest

from conde_control.control_law import ControlConfig, LaneFollowingController, Reference

DT_S = 1.0 / 30.0
CONFIG = ControlConfig()
EPS = 1e-9


def run(controller, refs, dt_s=DT_S):
    """Commands for a sequence of references."""
    return [controller.update(ref, dt_s) for ref in refs]


def random_references(rng, n):
    """Wild references: far beyond every limit, changing every few steps."""
    refs = []
    ref = Reference()
    for _ in range(n):
        if rng.random() < 0.2:
            ref = Reference(lateral_offset_m=rng.uniform(-2, 2), lateral_offset_ref_m=rng.uniform(-0.5, 0.5),
                            heading_error_rad=rng.uniform(-3, 3), heading_ref_rad=rng.uniform(-0.5, 0.5),
                            linear_velocity_mps=rng.uniform(-5, 5))
        refs.append(ref)
    return refs


# --- limits ---------------------------------------------------------------------------------------

def test_speed_limit_holds():
    c = LaneFollowingController(CONFIG)
    cmds = run(c, [Reference(linear_velocity_mps=10.0)] * 200) + run(c, [Reference(linear_velocity_mps=-10.0)] * 400)
    assert max(abs(v) for v, _ in cmds) == pytest.approx(CONFIG.max_linear_mps)
    assert all(abs(v) <= CONFIG.max_linear_mps + EPS for v, _ in cmds)
    assert cmds[199][0] == pytest.approx(CONFIG.max_linear_mps)
    assert cmds[-1][0] == pytest.approx(-CONFIG.max_linear_mps)


def test_yaw_rate_limit_holds():
    c = LaneFollowingController(CONFIG)
    cmds = run(c, [Reference(lateral_offset_m=1.5, heading_error_rad=1.0, linear_velocity_mps=1.0)] * 200)
    cmds += run(c, [Reference(lateral_offset_m=-1.5, heading_error_rad=-1.0, linear_velocity_mps=1.0)] * 200)
    assert all(abs(w) <= CONFIG.max_angular_radps + EPS for _, w in cmds)
    assert cmds[199][1] == pytest.approx(-CONFIG.max_angular_radps)  # saturated: the limit is reached
    assert cmds[-1][1] == pytest.approx(CONFIG.max_angular_radps)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_all_limits_hold_on_random_references(seed):
    rng = random.Random(seed)
    c = LaneFollowingController(CONFIG)
    v_prev, w_prev = 0.0, 0.0
    for ref in random_references(rng, 3000):
        dt_s = rng.uniform(0.001, 0.1)
        v, w = c.update(ref, dt_s)
        assert abs(v) <= CONFIG.max_linear_mps + EPS
        assert abs(w) <= CONFIG.max_angular_radps + EPS
        assert abs(v - v_prev) <= CONFIG.max_linear_accel_mps2 * dt_s + EPS
        assert abs(w - w_prev) <= CONFIG.max_angular_accel_radps2 * dt_s + EPS
        v_prev, w_prev = v, w


def test_acceleration_limits_are_reached_not_undercut():
    c = LaneFollowingController(CONFIG)
    v1, w1 = c.update(Reference(lateral_offset_m=1.0, linear_velocity_mps=1.0), DT_S)
    assert v1 == pytest.approx(CONFIG.max_linear_accel_mps2 * DT_S)
    assert w1 == pytest.approx(-min(CONFIG.max_angular_accel_radps2 * DT_S, CONFIG.offset_gain_per_m2 * v1 * 1.0))


def test_brake_decelerates_within_limits_to_a_stand():
    c = LaneFollowingController(CONFIG)
    run(c, [Reference(lateral_offset_m=0.3, linear_velocity_mps=1.0)] * 60)
    assert c.v_mps == pytest.approx(1.0) and c.omega_radps < -1.0
    v_prev, w_prev = c.v_mps, c.omega_radps
    steps = 0
    while (c.v_mps, c.omega_radps) != (0.0, 0.0):
        v, w = c.brake(DT_S)
        assert 0.0 <= v <= v_prev and abs(v - v_prev) <= CONFIG.max_linear_accel_mps2 * DT_S + EPS
        assert abs(w - w_prev) <= CONFIG.max_angular_accel_radps2 * DT_S + EPS
        v_prev, w_prev = v, w
        steps += 1
        assert steps < 1000
    # 1 m/s at 1 m/s^2 takes 1 s: 30 steps at 30 Hz (+1 for rounding).
    assert 30 <= steps <= 31


def test_reset_and_zero_dt():
    c = LaneFollowingController(CONFIG)
    run(c, [Reference(linear_velocity_mps=0.5)] * 30)
    before = (c.v_mps, c.omega_radps)
    assert c.update(Reference(linear_velocity_mps=0.0, lateral_offset_m=1.0), 0.0) == before
    c.reset()
    assert (c.v_mps, c.omega_radps) == (0.0, 0.0)


def test_bad_inputs_raise():
    c = LaneFollowingController(CONFIG)
    with pytest.raises(ValueError, match="non-finite"):
        c.update(Reference(lateral_offset_m=float("nan")), DT_S)
    with pytest.raises(ValueError, match="dt_s"):
        c.update(Reference(), -0.1)


# --- signs ----------------------------------------------------------------------------------------

def settled_omega(ref, steps=60):
    c = LaneFollowingController(CONFIG)
    return run(c, [ref] * steps)[-1][1]


def test_left_of_centre_turns_right():
    assert settled_omega(Reference(lateral_offset_m=0.05, linear_velocity_mps=0.5)) < 0.0
    assert settled_omega(Reference(lateral_offset_m=-0.05, linear_velocity_mps=0.5)) > 0.0


def test_pointing_left_turns_right():
    assert settled_omega(Reference(heading_error_rad=0.1, linear_velocity_mps=0.5)) < 0.0
    assert settled_omega(Reference(heading_error_rad=-0.1, linear_velocity_mps=0.5)) > 0.0


def test_references_shift_the_goal():
    # At the wanted offset and heading there is nothing to correct.
    assert settled_omega(Reference(lateral_offset_m=0.2, lateral_offset_ref_m=0.2, heading_error_rad=0.1,
                                   heading_ref_rad=0.1, linear_velocity_mps=0.5)) == pytest.approx(0.0)
    # A goal left of the robot (offset reference above the offset) turns it left.
    assert settled_omega(Reference(lateral_offset_ref_m=0.2, linear_velocity_mps=0.5)) > 0.0
    assert settled_omega(Reference(heading_ref_rad=0.2, linear_velocity_mps=0.5)) > 0.0


def test_standing_robot_does_not_turn():
    assert settled_omega(Reference(lateral_offset_m=0.2, heading_error_rad=0.3, linear_velocity_mps=0.0)) == 0.0


def test_expected_value():
    c = LaneFollowingController(CONFIG)
    run(c, [Reference(linear_velocity_mps=0.5)] * 30)  # at 0.5 m/s after 0.5 s
    v, w = c.update(Reference(lateral_offset_m=0.01, lateral_offset_ref_m=-0.01, heading_error_rad=0.02,
                              linear_velocity_mps=0.5), 1.0)
    assert v == pytest.approx(0.5)
    assert w == pytest.approx(-CONFIG.offset_gain_per_m2 * 0.5 * 0.02 - CONFIG.heading_gain_per_m * 0.5 * 0.02)


# --- closed loop ----------------------------------------------------------------------------------

def drive_straight_lane(speed_mps, offset_m, heading_rad, duration_s, dt_s=DT_S):
    """Kinematic unicycle along a straight lane (the x axis), commanded by the controller from the
    exact lane pose.  Returns the (offset, heading) history."""
    c = LaneFollowingController(CONFIG)
    y, th = offset_m, heading_rad
    history = []
    for _ in range(int(round(duration_s / dt_s))):
        v, w = c.update(Reference(lateral_offset_m=y, heading_error_rad=th, linear_velocity_mps=speed_mps), dt_s)
        # Exact integration of the unicycle over one period at constant (v, w).
        if abs(w) > 1e-12:
            y += v / w * (math.cos(th) - math.cos(th + w * dt_s))
        else:
            y += v * math.sin(th) * dt_s
        th += w * dt_s
        history.append((y, th))
    return history


@pytest.mark.parametrize("speed_mps", [0.3, 0.5, 1.0])
@pytest.mark.parametrize("offset_m, heading_deg", [(0.1, 10.0), (-0.1, -10.0), (0.1, -10.0)])
def test_converges_to_the_lane_centre(speed_mps, offset_m, heading_deg):
    history = drive_straight_lane(speed_mps, offset_m, math.radians(heading_deg), duration_s=15.0)
    y, th = history[-1]
    assert abs(y) < 0.01
    assert abs(math.degrees(th)) < 1.0
    # Well damped: it barely moves away from the lane centre and does not swing over to the other side.
    assert max(abs(y) for y, _ in history) < abs(offset_m) + 0.02
    assert max(-math.copysign(1.0, offset_m) * y for y, _ in history) < 0.01


def test_converges_to_an_offset_reference():
    c = LaneFollowingController(CONFIG)
    y, th = 0.0, 0.0
    for _ in range(600):
        v, w = c.update(Reference(lateral_offset_m=y, lateral_offset_ref_m=0.15, heading_error_rad=th,
                                  linear_velocity_mps=0.5), DT_S)
        y += v * math.sin(th) * DT_S
        th += w * DT_S
    assert y == pytest.approx(0.15, abs=0.01)
    assert abs(th) < math.radians(1.0)


def test_path_curvature_is_fed_forward():
    """On the wanted path (no offset or heading error) the robot turns at v * curvature: an arc
    of radius 1 / curvature; a message without the field follows the lane as before."""
    config = ControlConfig(max_angular_accel_radps2=100.0, max_linear_accel_mps2=100.0)
    for curvature in (1.0 / 0.609, -1.0 / 1.391):
        controller = LaneFollowingController(config)
        for _ in range(50):
            v, omega = controller.update(Reference(linear_velocity_mps=0.5, path_curvature_per_m=curvature), 0.02)
        assert v == pytest.approx(0.5) and omega == pytest.approx(0.5 * curvature)

    class WithoutCurvature:
        lateral_offset_m = lateral_offset_ref_m = heading_error_rad = heading_ref_rad = 0.0
        linear_velocity_mps = 0.5
    controller = LaneFollowingController(config)
    assert controller.update(WithoutCurvature(), 0.02)[1] == 0.0
