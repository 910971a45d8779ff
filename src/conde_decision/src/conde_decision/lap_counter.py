"""Crossings of the crosswalk and laps of the track, with the lap times.  Pure Python, no ROS.

A lap is crossings_per_lap crossings; it is complete when the robot arrives at the crosswalk.
The first lap's time runs from the robot's first motion, each next one from the end of the last."""

from typing import List, Optional


class LapCounter:
    def __init__(self, crossings_per_lap: int):
        self.crossings_per_lap = crossings_per_lap
        self.crossings = 0
        self.laps = 0
        self.lap_times_s: List[float] = []
        self.lap_mark_s: Optional[float] = None  # start of the current lap [s] (None: not moved yet)

    def on_motion(self, time_s: float) -> None:
        """The robot is moving at time_s [s]: the first call starts the first lap."""
        if self.lap_mark_s is None:
            self.lap_mark_s = time_s

    def on_crossing(self, time_s: float) -> bool:
        """The robot arrived at the crosswalk at time_s [s]; True if that completes a lap."""
        self.crossings += 1
        if self.crossings % self.crossings_per_lap != 0:
            return False
        self.laps += 1
        self.lap_times_s.append(time_s - (self.lap_mark_s if self.lap_mark_s is not None else time_s))
        self.lap_mark_s = time_s
        return True
