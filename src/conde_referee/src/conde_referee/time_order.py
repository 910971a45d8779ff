"""Inputs judged in the order of simulated time, not of arrival (pure, no ROS).

The referee reads several topics (odometry, contacts, object poses, panel signal); each arrives on
its own connection, so the order in which two messages of nearly the same simulated time reach the
node changes from run to run even when the simulation itself is bit-identical (lock-step). Fed
through a TimeOrder, they are handed on sorted by (stamp, rank of their kind, arrival within the
kind) once the newest stamp seen is at least lag_s later; a message later than that by more
than lag_s of simulated time would still be out of order (lock-step runs deliver within a few
steps). At the end of the run flush() hands on what is left.

    order = TimeOrder(lag_s=0.1)
    order.push(12.34, 0, ("odom", msg))
    for stamp, item in order.release():   # what is now old enough, in time order
        judge(stamp, item)
"""
import heapq
import math
from typing import Any, List, Tuple


class TimeOrder:
    def __init__(self, lag_s: float):
        if not (isinstance(lag_s, (int, float)) and math.isfinite(lag_s) and lag_s >= 0):
            raise ValueError("lag_s must be a finite number >= 0, got %r" % (lag_s,))
        self.lag_s = float(lag_s)
        self._heap: List[Tuple[float, int, int, Any]] = []
        self._arrivals = 0
        self.newest_s = -math.inf
        self.released_until_s = -math.inf  # stamp of the last item handed on

    def push(self, stamp_s: float, rank: int, item: Any):
        """An input stamped stamp_s [s of simulated time]; rank orders kinds of equal stamp (lower first)."""
        self._arrivals += 1
        heapq.heappush(self._heap, (float(stamp_s), int(rank), self._arrivals, item))
        self.newest_s = max(self.newest_s, float(stamp_s))

    def release(self) -> List[Tuple[float, Any]]:
        """[(stamp_s, item)] of every input at least lag_s older than the newest, in time order."""
        return self._pop_until(self.newest_s - self.lag_s + 1e-9)  # 1e-9: stamps on a grid of steps

    def flush(self) -> List[Tuple[float, Any]]:
        """Everything still held, in time order (the run is over)."""
        return self._pop_until(math.inf)

    def late(self, stamp_s: float) -> bool:
        """True if an input stamped stamp_s would come after inputs of later time already handed on."""
        return stamp_s < self.released_until_s

    def __len__(self):
        return len(self._heap)

    def _pop_until(self, limit_s: float):
        out = []
        while self._heap and self._heap[0][0] <= limit_s:
            stamp_s, _rank, _arrival, item = heapq.heappop(self._heap)
            self.released_until_s = max(self.released_until_s, stamp_s)
            out.append((stamp_s, item))
        return out


def judging_due(stamp_s: float, last_judged_s, period_s: float) -> bool:
    """True for the first input at or after each multiple of period_s of simulated time (the object
    poses are judged every period_s, on the same stamps in every run)."""
    if last_judged_s is None:
        return True
    return math.floor(stamp_s / period_s + 1e-9) > math.floor(last_judged_s / period_s + 1e-9)


def progress_mark(released_until_s: float, last_mark_s, period_s: float):
    """The "judged up to" stamp [s of simulated time] to publish now, or None: released_until_s
    (TimeOrder.released_until_s) once it reaches a multiple of period_s past last_mark_s (None = no
    mark yet), so a waiter learns at least every period_s how far the judging has come."""
    if not math.isfinite(released_until_s):
        return None
    return released_until_s if judging_due(released_until_s, last_mark_s, period_s) else None
