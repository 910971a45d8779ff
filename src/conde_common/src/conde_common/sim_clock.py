"""Waiting on ROS time (simulated under use_sim_time) so that a timer-driven node acts at the same
instants run after run, which lock-step needs (the simulator waits at each tick for the answer).

TickSchedule (pure) gives the deadlines of rospy.Rate(rate_hz) started at time 0: every
1/rate_hz seconds in whole nanoseconds, caught up when more than two periods behind, the rule the
simulator's lock-step bookkeeping assumes (conde_sim/lockstep_frames.h). rospy.Rate itself does not
do: it reads the clock twice per sleep, so a /clock message between the two reads moves its
deadline. Ticker (ROS) waits for those deadlines on /clock; wait_for_time waits for any condition.
"""

import rospy


class TickSchedule:
    """Deadlines [ns] of a timer at rate_hz [Hz] on a clock that starts at start_ns."""

    def __init__(self, rate_hz: float, start_ns: int = 0):
        if not rate_hz > 0:
            raise ValueError("rate_hz must be > 0, got %r" % (rate_hz,))
        self.period_ns = int(1e9 / rate_hz)  # as rospy.Rate's sleep_dur
        self.last_ns = start_ns

    def next_deadline_ns(self) -> int:
        return self.last_ns + self.period_ns

    def due(self, now_ns: int) -> bool:
        """True when now_ns has reached the next deadline; the schedule then moves on one period
        (or to now_ns when it is more than two periods behind, as rospy.Rate)."""
        if now_ns < self.last_ns:  # the clock moved backwards (a reset): start again from now
            self.last_ns = now_ns
            return False
        if now_ns < self.next_deadline_ns():
            return False
        self.last_ns += self.period_ns
        if now_ns - self.last_ns > 2 * self.period_ns:
            self.last_ns = now_ns
        return True


def wait_for_time(done):
    """Waits on ROS time until done(now) holds and returns now, the ROS time (rospy.Time) at which it
    held. Under use_sim_time it wakes on each /clock message. rospy.sleep(target - now) would not do:
    while ROS time is still 0 it counts the duration from the first /clock instead of from 0.
    Raises rospy.ROSInterruptException at shutdown, rospy.ROSTimeMovedBackwardsException when the
    time goes back."""
    if rospy.rostime.is_wallclock():
        while True:
            now = rospy.get_rostime()
            if done(now):
                return now
            if rospy.is_shutdown():  # rospy.sleep does not check under the wall clock
                raise rospy.ROSInterruptException("ROS shutdown request")
            rospy.sleep(0.01)
    time_changed = rospy.rostime.get_rostime_cond()
    previous = rospy.get_rostime()
    with time_changed:
        while True:
            if rospy.is_shutdown():
                raise rospy.ROSInterruptException("ROS shutdown request")
            now = rospy.get_rostime()
            if done(now):
                return now
            if now < previous:
                raise rospy.ROSTimeMovedBackwardsException((previous - now).to_sec())
            previous = now
            time_changed.wait(0.5)  # [s, wall] only a safety net: /clock messages notify


class Ticker:
    """A loop at rate_hz on ROS time whose ticks fall on the TickSchedule's deadlines from time 0:
    wait() returns the ROS time of the next tick. Time that goes back (a world reset) restarts the
    schedule from the new time."""

    def __init__(self, rate_hz: float):
        self.schedule = TickSchedule(rate_hz, 0)

    def wait(self) -> rospy.Time:
        while True:
            try:
                return wait_for_time(lambda now: self.schedule.due(now.to_nsec()))
            except rospy.ROSTimeMovedBackwardsException:
                self.schedule.last_ns = rospy.get_rostime().to_nsec()


def message_owed(stamps_ns, up_to_ns: int) -> bool:
    """True when a message of a regular stream stamped at or before up_to_ns [ns] may exist that has
    not come yet. stamps_ns: the stamps of the last messages received, in the order they came (one
    connection keeps the order): the next is due at the newest plus the smallest gap between them.
    False with fewer than two. In lock-step the simulator steps past a stamp only once the answers
    of that instant have come to it, but a node's receiving thread may not have run yet: a node
    waits (bounded) while this holds, and then acts on the same messages in every run."""
    stamps_ns = list(stamps_ns)
    if len(stamps_ns) < 2:
        return False
    smallest_gap_ns = min(b - a for a, b in zip(stamps_ns, stamps_ns[1:]))
    return stamps_ns[-1] + max(smallest_gap_ns, 1) <= up_to_ns
