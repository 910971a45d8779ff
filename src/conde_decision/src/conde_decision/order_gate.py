"""Which panel signals the decision takes as orders.  Pure Python, no ROS.

Standing (the state's command is speed stop: waiting for the go, stopped at the line) the robot
looks at the panel from the start zone, and every signal counts at once.  Driving, conde_semaphore
also reads the panel from afar (about 5 m): there it misreads arrows and the checkerboard as
right/left/forward for one to a few debounced frames (0.1-0.73 s of image stamps in D1-D4 on the
nominal track), while a real change of the panel is read for seconds, though from afar (Major
Alvega's camera) interrupted by frames of none.  So, driving, a signal that differs from the order
held counts only once it has been read for hold_s (image stamps, summed over its runs of
consecutive messages): a message that is no order (none, low confidence) pauses that count, a
pause longer than hold_s or any other signal starts it anew.  Signals equal to the order held
count at once (no event is delayed for the order in force).

Driving, a change of order also needs the panel to be where the robot looks: the panel stands over
the crosswalk, so the caller says whether the crosswalk ahead is in sight (panel_ahead).  In V1 the
red triangles of the vertical danger signs beside the road are read as `stop` for 6-7.6 s (longer
than any hold) 1.3-5 m past the crosswalk, where no crosswalk is ahead; the count of such a read
goes on (a read that lasts from afar until the crosswalk comes into sight is taken then), but it
is taken only while panel_ahead.

A stop read with the crosswalk close ahead is the caller's exception (at_once): there the hold would
carry the robot over the crosswalk before it brakes (D2, track seed 9: the panel turned to stop
0.4 m before the near edge), and a false stop costs only a halt at the line.
"""

from typing import Optional


class OrderGate:
    """accept(signal, time_s, standing) -> True when the signal is to be taken as an order now.

    `signal` is any hashable code (conde_msgs/PanelSignal's); the caller filters out what is no
    order at all (NONE, low confidence) and calls pause() for such messages."""

    def __init__(self, hold_s: float):
        if isinstance(hold_s, bool) or not isinstance(hold_s, (int, float)) or not hold_s >= 0.0:
            raise ValueError("hold_s must be a number >= 0, got %r" % (hold_s,))
        self.hold_s = float(hold_s)
        self.held = None  # the order in force (the last signal accepted)
        self.candidate = None  # a different signal being watched while driving
        self.read_s = 0.0  # how long the candidate has been read (summed over its runs) [s]
        self.last_read_s: Optional[float] = None  # stamp of the candidate's latest message [s]
        self.running = False  # the previous message was the candidate (no pause since)

    def pause(self) -> None:
        """A message that is no order (none, low confidence): the candidate's count pauses."""
        self.running = False

    def accept(self, signal, time_s: float, standing: bool, panel_ahead: bool = True, at_once: bool = False) -> bool:
        """panel_ahead: the panel can be what the camera reads (the crosswalk ahead is in sight);
        without it, driving, a change of order is watched but not taken.  at_once: the caller takes
        this signal now whatever the hold (a stop read at the line, DecisionConfig.stop_near_m)."""
        if standing or at_once or signal == self.held:
            return self._take(signal)
        if (signal != self.candidate or self.last_read_s is None or time_s < self.last_read_s
                or time_s - self.last_read_s > self.hold_s):
            self.candidate, self.read_s = signal, 0.0
        elif self.running:
            self.read_s += time_s - self.last_read_s
        self.last_read_s, self.running = time_s, True
        if self.read_s >= self.hold_s - 1e-9 and panel_ahead:
            return self._take(signal)
        return False

    def _take(self, signal) -> bool:
        self.held = signal
        self.candidate, self.read_s, self.last_read_s, self.running = None, 0.0, None, False
        return True
