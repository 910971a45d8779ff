"""ArcTrack: a junction's arc as a path on the floor, tracked by odometry (arc_track.py)."""

import math

import pytest

from conde_decision.arc_track import ArcTrack

RADIUS_M = 1.391  # the lane's radius of a left turn at a junction
DT_S = 1.0 / 30.0
SPEED_MPS = 0.5


def drive_arc(track, yaw0_rad, side, distance_m, step_m=0.01):
    """Drives exactly the arc from heading yaw0_rad; the (offset, heading error) of every step."""
    assert track.step(yaw0_rad, 0.5) == pytest.approx((0.0, yaw0_rad - track.direction_rad))  # driven before
    out, yaw = [], yaw0_rad
    for _ in range(int(round(distance_m / step_m))):
        yaw += side * step_m / RADIUS_M
        out.append(track.step(yaw, step_m))
    return out


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_the_arc_driven_exactly_has_no_error(side):
    track = ArcTrack()
    assert track.start(0.3, 0.3, RADIUS_M, side)
    errors = drive_arc(track, 0.3, side, 0.5 * math.pi * RADIUS_M)
    assert max(abs(offset) for offset, _ in errors) < 1e-4
    assert max(abs(heading) for _, heading in errors) < 1e-3


def test_a_robot_pointing_right_of_the_road_is_told_so_and_drifts_right_of_the_arc():
    """The arc starts along the road's direction, not the robot's heading: pointing 0.15 rad right of
    the road, the robot's heading error is -0.15 at once, and a robot that keeps that error while
    turning with the arc's curvature (feed-forward alone) ends right of the arc."""
    track = ArcTrack()
    road_rad = 2.0
    track.start(road_rad - 0.15, road_rad, RADIUS_M, 1.0)
    offset, heading = track.errors(road_rad - 0.15)
    assert offset == pytest.approx(0.0) and heading == pytest.approx(-0.15)
    errors = drive_arc(track, road_rad - 0.15, 1.0, 0.5 * math.pi * RADIUS_M)
    assert all(h < 0.0 for _, h in errors)  # pointing right of the path all the way
    # the robot's circle is the arc's turned by -0.15 rad about the start: after 90 deg it lies
    # 2 R sin(0.075) off the arc's end, mostly to the right of the path
    assert errors[-1][0] < -0.15


def test_the_road_direction_on_another_branch_of_the_angle_counts_as_the_nearest():
    track = ArcTrack()
    track.start(2.0 * math.pi + 0.1, 0.0, RADIUS_M, -1.0)
    assert track.errors(2.0 * math.pi + 0.1)[1] == pytest.approx(0.1)


def test_without_road_direction_the_arc_starts_along_the_robots_heading():
    track = ArcTrack()
    track.start(-1.2, None, RADIUS_M, 1.0)
    assert track.errors(-1.2) == pytest.approx((0.0, 0.0))


def test_without_odometry_the_arc_is_not_tracked():
    track = ArcTrack()
    assert not track.start(None, 0.0, RADIUS_M, 1.0)
    assert track.step(0.1, 0.02) is None
    track.start(0.0, 0.0, RADIUS_M, 1.0)
    assert track.step(None, 0.02) is None
    track.release()
    assert track.step(0.0, 0.02) is None


@pytest.mark.parametrize("radius, side", [(0.0, 1.0), (-1.0, 1.0), (1.0, 0.0), (1.0, 2.0)])
def test_a_bad_arc_is_refused(radius, side):
    with pytest.raises(ValueError, match="arc track"):
        ArcTrack().start(0.0, 0.0, radius, side)


def closed_loop_end(tracked, start_error_rad=-0.15, lag_s=0.3, turning_right_radps=-0.2):
    """A unicycle whose turn rate follows its command with a first-order lag (a steering servo),
    turning right and pointing start_error_rad off the road where a 90-degree left arc begins; the
    command is the control law of conde_control (offset gain 36, heading gain 10) with the arc's
    curvature and, tracked, the arc's errors.  Returns the robot's distance from the arc's end [m]
    once it has driven the arc's length."""
    track = ArcTrack()
    x = y = 0.0
    yaw, omega = start_error_rad, turning_right_radps
    track.start(yaw, 0.0, RADIUS_M, 1.0)
    offset, heading = track.step(yaw, 0.0)  # the decision's step in which the arc begins
    for _ in range(int(round(0.5 * math.pi * RADIUS_M / (SPEED_MPS * DT_S)))):
        command = SPEED_MPS / RADIUS_M
        if tracked:
            command -= 36.0 * SPEED_MPS * offset + 10.0 * SPEED_MPS * heading
        omega += (command - omega) * DT_S / lag_s
        new_yaw = yaw + omega * DT_S
        step_m = SPEED_MPS * DT_S
        x += step_m * math.cos(0.5 * (yaw + new_yaw))
        y += step_m * math.sin(0.5 * (yaw + new_yaw))
        yaw = new_yaw
        offset, heading = track.step(yaw, step_m)
    return math.hypot(x - RADIUS_M, y - RADIUS_M)


def test_tracked_the_arc_ends_where_it_should_despite_the_start_heading_and_the_lag():
    """The seed-2 merge in numbers: feed-forward alone ends the turn far from the arc's end (the
    central road's east lane), tracked it ends within a few cm."""
    assert closed_loop_end(tracked=False) > 0.3
    assert closed_loop_end(tracked=True) < 0.08
