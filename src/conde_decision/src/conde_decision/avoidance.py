"""Obstacle avoidance by a lane change and back (D3), and the working zone's temporary lane (D4).
Pure Python, no ROS.

Inputs per lane measurement: the lateral offset conde_tracking measured (against the lane it
tracks), whether it is usable, the distance driven [m], the current state's command.lane
(own | other), and the obstacles of the measurement (boxes and cones: distance ahead to their near
edge at the floor, lateral extent at their base from the tracked lane's centre line).

* The robot's own lane is the lane it drove in before the change (the right lane: traffic keeps
  right); the other lane is its left neighbour, lane_spacing_m to the left: the spacing
  conde_tracking measured (from the line separation), lane_spacing_m of the config until it
  measured one.  An obstacle blocks the own lane when its base reaches into +-block_half_width_m
  of the own lane's centre.
* The offset reference moves (in the own lane's frame) toward 0 (lane own) or the spacing (lane
  other) by one spacing per change_length_m (on the way back return_length_m) driven: a ramp, so
  the robot changes lanes along an S of that length; while it moves, the heading reference is the
  ramp's direction (atan(spacing / change_length_m), about 28 deg), so that the control law
  follows the ramp instead of fighting it with its heading term, and the reference given to the
  control is at most max_offset_error_m from the robot's offset: the control law (offset gain 3.6
  times its heading gain) then turns the robot at most about 8 deg more than the ramp.  Without
  these the robot lagged, then turned 60-70 deg off the lane, where the lane measurement's offset
  is tens of cm off.
* The way back is laid along the lane (the distance driven times the cosine of the heading error)
  and lands: from return_ease_per_m / spacing of it on, the reference approaches the own lane's
  centre at return_ease_per_m times what remains (heading reference the slope of that curve), and is
  put on it return_end_m away.  Before, it ran by the distance driven straight into the centre: to
  keep pace the robot crossed at asin(0.78) = 51 deg (59 deg by ground truth, D4 v2, ODE), reached
  the centre at that angle, went 10 cm past it and touched the outer line.
* The ramp's direction (and so its slope) does not jump: it grows by at most heading_ref_rate_per_m
  per m driven from min_ramp_rad, and is at most the heading at which Conde's rear corner on the
  far side (rear_corner_back_m behind base_footprint, rear_corner_side_m to the side) stays
  rear_clearance_m inside the edge the robot moves away from (the start lane's outer line's centre,
  half a spacing beyond it), placed by the reference or the robot, whichever is nearer that edge
  (rear_swing_heading_rad): the robot turns about base_footprint, near its front, so a turn swings
  the rear outwards.  Started at once at the ramp's direction (0.46 rad; 0.66 on the way back) the
  rear swung 0.19 m out and touched the outer line of a narrow lane (D3, Bullet, track seed 4).
* conde_tracking says which lane it measured (lane_index: 0 the right lane, 1 the left one, -1 not
  known): during a lane change and back, the tracked lane's centre lies lane_index spacings left
  of the own lane's (lane_shift_m), and the robot's offset from the own lane is the tracker's plus
  that.  Where the lane is not known (lines seen too briefly, a junction), the offset is
  dead-reckoned from the distance driven and the heading error (the same against either lane: they
  are parallel), the tracked lane taken as the whole number of spacings that best explains the
  tracker's offset, and a tracker offset with both lines fitted within anchor_tolerance_m of the
  dead-reckoned one re-anchors it.  Without a usable lane the heading error is the last usable one
  plus the turn since then by odometry (not integrated at all without odometry).  Offset and
  reference go to conde_control in the own lane's frame.
* While active, a usable measurement whose heading error is more than heading_gate_rad (plus
  heading_gate_per_m per m driven since the last one taken: the lane turns under the robot) from
  the one dead-reckoned by odometry is not taken (lane_rejected): the offset is dead-reckoned and the
  heading given to the control is the dead-reckoned one (heading_error_rad).  At 60-70 deg off the
  lane the tracker fits lines that are not the lane's (D3, Bullet, track seed 2: -0.45 rad read
  at -1.1 by ground truth, then +0.43 at -1.23, with lane_index 0 on the lane's centre line, 0.31 m
  off): taken, they turned the robot round on the road.  The lane's direction by odometry follows the
  measurements taken by at most lane_turn_rad_per_m per m driven since the one taken before: a run of fits
  each within the gate of the last but drifting together (D3, track seed 11, lap 2, crossing the
  dashed line in the north loop: -0.64 to -1.25 rad in 0.1 m, ground truth about -0.5) no longer
  carries the gate and the dead-reckoned heading along with it.
* Events: obstacle_ahead (a blocker's near edge ahead, within edge_seen_from_m..avoid_trigger_m),
  lane_changed (lane other, the reference is on the other lane and the robot within
  settle_tolerance_m of it), obstacle_passed (lane other, every blocker seen is avoid_clearance_m
  behind the robot along the own lane (own_arc_m): its far end is its near edge plus box_depth_m or
  cone_depth_m; cones in a row keep moving it on), lane_returned (lane own after a change, the
  reference back at 0 and the
  robot within settle_tolerance_m of it, heading along the lane within return_heading_rad).
* Events the avoid states cannot take (a fork or a loop's end met on the other lane:
  DELAYED_EVENTS) wait in EventDelay until a state takes them, for at most max_delay_m driven.
"""
import math
from dataclasses import dataclass, field, fields
from typing import List, Optional, Sequence, Tuple

