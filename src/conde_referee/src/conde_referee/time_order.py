"""Inputs judged in the order of simulated time, not of arrival (pure, no ROS).

The referee reads several topics (odometry, contacts, object poses, panel signal); each arrives on
its own connection, so the order in which two messages of nearly the same simulated time reach the
node changes from run to run even when the simulation itself is bit-identical (lock-step). Fed
through a TimeOrder, they are handed on sorted by (stamp, rank of their kind, arrival within the
kind) once the newest stamp seen is at least lag_s later. Streams named regular (a fixed rate,
in order on one connection, such as odometry) hold the release further: nothing is handed on
until every regular stream has shown that it has nothing earlier, that is, until the stamp its next
message is due at (its newest plus its smallest gap so far) is later. A node that falls behind on
one connection (a busy machine) is then still judged in time order. A regular stream that is more
than stopped_after_s behind the newest stamp counts as stopped and holds nothing (a stream may end
before the others); one not seen yet holds everything until the newest stamp of the regular
streams is stopped_after_s past their first (the streams may begin in any order). Name as regular
only streams that are subscribed to: one that never comes delays the judging by stopped_after_s.
A message later than those bounds is still out of order: late() tells. At the end of the run
flush() hands on what is left.

    order = TimeOrder(lag_s=0.1, regular_ranks=(0,))
    order.push(12.34, 0, ("odom", msg))
    for stamp, item in order.release():   # what is now old enough, in time order
        judge(stamp, item)
"""
import heapq
import math
from typing import Any, Iterable, List, Tuple


class TimeOrder:
    def __init__(self, lag_s: float, regular_ranks: Iterable[int] = (), stopped_after_s: float = 1.0):
        """lag_s, stopped_after_s: [s of simulated time]; regular_ranks: the ranks of the regular streams."""
        for name, value in (("lag_s", lag_s), ("stopped_after_s", stopped_after_s)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError("%s must be a finite number >= 0, got %r" % (name, value))
        self.lag_s = float(lag_s)
        self.stopped_after_s = float(stopped_after_s)
        # rank -> [newest stamp, smallest gap between two of its stamps (inf until two came)]
        self._regular = {int(rank): [-math.inf, math.inf] for rank in regular_ranks}
        self._heap: List[Tuple[float, int, int, Any]] = []
        self._arrivals = 0
        self.newest_s = -math.inf
        self.first_s = math.inf  # the earliest stamp of a regular stream
        self.released_until_s = -math.inf  # stamp of the last item handed on

    def push(self, stamp_s: float, rank: int, item: Any):
        """An input stamped stamp_s [s of simulated time]; rank orders kinds of equal stamp (lower first)."""
        stamp_s = float(stamp_s)
        self._arrivals += 1
        heapq.heappush(self._heap, (stamp_s, int(rank), self._arrivals, item))
        self.newest_s = max(self.newest_s, stamp_s)
        stream = self._regular.get(rank)
        if stream is not None:
            self.first_s = min(self.first_s, stamp_s)
            if stamp_s > stream[0] and math.isfinite(stream[0]):
                stream[1] = min(stream[1], stamp_s - stream[0])
            stream[0] = max(stream[0], stamp_s)

    def release(self) -> List[Tuple[float, Any]]:
        """[(stamp_s, item)] of every input at least lag_s older than the newest and earlier than the
        next message due on every regular stream that has not stopped (none while a regular stream
        has not been seen, for stopped_after_s), in time order."""
        limit_s = self.newest_s - self.lag_s + 1e-9  # 1e-9: stamps on a grid of steps
        newest_regular_s = max((newest_s for newest_s, _ in self._regular.values()), default=-math.inf)
        for newest_s, gap_s in self._regular.values():
            if not math.isfinite(newest_s):  # not seen yet
                if not newest_regular_s - self.first_s > self.stopped_after_s:
                    return []
            elif self.newest_s - newest_s <= self.stopped_after_s:
                # short of its next message's stamp; up to its newest while its gap is not known
                limit_s = min(limit_s, newest_s + gap_s - 1e-9 if math.isfinite(gap_s) else newest_s + 1e-9)
        return self._pop_until(limit_s)

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
