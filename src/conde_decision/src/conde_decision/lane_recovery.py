"""Recovering a lost lane.  Pure Python, no ROS.

After the lane-lost hold (no confident lane for lane_lost_timeout_s) a robot that stands still
sees the same view for ever: standing over a line, no lane comes back.  LaneRecovery moves it so
that the cameras see something else, slowly and a bounded distance at a time:

1. ``back``: reverse straight at speed_mps the way it came since the last confident lane (a robot
   without a confident lane holds its course), at most distance_m [m];
2. ``ahead``: forward at speed_mps for up to distance_m, steering back onto the lane as it was last
   seen, dead-reckoned by odometry: the road's direction there (heading less the measured heading
   error) and the lateral offset from it (the offset measured there plus the path's sideways part);
   only while that offset is within max_offset_m: from further off (or drifting further) the creep
   would steer by a lane dead reckoning puts beside the robot, so it does not start (or stops) and
   the try ends there.

The ways are net: forward counts +, backward - (the caller says which way the path since the last
step was driven), so that a robot still rolling forward as the try begins reverses that too, back
to where it saw its lane last, and the creep's reversing start does not count as its way ahead.

A confident lane seen in either phase ends the try: the lane follower takes over, at no more than
speed_mps until it has driven rejoin_m on a confident lane (``rejoin``): faster, conde_control's
turn-rate limits make it swing across the lane and lose it again.  Rejoining, it heads at most
rejoin_heading_rad toward the lane's centre (rejoin_heading_ref_rad): turning further, from 0.15-0.3 m
off, takes a narrow camera view off the lane, which is lost again.  The rejoin goes on after rejoin_m
until the robot is near enough the centre for that bound not to bite, at most reset_m.  After max_tries
tries without a lane the robot stands for good (gave_up, with a note saying why).  The count of
tries goes back to 0 once the robot has driven reset_m [m] with a confident lane.

Without odometry (no heading) there is no road direction: no recovery, the hold stays.
The caller decides when the robot may be moved (a state that drives along the lane, not a blind
manoeuvre or a state that stands)."""

import math
from dataclasses import dataclass
from typing import Optional

from conde_decision.road_distance import road_direction_rad

IDLE, BACK, AHEAD, REJOIN, GAVE_UP = "", "back", "ahead", "rejoin", "gave_up"


