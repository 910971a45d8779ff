"""conde_common.sim_clock: TickSchedule (rospy.Rate's deadlines from time 0, in nanoseconds),
message_owed and OwedWait (the bounded wait for an owed input, its give-ups counted)."""
import time

import pytest

from conde_common.sim_clock import OwedWait, TickSchedule, message_owed

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


class FakeCondition:
    """A condition whose wait() lets the test's inputs 'arrive' (runs a callback) and records waits."""

    def __init__(self, on_wait=None):
        self.on_wait = on_wait
        self.waited_s = []

    def wait(self, timeout_s):
        self.waited_s.append(timeout_s)
        if self.on_wait:
            self.on_wait()


def owed_wait(wait_s, warnings, infos):
    return OwedWait("node", "odometry message", wait_s, warn=warnings.append, info=infos.append,
                    is_shutdown=lambda: False)


def test_owed_wait_returns_once_the_owed_message_has_come():
    warnings, infos = [], []
    stamps = [0, 10 * MS]
    waiter = owed_wait(1.0, warnings, infos)
    condition = FakeCondition(on_wait=lambda: stamps.append(20 * MS))  # the receiving thread ran
    assert waiter.wait(condition, lambda: message_owed(stamps, 20 * MS))
    assert len(condition.waited_s) == 1 and (waiter.waits, waiter.gave_up) == (1, 0) and not warnings
    # nothing owed: no wait at all, nothing counted
    assert waiter.wait(condition, lambda: message_owed(stamps, 20 * MS))
    assert len(condition.waited_s) == 1 and waiter.waits == 1


def test_owed_wait_gives_up_at_its_bound_counts_and_warns_with_the_count():
    warnings, infos = [], []
    waiter = owed_wait(0.02, warnings, infos)
    never = FakeCondition(on_wait=lambda: time.sleep(0.005))  # the owed message never comes
    assert not waiter.wait(never, lambda: True)
    assert not waiter.wait(never, lambda: True)
    assert (waiter.waits, waiter.gave_up) == (2, 2)
    assert len(warnings) == 1  # the second within WARN_PERIOD_S is not repeated
    assert "node: lock-step: an owed odometry message had not come after 0.02 s of wall time (1 such" in warnings[0]
    assert waiter.summary() == ("node: lock-step: 2 of 2 waits for owed odometry message gave up after 0.02 s "
                                "of wall time")
    assert all(w <= 0.005 for w in never.waited_s)


def test_owed_wait_of_zero_waits_for_nothing():
    warnings, infos = [], []
    waiter = owed_wait(0.0, warnings, infos)
    condition = FakeCondition()
    assert waiter.wait(condition, lambda: True)
    assert (waiter.waits, waiter.gave_up, condition.waited_s, warnings) == (0, 0, [], [])
    with pytest.raises(ValueError, match="wait_s must be >= 0"):
        owed_wait(-1.0, warnings, infos)