from conde_decision.road_distance import road_direction_rad

BOX = "box"
CONE = "cone"


@dataclass(frozen=True)
class AvoidanceConfig:
    """Track facts and tuning; the initial values are the defaults (the decision node's parameters
    override them by name)."""

    # own lane centre to the other lane's centre [m] (2 x lane_offset_m): only until conde_tracking measured it
    lane_spacing_m: float = 0.782
    block_half_width_m: float = 0.25  # an obstacle reaching this close to the own lane's centre blocks it [m]
    # start the lane change when a blocker's near edge is this close [m] (seen up to 2 m; in a curve its
    # lane extents from the fitted lane, 1.3 m long, are off to the curve's inside beyond about 1.8 m)
    avoid_trigger_m: float = 1.6
    change_length_m: float = 1.5  # the reference crosses one lane spacing over this distance driven [m]
    # ... and back over this one: the referee allows the other lane only within 1.5 m of arc of the box
    return_length_m: float = 1.0
    # On the way back the reference approaches the own lane's centre no faster than this times its
    # remaining distance [1/m] (an exponential landing from return_ease_per_m / spacing of the way on),
    # so that the robot arrives heading along the lane ...
    return_ease_per_m: float = 4.0
    # ... and it is put on the centre when this close [m]
    return_end_m: float = 0.02
    max_offset_error_m: float = 0.04  # the reference given to the control is at most this far from the robot [m]
    # Return once the blockers' far ends are this far behind base_footprint [m]: Conde's footprint
    # reaches 0.443 m behind it (base_footprint is near its front), but the way back is a ramp: its
    # rear is past the far end before the robot is half way back, and turning right swings the rear
    # away from the blocker.
    avoid_clearance_m: float = 0.15
    # A blocker's far end is taken from sightings of its near edge at least this far ahead [m]
    # (beside the robot the cameras see only the part of it still ahead: the near edge is cut).
    edge_seen_from_m: float = 0.05
    anchor_tolerance_m: float = 0.3  # the tracker within this of the dead-reckoned offset re-anchors it [m]
    box_depth_m: float = 0.6  # a box's length along the road (hidden behind its near face) [m]
    cone_depth_m: float = 0.15  # a cone's base diameter [m]
    settle_tolerance_m: float = 0.1  # lane_changed / lane_returned within this of the lane's centre [m]
    # ... lane_returned also heading along the own lane within this [rad]: ended at an angle (D3, lap 2: 0.34 s
    # earlier than on the way it passed) the follower took the full offset and the robot overshot onto the edge line
    return_heading_rad: float = 0.15
    max_delay_m: float = 2.0  # a delayed fork / merge event is dropped after this distance driven [m]
    # While active, a measurement whose heading error is this far [rad] from the one dead-reckoned by
    # odometry since the last measurement taken is not taken ...
    heading_gate_rad: float = 0.4
    # ... plus this per m driven since then [rad/m] (the lane's turn under the robot: 1 / 0.97 m, the
    # tightest curve, a fork's arc)
    heading_gate_per_m: float = 1.0
    # While active, the lane's direction by odometry follows the measurements taken by at most this per m
    # driven since the one before [rad/m] (twice the tightest lane a lane change meets, 1 / 0.97 m: the junctions'
    # 0.609 m arcs wait for its end, DELAYED_EVENTS): a run of fits each within the gate
    # of the one before, but drifting (D3, track seed 11, lap 2, the north loop: -0.64, -0.79, -0.90, -1.07,
    # -1.25 rad in 0.1 m, ground truth -0.48), no longer carries the gate and the dead-reckoned heading along
    lane_turn_rad_per_m: float = 2.0
    # Conde's rear corners: this far behind base_footprint [m] ...
    rear_corner_back_m: float = 0.443
    # ... and this far to each side of it [m] (its body 0.373 m wide)
    rear_corner_side_m: float = 0.187
    # While a lane change or the way back turns the robot, its rear corner on the far side stays this far
    # inside the edge it starts from (half a lane spacing beyond the start lane's centre: the line's
    # centre) [m]: half the widest line (0.05 m) plus a margin for the control's lag and overshoot
    rear_clearance_m: float = 0.12
    # ... and the ramp's direction grows by at most this per m driven [rad/m] (no heading step)
    heading_ref_rate_per_m: float = 2.0
    # ... but the ramp heads at least this far off the lane [rad] (it moves from the first step on, and a
    # robot near that edge still changes lanes)
    min_ramp_rad: float = 0.1

    def check(self) -> "AvoidanceConfig":
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
                raise ValueError("%s: expected a finite number > 0, got %r" % (f.name, value))
        return self