@dataclass(frozen=True)
class RecoveryConfig:
    speed_mps: float = 0.15  # |speed| while recovering [m/s]
    distance_m: float = 0.8  # longest way driven in each phase of a try [m]
    max_tries: int = 2  # tries (back + ahead) before the robot stands for good
    reset_m: float = 1.0  # the tries count from 0 again after this far driven on a confident lane [m]
    rejoin_m: float = 0.4  # after a try found the lane: at most speed_mps for this far on a confident lane [m]
    # the creep ahead starts, and goes on, only while the robot is within this of the lane's centre as
    # last seen (dead-reckoned) [m]: the lane's half width less a margin, so that it steers on a lane it
    # is in rather than onto one dead reckoning puts beside it
    max_offset_m: float = 0.35
    # rejoining, the follower heads at most this toward the lane's centre [rad]: within the cameras'
    # view of the lane (turning further toward it from 0.15-0.3 m off, up to 0.52 rad, a narrow view
    # loses the lane again and the second loss uses up a try) ...
    rejoin_heading_rad: float = 0.25
    # ... aiming at the centre as at a point this far ahead [m]: conde_control's heading / offset gain
    # ratio (10 / 36 m) makes that its own law within the bound (rejoin_heading_ref_rad)
    rejoin_approach_m: float = 0.28

    def check(self) -> "RecoveryConfig":
        for name in ("speed_mps", "distance_m", "reset_m", "rejoin_m", "max_offset_m", "rejoin_heading_rad",
                     "rejoin_approach_m"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError("recovery_%s: must be a finite number > 0, got %r" % (name, value))
        if not (isinstance(self.max_tries, int) and not isinstance(self.max_tries, bool) and self.max_tries >= 0):
            raise ValueError("recovery_max_tries: expected an integer >= 0, got %r" % (self.max_tries,))
        return self


def rejoin_heading_ref_rad(offset_error_m: float, config: RecoveryConfig) -> float:
    """The heading toward the lane's centre [rad] (+ = left of the lane's direction) the follower is
    to take while rejoining, from the offset from where it is to be [m] (+ = left): the offset's
    share of the law (-offset / rejoin_approach_m) within +-rejoin_heading_rad.  Given to the law as
    its heading reference with no offset error, it is the law itself where the bound does not bite."""
    heading_rad = -offset_error_m / config.rejoin_approach_m
    return max(-config.rejoin_heading_rad, min(config.rejoin_heading_rad, heading_rad))


def lost_lane_status(phase: str, tries: int, max_tries: int) -> str:
    """What the robot does while its lane is lost, for the node's throttled log line: holding (the
    state may not move, no odometry, recovery off), recovering (reversing / creeping ahead, which
    try) or given up."""
    if phase == BACK:
        return "recovering: reversing the way it came (try %d of %d)" % (tries, max_tries)
    if phase == AHEAD:
        return "recovering: creeping ahead onto the lane by odometry (try %d of %d)" % (tries, max_tries)
    if phase == GAVE_UP:
        return "the recovery gave up after %d tries: holding the robot" % tries
    return "holding the robot"


@dataclass(frozen=True)
class RecoveryCommand:
    """What the recovery asks for in this step (phase IDLE / GAVE_UP: nothing, the hold stays;
    REJOIN: the lane follower at no more than speed_mps)."""

    phase: str
    speed_mps: float = 0.0  # signed [m/s]
    heading_error_rad: float = 0.0  # robot heading less the road direction [rad] (+ = robot left of it)
    lateral_offset_m: float = 0.0  # from the lane's centre by dead reckoning [m] (+ = left)

    @property
    def active(self) -> bool:
        return self.phase in (BACK, AHEAD)


class LaneRecovery:
    def __init__(self, config: RecoveryConfig = RecoveryConfig()):
        self.config = config.check()
        self.phase = IDLE
        self.tries = 0
        self.road_direction_rad: Optional[float] = None  # at the last confident lane (odometry frame) [rad]
        self.note = ""  # set in the step where something worth logging happened
        self._ok_since_m: Optional[float] = None
        self.offset_m = 0.0  # from the lane's centre, dead-reckoned from the last confident lane [m] (+ = left)
        # the way driven since the last confident lane, net: forward +, backward - [m]
        self.since_lane_m = 0.0
        self._phase_m = 0.0  # the way driven in this phase, net (+ = forward) [m]
        self._phase_path_m = 0.0  # ... and its path length (either way) [m]
        self._travelled_m: Optional[float] = None  # at the last step (or confident lane) [m]

    def on_confident_lane(self, yaw_rad: Optional[float], heading_error_rad: float, lateral_offset_m: float,
                          travelled_m: float) -> None:
        """A confident lane measurement (outside blind manoeuvres): the road's direction and the
        offset from the lane's centre [m], and the end of any try."""
        direction_rad = road_direction_rad(yaw_rad, heading_error_rad)
        if direction_rad is not None:
            self.road_direction_rad = direction_rad
        self.offset_m = lateral_offset_m if math.isfinite(lateral_offset_m) else 0.0
        self.since_lane_m = 0.0
        self._travelled_m = travelled_m  # the way to here is in the measurement
        if self.phase in (BACK, AHEAD):
            self.note = "lane recovery: lane seen again (%s, try %d of %d)" % (
                self.phase, self.tries, self.config.max_tries)
            self.phase = REJOIN
            self._ok_since_m = None
        if self._ok_since_m is None:
            self._ok_since_m = travelled_m
        if self.phase == REJOIN and self._rejoined(travelled_m - self._ok_since_m):
            self.phase = IDLE
        if self.tries and travelled_m - self._ok_since_m >= self.config.reset_m:
            self.tries = 0

    def _rejoined(self, on_lane_m: float) -> bool:
        """The rejoin ends after rejoin_m on a confident lane once the robot is near enough its centre
        that the heading bound no longer bites (the follower's law from there is the rejoin's), and
        at the latest after reset_m (as the tries count from 0 again)."""
        c = self.config
        near_m = c.rejoin_heading_rad * c.rejoin_approach_m
        return on_lane_m >= c.rejoin_m and (abs(self.offset_m) <= near_m or on_lane_m >= c.reset_m)

    def step(self, lost: bool, may_move: bool, yaw_rad: Optional[float], travelled_m: float,
             backwards: bool = False) -> RecoveryCommand:
        """One step.  lost: the lane-lost hold is on; may_move: the state drives along the lane;
        yaw_rad: the odometry's unwrapped heading (None: unknown); travelled_m: path length [m]
        (grows driving either way); backwards: the path since the last step was driven backwards."""
        self.note = ""
        path_m = 0.0 if self._travelled_m is None else max(0.0, travelled_m - self._travelled_m)
        step_m = -path_m if backwards else path_m
        self._travelled_m = travelled_m
        self.since_lane_m += step_m
        self._phase_m += step_m
        self._phase_path_m += path_m
        if yaw_rad is not None and self.road_direction_rad is not None:
            self.offset_m += step_m * math.sin(yaw_rad - self.road_direction_rad)
        return self._step(lost, may_move, yaw_rad)

    def _step(self, lost: bool, may_move: bool, yaw_rad: Optional[float]) -> RecoveryCommand:
        if not lost:
            if self.phase in (BACK, AHEAD, GAVE_UP):  # the hold ended without a confident lane (a blind state)
                self.phase = IDLE
            return RecoveryCommand(self.phase, self.config.speed_mps if self.phase == REJOIN else 0.0)
        self._ok_since_m = None
        if self.phase == REJOIN:
            self.phase = IDLE
        if not may_move or yaw_rad is None or self.road_direction_rad is None:
            if self.phase in (BACK, AHEAD):
                self.phase = IDLE
            return RecoveryCommand(self.phase)
        c = self.config
        if self.phase == IDLE:
            if self.tries >= c.max_tries:
                self.phase = GAVE_UP
                self.note = ("lane recovery: no lane after %d tries (back and ahead %.2f m each): "
                             "standing" % (self.tries, c.distance_m))
                return RecoveryCommand(self.phase)
            self.tries += 1
            self._start(BACK)
        # back: to where the lane was seen last, at most distance_m; ahead: distance_m.  Net ways (a
        # robot still rolling forward when the try begins reverses that too); the path driven in a
        # phase bounds it whatever the direction says
        if self.phase == BACK and (self.since_lane_m <= 0.0 or -self._phase_m >= c.distance_m
                                   or self._phase_path_m >= 2.0 * c.distance_m):
            if abs(self.offset_m) > c.max_offset_m:  # the creep would steer by a lane it is not in
                return self._too_far_off("%.2f m off", "no creep ahead")
            self._start(AHEAD)
        elif self.phase == AHEAD and abs(self.offset_m) > c.max_offset_m:
            return self._too_far_off("the creep ahead came %.2f m off", "stopped")
        elif self.phase == AHEAD and (self._phase_m >= c.distance_m or self._phase_path_m >= 2.0 * c.distance_m):
            self.phase = IDLE
            self.note = "lane recovery: try %d of %d found no lane" % (self.tries, c.max_tries)
            return RecoveryCommand(self.phase)
        if self.phase == GAVE_UP:
            return RecoveryCommand(self.phase)
        if self.phase == BACK:  # straight back
            return RecoveryCommand(self.phase, -c.speed_mps)
        heading_error_rad = math.remainder(yaw_rad - self.road_direction_rad, 2.0 * math.pi)
        return RecoveryCommand(self.phase, c.speed_mps, heading_error_rad, self.offset_m)

    def _too_far_off(self, how: str, what: str) -> RecoveryCommand:
        """The try ends: the robot is further than max_offset_m from the lane's centre as last seen."""
        c = self.config
        self.phase = IDLE
        self.note = ("lane recovery: try %d of %d: " + how + " the lane's centre as last seen (odometry), more than "
                     "recovery_max_offset_m %.2f m: %s") % (self.tries, c.max_tries, self.offset_m, c.max_offset_m,
                                                            what)
        return RecoveryCommand(self.phase)

    def _start(self, phase: str) -> None:
        self.phase = phase
        self._phase_m = self._phase_path_m = 0.0
        if phase == BACK:
            what = "reversing %.2f m (the way it came)" % min(self.config.distance_m, max(0.0, self.since_lane_m))
        else:
            what = "creeping ahead up to %.2f m back onto the lane by odometry (%.2f m off its centre)" % (
                self.config.distance_m, self.offset_m)
        self.note = "lane recovery: try %d of %d, %s at %.2f m/s" % (
            self.tries, self.config.max_tries, what, self.config.speed_mps)
