"""conde_common.sim_clock.TickSchedule: rospy.Rate's deadlines from time 0, in nanoseconds."""
import pytest

from conde_common.sim_clock import TickSchedule, message_owed

MS = 1_000_000  # [ns]


def ticks(schedule, clock_ns):
    return [t for t in clock_ns if schedule.due(t)]


def test_ticks_fall_on_the_first_clock_at_or_after_each_period_from_zero():
    # 30 Hz on a 100 Hz clock: deadlines 33.33, 66.67, 100 ms -> clocks 40, 70, 100 ms.
    assert ticks(TickSchedule(30.0), range(0, 101 * MS, 10 * MS)) == [40 * MS, 70 * MS, 100 * MS]


def test_a_clock_that_skips_more_than_two_periods_restarts_the_schedule_from_now():
    schedule = TickSchedule(10.0)
    assert schedule.due(1000 * MS) and schedule.last_ns == 1000 * MS
    assert not schedule.due(1050 * MS) and schedule.due(1100 * MS)


def test_time_that_goes_back_restarts_the_schedule_without_a_tick():
    schedule = TickSchedule(10.0)
    assert schedule.due(500 * MS)
    assert not schedule.due(0)
    assert ticks(schedule, [50 * MS, 100 * MS]) == [100 * MS]


def test_a_rate_that_is_not_positive_is_refused():
    with pytest.raises(ValueError, match="rate_hz must be > 0"):
        TickSchedule(0.0)


def test_a_message_is_owed_when_the_next_one_at_the_smallest_gap_is_due():
    camera_ns = [9700 * MS, 9733 * MS, 9767 * MS]  # frames 33 or 34 ms apart: the next at 9800 ms
    assert message_owed(camera_ns, 9800 * MS)
    assert not message_owed(camera_ns, 9799 * MS)
    assert not message_owed(camera_ns + [9800 * MS], 9800 * MS)


def test_nothing_is_owed_before_two_messages_have_come():
    assert not message_owed([], 10**12) and not message_owed([0], 10**12)