@dataclass(frozen=True)
class Obstacle:
    kind: str  # BOX or CONE
    near_x_m: float  # ahead of base_footprint to the near edge at the floor [m]
    lane_y_min_m: float  # lateral extent at the base from the tracked lane's centre line, + = left [m]
    lane_y_max_m: float


@dataclass
class AvoidanceStep:
    events: List[str] = field(default_factory=list)
    offset_ref_m: float = 0.0  # lateral offset reference in the own lane's frame [m]
    control_ref_m: float = 0.0  # ... for the control: within max_offset_error_m of own_lane_offset_m [m]
    heading_ref_rad: float = 0.0  # heading reference: the ramp's direction while it moves (+ = left) [rad]
    own_lane_offset_m: float = float("nan")  # the robot from the own lane's centre (+ = left) [m]
    active: bool = False  # a lane change or the way back: control on own_lane_offset_m and offset_ref_m
    # the heading error dead-reckoned with [rad] (nan: not known); the control's when lane_rejected
    heading_error_rad: float = float("nan")
    lane_rejected: bool = False  # a usable measurement not taken: its heading is not the odometry's


class Avoidance:
    def __init__(self, config: AvoidanceConfig = AvoidanceConfig()):
        self.config = config.check()
        self.ref_m = 0.0  # offset reference in the own lane's frame [m]
        self.lane_shift_m = 0.0  # the tracked lane's centre from the own lane's centre (+ = left) [m]
        self.far_end_m: Optional[float] = None  # own_arc_m at which the last blocker ends [m]
        # Distance along the own lane [m]: the distance driven, plus the offset from the own lane times
        # the turn by odometry (in a left curve the robot on the other lane, inside, drives a shorter
        # arc than the own lane's: a box's depth along the own lane is a shorter drive beside it).
        self.own_arc_m = 0.0
        self._last_yaw_rad: Optional[float] = None
        self.changed = False  # a lane change happened and the robot is not back yet
        self.own_offset_m: Optional[float] = None  # dead-reckoned and re-anchored, while active [m]
        self.spacing_m = config.lane_spacing_m  # the lanes' centres apart: the last measured [m]
        self.lane_yaw_rad: Optional[float] = None  # the lane's direction by odometry at the last usable frame [rad]
        self._taken_m = 0.0  # travelled_m at the last usable frame taken [m]
        self._last_travelled_m: Optional[float] = None
        self._ramp_rad = 0.0  # the ramp's direction at the last step [rad], 0 while the reference stands

    @property
    def active(self) -> bool:
        return self.changed or self.ref_m != 0.0

    def blockers(self, obstacles: Sequence[Obstacle]) -> List[Obstacle]:
        """The obstacles that reach into the own lane (in the own lane's frame)."""
        w, s = self.config.block_half_width_m, self.lane_shift_m
        return [o for o in obstacles if o.lane_y_min_m + s <= w and o.lane_y_max_m + s >= -w]

    def step(self, lane_offset_m: float, lane_ok: bool, travelled_m: float, lane_command: str,
             obstacles: Sequence[Obstacle] = (), heading_error_rad: float = 0.0,
             both_lines: bool = True, lane_index: int = -1, lane_spacing_m: float = float("nan"),
             yaw_rad: Optional[float] = None, tracked_shift_m: float = 0.0) -> AvoidanceStep:
        """One lane measurement: its offset [m], whether usable, the distance driven so far [m], the
        state's command.lane, the obstacles, the heading error [rad], whether both lines were fitted
        (only such a measurement re-anchors the dead-reckoned offset), which lane it measured (0
        right, 1 left, -1 not known), the lanes' spacing it measured [m] and the robot's heading
        by odometry [rad] (unwrapped; None: no odometry).  tracked_shift_m [m]: the tracked lane's centre
        from the own lane's as the caller places it (lane_frame.py: not 0 only where the tracker may
        measure the lane on the left, after a right fork crossed straight): outside a lane change the
        obstacles' lane extents are taken from it, and a lane change starts from it."""
        c = self.config
        out = AvoidanceStep()
        driven_m = 0.0 if self._last_travelled_m is None else max(0.0, travelled_m - self._last_travelled_m)
        self._last_travelled_m = travelled_m
        turned_rad = 0.0 if yaw_rad is None or self._last_yaw_rad is None else yaw_rad - self._last_yaw_rad
        self._last_yaw_rad = yaw_rad
        if self.own_offset_m is not None and driven_m > 0.0:
            self.own_arc_m += max(0.0, driven_m + self.own_offset_m * turned_rad)
        else:
            self.own_arc_m += driven_m
        if lane_ok and math.isfinite(lane_spacing_m) and lane_spacing_m > 0:
            self.spacing_m = lane_spacing_m
        spacing_m = self.spacing_m
        other = lane_command == "other"
        if other:
            self.changed = True
        since_taken_m = max(0.0, travelled_m - self._taken_m)  # driven since the last measurement taken [m]
        if self.active and lane_ok and not self._plausible(heading_error_rad, yaw_rad, since_taken_m):
            lane_ok, out.lane_rejected = False, True
        if lane_ok:
            self._taken_m = travelled_m
        heading_rad = self._heading(lane_ok, heading_error_rad, yaw_rad, since_taken_m)
        out.heading_error_rad = float("nan") if heading_rad is None else heading_rad
        if self.active:
            if self.own_offset_m is None:
                self.own_offset_m = lane_offset_m + tracked_shift_m if lane_ok else 0.0
            elif heading_rad is not None:
                self.own_offset_m += driven_m * math.sin(heading_rad)
            if lane_ok and lane_index in (0, 1):
                self.lane_shift_m = lane_index * spacing_m
                self.own_offset_m = lane_offset_m + self.lane_shift_m
            elif lane_ok:
                self.lane_shift_m = spacing_m * round((self.own_offset_m - lane_offset_m) / spacing_m)
                if both_lines and abs(lane_offset_m + self.lane_shift_m - self.own_offset_m) <= c.anchor_tolerance_m:
                    self.own_offset_m = lane_offset_m + self.lane_shift_m
        else:
            self.own_offset_m, self.lane_shift_m = None, tracked_shift_m
        target_m = spacing_m if other else 0.0
        direction = 1.0 if target_m > self.ref_m else -1.0
        # the rear corner's room from the edge the robot moves away from, on the reference or the robot
        # (whichever is nearer that edge), and the ramp's direction that keeps it inside
        edge_m = target_m - direction * 1.5 * spacing_m
        nearest_m = self.ref_m if self.own_offset_m is None else direction * min(
            direction * self.ref_m, direction * self.own_offset_m)
        swing_rad = rear_swing_heading_rad(direction * (nearest_m - edge_m) - c.rear_clearance_m,
                                           c.rear_corner_back_m, c.rear_corner_side_m)
        bound_rad = max(c.min_ramp_rad, min(self._ramp_rad + c.heading_ref_rate_per_m * driven_m, swing_rad))
        if other:
            slope = min(spacing_m / c.change_length_m, math.tan(bound_rad))
            slew_m = slope * driven_m
            if abs(target_m - self.ref_m) <= slew_m + 1e-9:
                self.ref_m = target_m
            else:
                self.ref_m += math.copysign(slew_m, target_m - self.ref_m)
        else:
            slope = min(spacing_m / c.return_length_m, math.tan(bound_rad))
            # the way back is laid along the lane: the distance driven times cos(heading error)
            along_m = driven_m if heading_rad is None else driven_m * max(0.0, math.cos(heading_rad))
            left_m = return_remaining_m(abs(target_m - self.ref_m), along_m, slope, c.return_ease_per_m)
            self.ref_m = target_m if left_m <= c.return_end_m else math.copysign(left_m, self.ref_m)  # target 0
            slope = min(slope, c.return_ease_per_m * left_m)
        self._ramp_rad = 0.0
        if self.ref_m != target_m:
            self._ramp_rad = math.atan(slope)
            out.heading_ref_rad = math.copysign(self._ramp_rad, target_m - self.ref_m)
        if self.own_offset_m is not None:
            own_offset_m = self.own_offset_m
        else:
            own_offset_m = lane_offset_m if lane_ok else float("nan")
        out.own_lane_offset_m = own_offset_m

        blocking = self.blockers(obstacles)
        for o in blocking:
            if (other or o.near_x_m <= c.avoid_trigger_m) and o.near_x_m >= c.edge_seen_from_m:
                end_m = self.own_arc_m + o.near_x_m + (c.box_depth_m if o.kind == BOX else c.cone_depth_m)
                self.far_end_m = end_m if self.far_end_m is None else max(self.far_end_m, end_m)
        # ahead: its near edge seen in front (beside the robot the cameras see the rest of a box it passes)
        if any(c.edge_seen_from_m <= o.near_x_m <= c.avoid_trigger_m for o in blocking):
            out.events.append("obstacle_ahead")
        settled = (math.isfinite(own_offset_m) and abs(own_offset_m - target_m) <= c.settle_tolerance_m
                   and self.ref_m == target_m)
        if other and settled:
            out.events.append("lane_changed")
        if other and self.far_end_m is not None and self.own_arc_m >= self.far_end_m + c.avoid_clearance_m:
            out.events.append("obstacle_passed")
            self.far_end_m = None
        along_rad = heading_rad is not None and abs(heading_rad) <= c.return_heading_rad
        if not other and self.changed and settled and along_rad:
            out.events.append("lane_returned")
            self.changed = False
            self.far_end_m = None
        out.offset_ref_m = out.control_ref_m = self.ref_m
        if self.active and math.isfinite(own_offset_m):
            limit_m = c.max_offset_error_m
            out.control_ref_m = own_offset_m + min(max(self.ref_m - own_offset_m, -limit_m), limit_m)
        out.active = self.active
        return out

    def _plausible(self, heading_error_rad: float, yaw_rad: Optional[float], since_taken_m: float) -> bool:
        """Whether a usable measurement's heading error is near the one dead-reckoned by odometry since
        the last measurement taken (true when that is not known)."""
        if yaw_rad is None or self.lane_yaw_rad is None:
            return True
        c = self.config
        allowed_rad = c.heading_gate_rad + c.heading_gate_per_m * since_taken_m
        return abs(heading_error_rad - (yaw_rad - self.lane_yaw_rad)) <= allowed_rad

    def _heading(self, lane_ok: bool, heading_error_rad: float, yaw_rad: Optional[float],
                 since_taken_m: float) -> Optional[float]:
        """The heading error to dead-reckon with [rad]: the measured one when the lane is usable (the
        lane's direction by odometry kept: while active, moved toward the measured one by at most
        lane_turn_rad_per_m per m driven since the last measurement taken, since_taken_m; without odometry
        it is None and the next one is taken whole), else that direction's difference to the
        odometry's heading; None when neither is known."""
        if lane_ok and math.isfinite(heading_error_rad):
            measured_rad = road_direction_rad(yaw_rad, heading_error_rad)
            if self.active and measured_rad is not None and self.lane_yaw_rad is not None:
                turn_rad = self.config.lane_turn_rad_per_m * since_taken_m
                self.lane_yaw_rad += min(max(measured_rad - self.lane_yaw_rad, -turn_rad), turn_rad)
            else:
                self.lane_yaw_rad = measured_rad
            return heading_error_rad
        if yaw_rad is None or self.lane_yaw_rad is None:
            return None
        return yaw_rad - self.lane_yaw_rad


