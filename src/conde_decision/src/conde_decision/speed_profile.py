"""The commanded speed [m/s] for a state's speed command, ramped as conde_control ramps it.
Pure Python, no ROS.

``cruise``: cruise_speed_mps; ``stop``: 0; ``stop_at_crosswalk``: cruise, braking at
brake_decel_mps2 so as to stand stop_margin_m before the near edge of the crosswalk ahead;
``stop_at_finish``: the same, finish_margin_m before it (the end of trial: no panel left to read);
``creep`` / ``reverse`` (parking manoeuvres): +park_speed_mps / -park_speed_mps.  The
speed approaches its target at ramp_mps2, conde_control's acceleration limit, so that the speed
commanded is the speed the robot drives (the decision dead-reckons with it)."""

import math
from typing import Optional

from conde_common.rate_limit import RateLimiter
from conde_decision.parking import manoeuvre_speed_mps

#: the speed commands that brake for the crosswalk ahead
STOP_SPEEDS = ("stop_at_crosswalk", "stop_at_finish")


class SpeedProfile:
    def __init__(self, cruise_speed_mps: float, ramp_mps2: float, brake_decel_mps2: float, stop_margin_m: float,
                 park_speed_mps: float = 0.2, finish_margin_m: Optional[float] = None):
        self.cruise_speed_mps = cruise_speed_mps
        self.park_speed_mps = park_speed_mps
        self.brake_decel_mps2 = brake_decel_mps2
        self.stop_margin_m = stop_margin_m
        self.finish_margin_m = stop_margin_m if finish_margin_m is None else finish_margin_m
        self._ramp = RateLimiter(ramp_mps2)
        self.stop_latched = False  # stop_at_crosswalk has committed to stopping at this crosswalk

    @property
    def v_mps(self) -> float:
        """The speed commanded in the last step [m/s]."""
        return self._ramp.value

    def unlatch(self) -> None:
        """Forget the crosswalk committed to (a new state, or the robot left the crosswalk)."""
        self.stop_latched = False

    def step(self, speed: str, to_near_edge_m: Optional[float], dt_s: float, hold: bool = False,
             target_mps: Optional[float] = None, max_mps: Optional[float] = None) -> float:
        """The speed [m/s] after dt_s [s] for the command `speed`, with the near edge of the
        crosswalk ahead to_near_edge_m [m] away (None: unknown); hold: ramp to 0 instead;
        target_mps: ramp to that instead of either (the lane recovery); max_mps: the command's
        target but no more than that (the lane recovery's rejoin).  Only a step that drives by the
        command commits to the crosswalk ahead (stop_latched)."""
        if target_mps is None:
            if hold:
                target_mps = 0.0
            else:
                self._latch(speed, to_near_edge_m)
                target_mps = self.target_mps(speed, to_near_edge_m)
                if max_mps is not None:
                    target_mps = min(max_mps, target_mps)
        return self._ramp.step(target_mps, dt_s)

    def target_mps(self, speed: str, to_near_edge_m: Optional[float]) -> float:
        """The target [m/s] of the command `speed` with the near edge of the crosswalk ahead
        to_near_edge_m [m] away: a query, it changes nothing (step() commits to the crosswalk)."""
        if speed == "stop":
            return 0.0
        if speed == "cruise":
            return self.cruise_speed_mps
        manoeuvre_mps = manoeuvre_speed_mps(speed, self.park_speed_mps)
        if manoeuvre_mps is not None:
            return manoeuvre_mps
        # stop_at_crosswalk / stop_at_finish: a constant-deceleration profile ending stop_margin_m /
        # finish_margin_m before the near edge.  Once committed it holds even if dead reckoning
        # overshoots the edge; a state that begins with the robot already on the crosswalk drives on
        # to the next one.
        if not self._brakes_for(to_near_edge_m):
            return self.cruise_speed_mps
        margin_m = self.finish_margin_m if speed == "stop_at_finish" else self.stop_margin_m
        room_m = max(0.0, to_near_edge_m - margin_m)
        return min(self.cruise_speed_mps, math.sqrt(2.0 * self.brake_decel_mps2 * room_m))

    def _brakes_for(self, to_near_edge_m: Optional[float]) -> bool:
        """stop_at_crosswalk / stop_at_finish brake for the crosswalk ahead: it is known and ahead, or
        committed to."""
        return to_near_edge_m is not None and (to_near_edge_m >= 0.0 or self.stop_latched)

    def _latch(self, speed: str, to_near_edge_m: Optional[float]) -> None:
        """The update: a command that brakes for the crosswalk ahead commits to it."""
        if speed in STOP_SPEEDS and self._brakes_for(to_near_edge_m):
            self.stop_latched = True
