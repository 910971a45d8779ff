"""Lap timing from a car's ground-truth positions (pure Python; the lap_timer node feeds it).

A lap is timed from one forward crossing of the start/finish line to the next, and counts only
if the car crossed every checkpoint line forward, in order, in between (so wiggling across the
line, or reversing over it and back, is no lap). The first forward crossing starts the first
lap: cars start behind the line. Crossing instants and the distance are interpolated between
the samples. A backward crossing of the start line abandons the lap in progress; so does a
jump between samples longer than `max_jump_m` (the world was reset, the car was moved) or time
going backwards (the simulation restarted).

Lines are given by their two ends, right end first as seen facing the race direction; forward
is then the direction of (left - right) turned by -90 degrees.

Units: metres, seconds, metres per second.
"""

import csv
import io
import math
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

Point = Tuple[float, float]


@dataclass(frozen=True)
class Line:
    right: Point
    left: Point

    def __post_init__(self):
        values = tuple(self.right) + tuple(self.left)
        if len(values) != 4 or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
            raise ValueError("a line is [[x, y], [x, y]] of finite numbers, got %r" % ([self.right, self.left],))
        if self.right[0] == self.left[0] and self.right[1] == self.left[1]:
            raise ValueError("the two ends of a line must differ, got %r twice" % (self.right,))

    def crossing(self, p0: Point, p1: Point) -> Optional[Tuple[float, int]]:
        """Where the move p0 -> p1 crosses this line segment: (fraction of the move in [0, 1],
        +1 forward / -1 backward), or None. A move that ends on the line crosses it; one that
        starts on it does not (it was counted by the move before)."""
        (ax, ay), (bx, by) = self.right, self.left
        ex, ey = bx - ax, by - ay                      # along the line, right end -> left end
        d0 = ey * (p0[0] - ax) - ex * (p0[1] - ay)     # ahead of the line (> 0) or behind (< 0)
        d1 = ey * (p1[0] - ax) - ex * (p1[1] - ay)
        if d0 < 0 <= d1:
            direction = 1
        elif d0 > 0 >= d1:
            direction = -1
        else:
            return None
        u = d0 / (d0 - d1)
        x, y = p0[0] + u * (p1[0] - p0[0]), p0[1] + u * (p1[1] - p0[1])
        along = ((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey)
        if not 0.0 <= along <= 1.0:
            return None                                # passed beside the line's ends
        return u, direction


@dataclass(frozen=True)
class Lap:
    car: str
    number: int                 # 1, 2, ... per car
    start_time_s: float
    end_time_s: float
    distance_m: float           # driven along the ground-truth path
    top_speed_mps: float        # largest ground-truth speed sampled within the lap

    @property
    def time_s(self) -> float:
        return self.end_time_s - self.start_time_s

    @property
    def average_speed_mps(self) -> float:
        return self.distance_m / self.time_s if self.time_s > 0 else 0.0


class LapCounter:
    """Laps of one car. Call update() with each ground-truth sample, in time order."""

    def __init__(self, car: str, start_line: Line, checkpoints: Sequence[Line] = (), max_jump_m: float = 1.0):
        if max_jump_m <= 0:
            raise ValueError("max_jump_m must be > 0, got %r" % max_jump_m)
        self.car = car
        self.start_line = start_line
        self.checkpoints = tuple(checkpoints)
        self.max_jump_m = max_jump_m
        self.laps: List[Lap] = []
        self.abandoned = 0          # laps started and not finished (reset, backward crossing, jump)
        self._last = None           # (t, x, y) of the previous sample
        self._lap_start_s = None    # None: no lap in progress
        self._distance_m = 0.0
        self._top_mps = 0.0
        self._next_checkpoint = 0

    @property
    def lap_in_progress(self) -> bool:
        return self._lap_start_s is not None

    def _abandon(self) -> None:
        if self._lap_start_s is not None:
            self.abandoned += 1
        self._lap_start_s = None

    def _start(self, t_s: float, distance_m: float, speed_mps: float) -> None:
        self._lap_start_s = t_s
        self._distance_m = distance_m
        self._top_mps = speed_mps
        self._next_checkpoint = 0

    def update(self, t_s: float, x_m: float, y_m: float, speed_mps: float) -> Optional[Lap]:
        """Feeds one sample; returns the lap it completes, if any."""
        if not all(math.isfinite(v) for v in (t_s, x_m, y_m, speed_mps)):
            return None
        last, self._last = self._last, (t_s, x_m, y_m)
        if last is None:
            return None
        t0, x0, y0 = last
        if t_s <= t0:
            if t_s < t0:
                self._abandon()     # time went backwards: a new run
            return None
        step_m = math.hypot(x_m - x0, y_m - y0)
        if step_m > self.max_jump_m:
            self._abandon()
            return None

        for i, line in enumerate(self.checkpoints):
            hit = line.crossing((x0, y0), (x_m, y_m))
            if hit is None:
                continue
            if hit[1] > 0 and i == self._next_checkpoint:
                self._next_checkpoint += 1
            elif hit[1] < 0 and i == self._next_checkpoint - 1:
                self._next_checkpoint -= 1

        hit = self.start_line.crossing((x0, y0), (x_m, y_m))
        if hit is None:
            if self._lap_start_s is not None:
                self._distance_m += step_m
                self._top_mps = max(self._top_mps, speed_mps)
            return None
        u, direction = hit
        t_cross = t0 + u * (t_s - t0)
        if direction < 0:
            self._abandon()
            return None
        lap = None
        if self._lap_start_s is not None:
            if self._next_checkpoint == len(self.checkpoints):
                lap = Lap(self.car, len(self.laps) + 1, self._lap_start_s, t_cross, self._distance_m + u * step_m,
                          self._top_mps)
                self.laps.append(lap)
            else:
                self.abandoned += 1  # missed a checkpoint: this crossing starts a new lap
        self._start(t_cross, (1.0 - u) * step_m, speed_mps)
        return lap


CSV_COLUMNS = ("car", "lap", "start_time_s", "end_time_s", "lap_time_s", "distance_m", "average_speed_mps",
               "top_speed_mps")


def csv_row(lap: Lap) -> List[str]:
    return [lap.car, str(lap.number), "%.3f" % lap.start_time_s, "%.3f" % lap.end_time_s, "%.3f" % lap.time_s,
            "%.3f" % lap.distance_m, "%.3f" % lap.average_speed_mps, "%.3f" % lap.top_speed_mps]


def csv_text(laps: Sequence[Lap]) -> str:
    """The CSV of laps (header, then one row per lap, in the order given)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for lap in laps:
        writer.writerow(csv_row(lap))
    return out.getvalue()


def summary_lines(counters: Sequence[LapCounter]) -> List[str]:
    """A table per car: laps, best and mean lap time, best average speed, top speed."""
    lines = ["car     laps  best lap [s]  mean lap [s]  top speed [m/s]  abandoned"]
    for c in counters:
        if c.laps:
            times = [lap.time_s for lap in c.laps]
            lines.append("%-7s %4d  %12.3f  %12.3f  %15.2f  %9d" % (
                c.car, len(c.laps), min(times), sum(times) / len(times), max(lap.top_speed_mps for lap in c.laps),
                c.abandoned))
        else:
            lines.append("%-7s %4d  %12s  %12s  %15s  %9d" % (c.car, 0, "-", "-", "-", c.abandoned))
    return lines
