"""Waiting on ROS time (simulated under use_sim_time) so that a timer-driven node acts at the same
instants run after run, which lock-step needs (the simulator waits at each tick for the answer).

TickSchedule (pure) gives the deadlines of rospy.Rate(rate_hz) started at time 0: every
1/rate_hz seconds in whole nanoseconds, caught up when more than two periods behind, the rule the
simulator's lock-step bookkeeping assumes (conde_sim/lockstep_frames.h). rospy.Rate itself does not
do: it reads the clock twice per sleep, so a /clock message between the two reads moves its
deadline. Ticker (ROS) waits for those deadlines on /clock; wait_for_time waits for any condition.
message_owed and OwedWait: a node that joins streams waits (bounded) for an input still owed.
"""

import time

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


class OwedWait:
    """The bounded wait of a node that joins streams in lock-step: while an input that the simulator
    already has is still owed (message_owed: the node's receiving thread has not run yet), wait on
    the node's condition, at most wait_s of wall time. A wait that reaches that bound means the
    machine held the sender or this node back longer than wait_s, and this frame may then differ from
    run to run: each such give-up is counted, warned about (the first at once, then at most once per
    WARN_PERIOD_S of wall time, with the count), and the count is logged at shutdown:

        "<node>: lock-step: <N> of <M> waits for owed <what> gave up after <wait_s> s of wall time"

    wait_s 0 (not lock-step) waits for nothing and counts nothing."""

    WARN_PERIOD_S = 10.0  # [s, wall]

    def __init__(self, node_name: str, what: str, wait_s: float, warn=None, info=None, is_shutdown=None):
        """warn(line), info(line), is_shutdown(): default rospy's (info also at shutdown)."""
        if not wait_s >= 0:
            raise ValueError("wait_s must be >= 0, got %r" % (wait_s,))
        self.node_name, self.what, self.wait_s = node_name, what, float(wait_s)
        self.waits = 0      # frames that found an input owed
        self.gave_up = 0    # ... and gave up at wait_s
        self._warned_s = None
        if info is None:
            info = rospy.loginfo
            if self.wait_s > 0:
                rospy.on_shutdown(lambda: info(self.summary()))
        self._warn = warn or rospy.logwarn
        self._info = info
        self._is_shutdown = is_shutdown or rospy.is_shutdown

    def wait(self, condition, owed) -> bool:
        """Waits on `condition` (held by the caller; notified when an input comes) while owed() holds;
        False when it gave up at wait_s, True otherwise (nothing owed, or the shutdown)."""
        if self.wait_s <= 0 or not owed():
            return True
        self.waits += 1
        give_up_s = time.monotonic() + self.wait_s
        while owed():
            if self._is_shutdown():
                return True
            left_s = give_up_s - time.monotonic()
            if left_s <= 0:
                self._gave_up()
                return False
            condition.wait(min(0.005, left_s))
        return True

    def _gave_up(self) -> None:
        self.gave_up += 1
        now_s = time.monotonic()
        if self._warned_s is None or now_s - self._warned_s >= self.WARN_PERIOD_S:
            self._warned_s = now_s
            self._warn("%s: lock-step: an owed %s had not come after %g s of wall time (%d such waits so far): "
                       "this frame may differ from run to run (the machine is too busy for this wait)"
                       % (self.node_name, self.what, self.wait_s, self.gave_up))

    def summary(self) -> str:
        return "%s: lock-step: %d of %d waits for owed %s gave up after %g s of wall time" % (
            self.node_name, self.gave_up, self.waits, self.what, self.wait_s)
