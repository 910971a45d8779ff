"""CourseHold (course_hold.py): across a junction driven straight, the robot's offset and heading
against the road seen before it, by odometry."""

import math

import pytest

from conde_decision.course_hold import CourseHold

ROAD_RAD = 1.5 * math.pi  # southbound, unwrapped as odometry gives it


def test_heading_error_is_the_odometry_heading_less_the_road_direction():
    hold = CourseHold()
    for offset_m in (0.02, 0.03, 0.02, 0.04, 0.03):
        hold.measured(offset_m)
    offset_m, heading_rad = hold.step(ROAD_RAD - 0.1, ROAD_RAD, 0.0)
    assert heading_rad == pytest.approx(-0.1)  # pointing right of the road
    assert offset_m == pytest.approx(0.03)  # the median of the offsets seen


def test_offset_is_dead_reckoned_from_the_median_of_the_last_offsets_seen():
    """One frame lured by the junction's lines (0.3 m) among the last five does not move the start."""
    hold = CourseHold(samples=5)
    for offset_m in (0.5, 0.5, 0.5, 0.0, 0.01, 0.3, 0.0, 0.01):  # the first three have left the window
        hold.measured(offset_m)
    offsets = [hold.step(ROAD_RAD - 0.1, ROAD_RAD, 0.1)[0] for _ in range(20)]  # 2 m pointing 0.1 rad right
    assert offsets[0] == pytest.approx(0.01 - 0.1 * math.sin(0.1))
    assert offsets[-1] == pytest.approx(0.01 - 2.0 * math.sin(0.1))  # 0.19 m right of where it began


def test_release_starts_the_next_hold_from_the_offsets_seen_then():
    hold = CourseHold(samples=1)
    hold.measured(0.05)
    assert hold.step(ROAD_RAD, ROAD_RAD, 1.0) == pytest.approx((0.05, 0.0))
    hold.step(ROAD_RAD + 0.2, ROAD_RAD, 1.0)
    hold.release()
    hold.measured(-0.02)
    assert hold.step(ROAD_RAD, ROAD_RAD, 1.0) == pytest.approx((-0.02, 0.0))


def test_without_odometry_or_road_direction_there_is_no_hold_by_odometry():
    hold = CourseHold()
    hold.measured(0.1)
    assert hold.step(None, ROAD_RAD, 0.1) is None
    assert hold.step(ROAD_RAD, None, 0.1) is None
    assert hold.step(ROAD_RAD, ROAD_RAD, 0.1) == pytest.approx((0.1, 0.0))  # nothing was integrated before


def test_no_offset_seen_starts_on_the_centre():
    assert CourseHold().step(ROAD_RAD, ROAD_RAD, 0.1) == pytest.approx((0.0, 0.0))


def test_heading_error_wraps_across_a_full_turn():
    assert CourseHold().step(ROAD_RAD + 2.0 * math.pi + 0.05, ROAD_RAD, 0.0)[1] == pytest.approx(0.05)


def test_samples_must_be_positive():
    with pytest.raises(ValueError, match="samples must be >= 1, got 0"):
        CourseHold(samples=0)