def return_remaining_m(remaining_m: float, along_m: float, slope: float, ease_per_m: float) -> float:
    """The way back's reference [m from the own lane's centre] after along_m [m] more along the lane:
    it moves at slope [m per m] while remaining_m > slope / ease_per_m, then at ease_per_m times what
    remains (an exponential approach)."""
    knee_m = slope / ease_per_m
    if remaining_m > knee_m:
        linear_m = min(along_m, (remaining_m - knee_m) / slope)
        remaining_m -= slope * linear_m
        along_m -= linear_m
    return remaining_m * math.exp(-ease_per_m * along_m) if remaining_m <= knee_m + 1e-12 else remaining_m


def rear_swing_heading_rad(room_m: float, back_m: float, side_m: float) -> float:
    """The largest heading [rad, >= 0] off the lane at which a rear corner back_m behind the robot's
    turning point and side_m to the side [m] swings at most room_m [m] out from the turning point's
    line along the lane (turning left, the right rear corner: back_m sin + side_m cos of the heading);
    0 when even heading along the lane leaves no room."""
    reach_m = math.hypot(back_m, side_m)
    if room_m >= reach_m:
        return math.pi / 2
    return max(0.0, math.asin(max(-1.0, room_m / reach_m)) - math.atan2(side_m, back_m))


# Events that the avoid states do not take: they wait until a state does (EventDelay).
DELAYED_EVENTS = ("fork_left", "fork_right", "fork_straight", "merge_left", "merge_right")


class EventDelay:
    """Keeps a fork or merge event that came while the state could not take it (the robot on the
    other lane), for at most max_delay_m driven [m]: offer() it when it comes, due() at every step."""

    def __init__(self, max_delay_m: float):
        self.max_delay_m = max_delay_m
        self.event: Optional[str] = None
        self.since_m = 0.0  # travelled_m when it came [m]

    def offer(self, event: str, travelled_m: float, taken: bool) -> None:
        """An event produced at travelled_m [m]; taken: the current state takes it (or need not)."""
        if event in DELAYED_EVENTS and not taken:
            self.event, self.since_m = event, travelled_m

    def due(self, travelled_m: float, takes) -> Tuple[Optional[str], str]:
        """(the kept event, if takes(event) now, else None; a note when it was dropped as too old)."""
        if self.event is None:
            return None, ""
        event = self.event
        if takes(event):
            self.event = None
            return event, ""
        if travelled_m - self.since_m > self.max_delay_m:
            self.event = None
            return None, "%s dropped: no state took it within %.1f m" % (event, self.max_delay_m)
        return None, ""
