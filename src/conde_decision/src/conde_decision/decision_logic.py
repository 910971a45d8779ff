"""The decision logic of the Conde driving stack: lane measurements and panel signals in,
control reference and state out.  Pure Python, no ROS.

It turns its inputs into the events of state_machine.EVENTS, feeds them to the state machine
loaded from YAML, and turns the current state's command into the fields of
conde_msgs/ControlReference.  What it knows about the track (defaults in DecisionConfig, from
worlds/tracks/competition_track.geometry.yaml):

* The robot starts standing at the crosswalk (start zone), northbound in the east lane of the
  central straight.  Lap after lap it passes the crosswalk alternately northbound and southbound
  (the two loops of the "8" are driven in opposite senses), so one lap of the track is
  `crossings_per_lap` = 2 crossings.  A crossing is counted when the robot reaches the crosswalk
  after having left it; the start does not count.  Laps are counted at the end of a crossing's
  approach (the robot arriving at the crosswalk), so the last lap is complete when the robot
  stops there on "end of trial".
* `fork_distance_m` after the crosswalk's far edge the road forks: the loop's road leaves the
  central road on the west side, to the left after a northbound crossing, to the right after a
  southbound one (`fork_sides`, taken in turn from the start).  The last direction signal
  (forward / left / right) seen before the fork chooses: fork_left / fork_right when it names the
  side the fork opens to, fork_straight when it names the other side (a "left" at a
  right-opening fork cannot be obeyed); "forward" does what `fork_forward` says for that fork
  ("straight" or "branch").  The order is used up at the fork.  The default lap on "forward":
  straight on at the north fork, counter-clockwise around the north loop and right onto the
  central road; the branch at the south fork, counter-clockwise around the south loop and
  straight onto the central road (both loops in their outer lane).
* Straight on at a fork, the robot drives the loop beyond it (counter-clockwise after the north
  fork, clockwise after the south one), turns through `loop_sweep_rad` and comes back along the
  loop's road, which joins the central road again at the fork with a 90-degree turn toward it
  (right at the north fork, left at the south one).  That junction is found by the robot's
  heading (on_odometry): once the heading has turned through the loop's sweep (less
  `loop_exit_tolerance_rad`, plus the arc that tolerance leaves at `loop_lane_radii_m`), the turn
  starts `loop_exit_m` further on, and merge_right / merge_left fires.  Without odometry the
  merges never fire.

Junction corners from the cameras: a lane measurement whose right (edge) line ends between
min_line_end_m and corner_sight_m ahead (conde_tracking's right_line_end_m) shows the corner of a
right turn: the edge line leaves its band corner_line_offset_m beyond the corner, where it turns
away.  The corner's place along the road is kept (the median of its sightings: junction_corners.py)
and, corner_lead_m before
the robot reaches it, a fork_right or merge_right fires, from junction_window_m before the stored
distance (fork_distance_m, loop_exit_m) on: the turn's arc begins at the corner the robot sees.
The stored distances arm the search; junction_fallback_m after them the turn begins anyway (on a
track seed with a 3.6 % longer y the stored fork distance came 19 cm before the corner).
Left turns (fork_left, merge_left) likewise from far_left_line_end_m, the other lane's outer edge
line, which turns left at the left turn's corner with the same radius (junction_corners.py; the
dashed centre line ends anywhere within a dash period before the branch and is no mark).
Straight on at a fork that opens right the course is held across the junction (straight_crossing_m
past the fork: the lane's edge line turns into the branch there; ForkNavigator.holds_course),
steering by odometry along the road's direction seen before the fork, from the offset seen
there (course_hold.py).

Where the robot is along the road is measured by odometry (the path length on_odometry is given)
or, without it, dead-reckoned from the speed it is commanded (ramped at speed_ramp_mps2 with
conde_common's rate limiter, which conde_control uses for its acceleration limit, so that the
commanded speed is what the robot drives), and corrected by every crosswalk sighting of
conde_tracking (crosswalk_distance_m).  Sightings are ignored from the moment the robot is at the
crosswalk until it has driven crosswalk_rearm_m past it (the stripes under and behind the robot
are not a new crosswalk).

Commands (the state's `command` in the YAML):

* speed ``cruise``: cruise_speed_mps; ``stop``: 0; ``stop_at_crosswalk``: cruise, braking at
  brake_decel_mps2 so as to stand stop_margin_m before the near edge of the crosswalk ahead
  (if the state begins while the robot is already on a crosswalk, at the next one);
  ``stop_at_finish``: the same with finish_margin_m (the end of trial), and the robot is "at" the
  crosswalk (crosswalk_reached) as much nearer as finish_margin_m is smaller than stop_margin_m;
* branch ``left`` / ``right`` with ``radius_m``: an arc of that radius toward the branch, driven
  blind (the control reference carries the path curvature, the lane measurement is not used and
  a lost lane does not stop the robot), for distance_m; the junctions' turns.  With
  arcs_by_odometry the arc is a path on the floor from where it begins, along the road's direction
  seen before the turn, and its offset and heading error by odometry go to the control (arc_track.py);
* branch ``left`` / ``right`` without ``radius_m``: a bias of the references toward the branch, for a short while:
  the lateral offset reference becomes +-branch_offset_m times a trapezoid of the distance driven
  in the state (rising over the first quarter of the state's distance_m, full until half-way,
  back to 0 at the end; full all along without distance_m), the heading reference likewise with
  branch_heading_rad.  The robot swerves toward the branch where it diverges and is back on its
  lane's centre when the state ends.  This is a simplification: it works if conde_tracking
  measures the robot against the lane it is in (the lane it leaves, then the branch);
* speed ``creep`` / ``reverse``: forward / backward at park_speed_mps, blind (an arc with
  branch and radius_m, else straight on): the parking manoeuvres (parking.py);
* lane_aligned: in such an arc the cameras see the lane the turn leads to with both lines, confirmed
  over several frames (arc_end.py), and the robot heads along it: the turn can end there,
  as the cameras see it, rather than after its stored length (the arc's radius is what the robot
  drives, which lags: it ended about 10 deg past the new lane and 9 cm inside it);
* distance_m: the event distance_elapsed fires after that distance in the state (driven either
  way: forward or backward).

Parking (parking.py): with parking_place set to a place, its event fires in every step while the
current state listens to it (parking_parallel after parking_search_m in the state); with
parking_place auto (the default) the place is the parking area the cameras show
(conde_tracking's bay lines and boxes: parking_bays_seen, or parking_parallel when no bay line was
seen in the first parking_search_m), and bay_entry_near fires where the way into the first free
bay begins, anchored on its lines.

Safety: when the lane confidence is below min_lane_confidence the measured offset and heading
are replaced by their references (the robot holds its course, e.g. over the crosswalk stripes);
after lane_lost_timeout_s without a confident lane the speed goes to 0 until the lane is back.
In a state that drives along the lane the robot then tries to find it again (lane_recovery.py):
it reverses straight the way it came since the last confident lane (at most recovery_distance_m, at
recovery_speed_mps), then creeps up to recovery_distance_m ahead, steering onto the lane as it was
last seen, dead-reckoned by odometry; up to recovery_max_tries times before it stands.
"""

import math
from dataclasses import dataclass, field, fields
from typing import List, Optional, Tuple

from conde_common.bay_pairing import BAY_WIDTH_M
from conde_common.panel_signals import NAMES_BY_CODE, SIGNAL_CODES
from conde_decision.arc_end import ArcEnd
from conde_decision.arc_track import ArcTrack
from conde_decision.handover import HandOver
from conde_decision.avoidance import Avoidance, AvoidanceConfig, EventDelay, Obstacle
from conde_decision.crosswalk import CrosswalkTracker
from conde_decision.fork_navigator import ForkNavigator
from conde_decision.course_hold import CourseHold
from conde_decision.junction_corners import JunctionCorners, visible_sides
from conde_decision.lane_frame import UNKNOWN_LANE, LaneFrame, lane_frame
from conde_decision.lane_recovery import AHEAD, BACK, REJOIN, LaneRecovery, RecoveryConfig, rejoin_heading_ref_rad
from conde_decision.lap_counter import LapCounter
from conde_decision.order_gate import OrderGate
from conde_decision.parking import (BLIND_SPEEDS, PARKING_PLACES, PARKING_SEARCH_EVENTS, BayFinder,
                                    ParallelGapFinder, bay_entry_lead_m, check_parking_place, manoeuvre_advance_m,
                                    parking_event)
from conde_decision.road_distance import RoadDistance, road_direction_rad
from conde_decision.speed_profile import STOP_SPEEDS, SpeedProfile
from conde_decision.state_machine import StateMachine, StateMachineSpec

#: conde_msgs/PanelSignal constants and the event name of each (code -> name).
SIGNAL_NAMES = NAMES_BY_CODE
NONE, LEFT, RIGHT, FORWARD, STOP, END_OF_TRIAL, PARKING = (SIGNAL_CODES[name] for name in (
    "none", "left", "right", "forward", "stop", "end_of_trial", "parking"))
DIRECTIONS = {FORWARD: "forward", LEFT: "left", RIGHT: "right"}


@dataclass(frozen=True)
class DecisionConfig:
    """Tuning and track facts.  The initial values are the defaults (node parameters override
    them by name)."""

    cruise_speed_mps: float = 0.5  # lane-following speed [m/s]
    speed_ramp_mps2: float = 1.0  # rate of change of the commanded speed [m/s^2] (= conde_control's limit)
    brake_decel_mps2: float = 0.5  # deceleration when stopping before the crosswalk [m/s^2]
    # Stand this far before the crosswalk's near edge [m].  The robot follows the commanded speed
    # about 0.1 s late, so it stops a few cm beyond the dead-reckoned point (3 cm before the edge
    # with a 0.05 m margin, measured in the simulator): the margin keeps it off the crosswalk.
    stop_margin_m: float = 0.10
    crosswalk_zone_m: float = 0.15  # within this distance of the near edge the robot is "at" the crosswalk [m]
    # speed stop_at_finish (the end of trial: no panel left to read) stands this far before the near edge [m]
    # (Major Alvega: 0.25, where its stop_margin_m keeps the panel in view but leaves the last lap short)
    finish_margin_m: float = 0.10
    crosswalk_length_m: float = 0.592  # near edge to far edge along the road [m] (y -0.340 .. 0.252)
    crosswalk_rearm_m: float = 1.0  # ignore crosswalk sightings for this distance after leaving one [m]
    start_to_near_edge_m: float = 0.0  # distance from base_footprint to the near edge at the start [m]
    fork_distance_m: float = 1.8  # crosswalk far edge to the fork [m] (1.82 northbound, 1.73 southbound)
    fork_sides: Tuple[str, ...] = ("left", "right")  # side the branch opens to at the 1st, 2nd, ... fork (cyclic)
    fork_forward: Tuple[str, ...] = ("straight", "branch")  # what "forward" does at each fork of fork_sides
    crossings_per_lap: int = 2  # crosswalk crossings per lap of the track
    loop_sweep_rad: float = 4.712389  # heading change around a loop, fork to where its road turns back [rad]
    # the loop counts as done this much before its full sweep [rad]: from there the corner the cameras
    # see starts the merge (the window and the fallback count from the loop's end, whatever this is);
    # 15 deg, as the robot's heading wobbles a few degrees on the lane and the odometry drifts
    loop_exit_tolerance_rad: float = 0.26
    # the loop's sweep counts from the median road direction of at least this many measurements before the fork
    min_road_direction_samples: int = 5
    loop_lane_radii_m: Tuple[float, ...] = (2.5685, 1.7865)  # lane radius of the loop after each fork of fork_sides [m]
    loop_exit_m: float = 1.1775  # end of the loop's arc to the start of the turn onto the central road [m]
    # a turn's corner seen by the cameras counts from this far before the stored distance [m]
    junction_window_m: float = 0.6
    # where the cameras mark the corner (right turns), the stored distance is the fallback this much later [m]
    junction_fallback_m: float = 0.3
    # the sides whose junction corners the robot's cameras show (junction_corners.py): turns to the
    # others begin at the stored distances, with no fallback.  Major Alvega: right only (its one
    # ground camera never shows the far-left line that marks a left turn's corner)
    corner_sides: Tuple[str, ...] = ("right", "left")
    corner_sight_m: float = 0.6  # a right edge line ending within this distance ahead marks a corner [m]
    # a fork that opens right taken straight: the course is held (no lane) this far past the stored fork distance [m]
    straight_crossing_m: float = 1.8
    # between the lines' centres: a lane measured against the lane on the left is off by this [m]
    line_spacing_m: float = 0.8065
    own_lane_offset_m: float = 0.2  # ... after such a doubt, a lane measured within this is the own lane [m]
    # ... the corner lies this much before the line's end: where the edge line, turning away with
    # the corner's radius (0.19 m on the competition track), leaves its band [m] (measured: 0.19-0.22)
    corner_line_offset_m: float = 0.21
    corner_lead_m: float = 0.05  # the turn begins this far before the corner: the robot follows its commands late [m]
    # the junctions' arcs tracked by odometry (arc_track.py): a path on the floor from where the turn
    # begins, along the road's direction seen before it, steered back onto like a lane; false: the
    # arc's curvature alone (feed-forward), begun along the robot's heading.  Major Alvega's steering lags
    # the arc's start; Conde began its right turns about 0.1 rad inward and ended them 4-15 cm inside
    arcs_by_odometry: bool = True
    min_line_end_m: float = 0.1  # line ends nearer than this are no measurement (an unset field is 0) [m]
    lane_aligned_rad: float = 0.1  # lane_aligned: heading within this of (or past) the follower's approach [rad]
    # ... confirmed (arc_end.py): not before this part of the arc's sweep is turned
    lane_aligned_min_sweep: float = 0.6
    lane_aligned_frames: int = 3  # ... in this many consecutive confident measurements of one lane
    lane_aligned_direction_rad: float = 0.3  # ... each within this of the direction the arc leads to [rad]
    lane_aligned_spread_rad: float = 0.05  # ... their lane directions within this of each other [rad]
    lane_aligned_spread_m: float = 0.04  # ... and their lateral offsets [m]
    # the follower's approach heading per m of offset (conde_control: offset gain / heading gain = 36 / 10) [rad/m]
    lane_aligned_approach_per_m: float = 3.6
    lane_aligned_max_approach_rad: float = 0.4  # ... at most this [rad]
    # after a junction's blind arc, the follower's offset reference starts at the offset measured and
    # eases to 0 over this distance driven (handover.py; 0: at once) [m]
    handover_ease_m: float = 0.6
    branch_offset_m: float = 0.2  # peak lateral offset reference while taking a branch [m] (+ = left branch)
    branch_heading_rad: float = 0.0  # peak heading reference while taking a branch [rad] (+ = left branch)
    min_signal_confidence: float = 0.5  # panel signals below this confidence are ignored
    # a robot whose panel camera is this far ahead of base_footprint sees the panel at an angle that
    # far earlier: driving (not stopping at the line), its direction orders are latched from there
    # on before the crosswalk's stop line [m] (Major Alvega: 0.448, its top camera; Conde: 0)
    order_latch_lead_m: float = 0.0
    # driving, a signal other than the order held counts once it has been read this long (image stamps,
    # none pausing the count; far reads of the panel flicker for 0.1-0.73 s); standing, at once [s]
    order_hold_s: float = 1.5
    # driving, a change of order counts only while the robot is on the crosswalk or conde_tracking has
    # seen the crosswalk ahead within this distance of its near edge (the panel stands over it; V1's
    # red danger signs elsewhere are read as stop) [m]; 0: anywhere (the rule before)
    order_crosswalk_range_m: float = 2.0
    # driving, a stop read while the crosswalk ahead is within this distance of its near edge counts at
    # once, without order_hold_s: the panel is close above, and the hold (0.75 m at cruise) would carry
    # the robot over the crosswalk; a false stop there costs a halt at the line [m]; 0: the hold everywhere
    stop_near_m: float = 1.0
    min_lane_confidence: float = 0.3  # lane measurements below this confidence are not used
    lane_lost_timeout_s: float = 1.0  # stop after this long without a confident lane [s]
    # then, in a state driving along the lane, recover (lane_recovery.py): |speed| [m/s], ...
    recovery_speed_mps: float = RecoveryConfig.speed_mps
    recovery_distance_m: float = RecoveryConfig.distance_m  # ... way back and ahead in each try [m]
    recovery_max_tries: int = RecoveryConfig.max_tries  # ... tries before standing for good (0: no recovery)
    recovery_reset_m: float = RecoveryConfig.reset_m  # ... counted from 0 again after this far on a lane [m]
    recovery_rejoin_m: float = RecoveryConfig.rejoin_m  # ... the lane found: at most recovery_speed_mps this far [m]
    # ... the creep ahead only within this of the lane's centre as last seen, by odometry [m]
    recovery_max_offset_m: float = RecoveryConfig.max_offset_m
    # ... rejoining, at most this heading toward the lane's centre [rad], aiming at it this far ahead [m]
    recovery_rejoin_heading_rad: float = RecoveryConfig.rejoin_heading_rad
    recovery_rejoin_approach_m: float = RecoveryConfig.rejoin_approach_m
    max_step_s: float = 1.0  # longest time step dead-reckoned at once [s] (gaps in the input)
    park_speed_mps: float = 0.2  # |speed| of the parking manoeuvres (speeds creep and reverse) [m/s]
    # where to park on the parking order: auto (the place seen, parking.py) | parallel | bay_north | bay_south
    parking_place: str = "auto"
    # parking_parallel fires after this distance in go_to_parking (auto: if no bay line was seen) [m]
    parking_search_m: float = 0.3
    # neighbouring bay lines this far apart (or twice) enclose a bay ... [m] (conde_common.bay_pairing)
    bay_width_min_m: float = BAY_WIDTH_M[0]
    bay_width_max_m: float = BAY_WIDTH_M[1]  # ... up to this [m] (0.773 on the competition track)
    bay_line_merge_m: float = 0.1  # sightings of a bay line within this along the road are one line [m]
    bay_line_sightings: int = 2  # a bay line is known after this many sightings
    # auto: lines of the bay-parking area known but no free bay between them when the robot is this far
    # past the last one: the search gives up and heads for the parallel bay (parking_parallel) [m]
    bay_search_past_m: float = 1.0
    # parallel parking (ParallelGapFinder): park in the middle of the first free stretch this long ... [m]
    park_min_gap_m: float = 0.9
    # ... or, with no box in the bay, this far beyond the start of its straight part (half of it) [m]
    park_bay_centre_m: float = 1.53
    # the manoeuvre ends with base_footprint (the wheels' axle; the body trails) this far past that middle [m]
    park_axle_past_centre_m: float = 0.25

    def check(self) -> "DecisionConfig":
        """Returns self if every value is usable, else raises ValueError naming the field."""
        def need(name, ok, what):
            if not ok:
                raise ValueError("%s: %s, got %r" % (name, what, getattr(self, name)))

        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "fork_sides":
                need(f.name, isinstance(value, (list, tuple)) and len(value) > 0
                     and all(v in ("left", "right") for v in value), "expected a non-empty list of left/right")
            elif f.name == "corner_sides":
                need(f.name, isinstance(value, (list, tuple)) and all(v in ("left", "right") for v in value),
                     "expected a list of left/right")
            elif f.name == "fork_forward":
                need(f.name, isinstance(value, (list, tuple)) and len(value) == len(self.fork_sides)
                     and all(v in ("straight", "branch") for v in value),
                     "expected straight or branch for each entry of fork_sides")
            elif f.name == "loop_lane_radii_m":
                need(f.name, isinstance(value, (list, tuple)) and len(value) == len(self.fork_sides)
                     and all(isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0 for v in value),
                     "expected one radius > 0 per entry of fork_sides")
            elif f.name == "arcs_by_odometry":
                need(f.name, isinstance(value, bool), "expected true or false")
            elif f.name == "parking_place":
                need(f.name, value in PARKING_PLACES, "expected one of %s" % ", ".join(PARKING_PLACES))
            elif f.name in ("crossings_per_lap", "bay_line_sightings", "min_road_direction_samples",
                            "lane_aligned_frames"):
                need(f.name, isinstance(value, int) and not isinstance(value, bool) and value >= 1,
                     "expected an integer >= 1")
            else:
                need(f.name, isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value),
                     "expected a finite number")
        for name in ("cruise_speed_mps", "speed_ramp_mps2", "brake_decel_mps2", "crosswalk_length_m",
                     "lane_lost_timeout_s", "max_step_s", "park_speed_mps"):
            need(name, getattr(self, name) > 0, "must be > 0")
        for name in ("stop_margin_m", "finish_margin_m", "crosswalk_rearm_m", "fork_distance_m", "branch_offset_m",
                     "loop_sweep_rad",
                     "loop_exit_tolerance_rad", "loop_exit_m", "junction_window_m", "junction_fallback_m",
                     "corner_sight_m", "straight_crossing_m",
                     "line_spacing_m", "own_lane_offset_m",
                     "corner_line_offset_m", "corner_lead_m", "min_line_end_m", "lane_aligned_rad",
                     "order_latch_lead_m", "lane_aligned_min_sweep", "lane_aligned_direction_rad",
                     "lane_aligned_spread_rad", "lane_aligned_spread_m", "lane_aligned_approach_per_m",
                     "lane_aligned_max_approach_rad", "handover_ease_m", "order_hold_s", "order_crosswalk_range_m",
                     "stop_near_m"):
            need(name, getattr(self, name) >= 0, "must be >= 0")
        for name in ("min_signal_confidence", "min_lane_confidence"):
            need(name, 0 <= getattr(self, name) <= 1, "must be in [0, 1]")
        for name in ("bay_width_min_m", "bay_line_merge_m", "parking_search_m", "bay_search_past_m"):
            need(name, getattr(self, name) > 0, "must be > 0")
        need("bay_width_max_m", self.bay_width_max_m > self.bay_width_min_m, "must be > bay_width_min_m")
        need("crosswalk_zone_m", self.crosswalk_zone_m >= self.stop_margin_m,
             "must be >= stop_margin_m (%g), or a robot stopping before the crosswalk never reaches it"
             % self.stop_margin_m)
        return self


@dataclass(frozen=True)
class DecisionOutput:
    """The fields of conde_msgs/ControlReference, the state, and what happened in this step."""

    state: str
    last_event: str
    lateral_offset_m: float
    lateral_offset_ref_m: float
    heading_error_rad: float
    heading_ref_rad: float
    linear_velocity_mps: float
    path_curvature_per_m: float = 0.0  # of the arc being driven blind (+ = left), 0 = follow the lane
    transitions: List[Tuple[str, str, str]] = field(default_factory=list)  # (from, event, to) that fired
    events: List[str] = field(default_factory=list)  # every event produced, fired or ignored
    lane_lost: bool = False  # no confident lane for lane_lost_timeout_s: the speed is held at 0 (or recovering)
    recovery: str = ""  # the lane recovery's phase (lane_recovery.py): "", back, ahead, gave_up


class DecisionLogic:
    """Call on_signal() for each panel signal and on_lane() for each lane measurement (which
    returns the control reference).  Attributes worth reading: state, notes (human-readable
    remarks of the last step, e.g. an order that could not be obeyed), lap_counter (crossings,
    laps, lap_times_s) and road (travelled_m).

    It composes the state machine with pure parts, one per concern: RoadDistance (how far along
    the road, heading), CrosswalkTracker (the crosswalk ahead), LapCounter, ForkNavigator (forks
    and the ends of the loops) and SpeedProfile (the commanded speed)."""

    def __init__(self, spec: StateMachineSpec, config: DecisionConfig = DecisionConfig(),
                 avoidance_config: AvoidanceConfig = AvoidanceConfig()):
        self.config = config.check()
        self.avoidance = Avoidance(avoidance_config)  # obstacles and the working zone: command.lane
        self.delayed = EventDelay(avoidance_config.max_delay_m)  # a fork / merge met on the other lane
        self.machine = StateMachine(spec)
        self.road = RoadDistance()
        self.crosswalk = CrosswalkTracker(config.crosswalk_length_m, config.crosswalk_zone_m,
                                          config.crosswalk_rearm_m, config.start_to_near_edge_m)
        self.lap_counter = LapCounter(config.crossings_per_lap)
        self.forks = ForkNavigator(config, config.corner_sides)
        self.speed = SpeedProfile(config.cruise_speed_mps, config.speed_ramp_mps2, config.brake_decel_mps2,
                                  config.stop_margin_m, config.park_speed_mps, config.finish_margin_m)
        self.parking_event = parking_event(check_parking_place(config.parking_place))
        self.bays = BayFinder((config.bay_width_min_m, config.bay_width_max_m), config.bay_line_merge_m,
                              config.bay_line_sightings)
        self.gap = ParallelGapFinder(config.park_min_gap_m, config.park_bay_centre_m,
                                     min_sightings=config.bay_line_sightings)
        self.corners = JunctionCorners(config)  # the junctions' corners the cameras see, both sides
        self.arc_end = ArcEnd(self.config)  # where a junction's arc ends on the lane seen (lane_aligned)
        self.arc_track = ArcTrack()  # a junction's arc as a path on the floor (arcs_by_odometry)
        self.handover = HandOver(config.handover_ease_m)  # from a blind arc to the follower (handover.py)
        # straight across a junction by odometry (course_hold.py)
        self.course_hold = CourseHold(config.min_road_direction_samples)
        self.last_time_s: Optional[float] = None
        self.state_entry_m = 0.0  # travelled_m when the current state was entered
        self.distance_fired = False  # distance_elapsed already fired in this state
        self.last_signal = NONE
        self.orders = OrderGate(config.order_hold_s)  # which signals count as orders (order_gate.py)
        self.lane_bad_since_s: Optional[float] = None
        self.recovery = LaneRecovery(RecoveryConfig(config.recovery_speed_mps, config.recovery_distance_m,
                                                    config.recovery_max_tries, config.recovery_reset_m,
                                                    config.recovery_rejoin_m, config.recovery_max_offset_m,
                                                    config.recovery_rejoin_heading_rad,
                                                    config.recovery_rejoin_approach_m))
        self.notes: List[str] = []
        self._transitions: List[Tuple[str, str, str]] = []
        self._events: List[str] = []

    @property
    def state(self) -> str:
        return self.machine.state

    @property
    def last_event(self) -> str:
        return self.machine.last_event

    @property
    def parking_search(self) -> bool:
        """The current state looks for a parking place (listens to a parking_* / *_entry_near event):
        conde_tracking's search of the parking areas is wanted."""
        listens = self.machine.spec.states[self.state].transitions
        return any(e in listens for e in PARKING_SEARCH_EVENTS)

    # --- inputs ---------------------------------------------------------------------------------

    def on_signal(self, signal: int, confidence: float, time_s: Optional[float] = None) -> List[Tuple[str, str, str]]:
        """A panel signal (PanelSignal constant) of an image taken at time_s [s] (None: the time of
        the last lane measurement).  NONE and signals below min_signal_confidence produce no event;
        driving, a change of order counts once it has been read for order_hold_s (order_gate.py).
        Returns the transitions that fired."""
        if signal not in SIGNAL_NAMES:
            raise ValueError("unknown panel signal %r (expected 0..6)" % (signal,))
        self._transitions, self._events, self.notes = [], [], []
        if signal == NONE or not confidence >= self.config.min_signal_confidence:
            self.orders.pause()
            return []
        if time_s is None:
            time_s = self.last_time_s if self.last_time_s is not None else 0.0
        watched, held = self.orders.candidate, self.orders.held
        panel_ahead = self.panel_ahead()
        standing = self.machine.command.speed == "stop"
        at_once = signal == STOP and self.stop_near()
        if not self.orders.accept(signal, time_s, standing=standing, panel_ahead=panel_ahead, at_once=at_once):
            if watched != signal:
                self.notes.append("signal %s (confidence %.2f) while driving, order %s held: "
                                  "taken once read for %.1f s%s"
                                  % (SIGNAL_NAMES[signal], confidence, SIGNAL_NAMES.get(self.orders.held, "none"),
                                     self.config.order_hold_s,
                                     "" if panel_ahead else " with the crosswalk in sight"))
            return []
        if at_once and not standing and held != signal:
            self.notes.append("signal stop (confidence %.2f) while driving taken at once: the crosswalk's near edge "
                              "is %.2f m ahead (stop_near_m %.2f)"
                              % (confidence, self.crosswalk.to_near_edge_m, self.config.stop_near_m))
        self.last_signal = signal
        if signal in DIRECTIONS:
            note = self.forks.on_direction(DIRECTIONS[signal])
            if note:
                self.notes.append(note)
        self._fire("signal_" + SIGNAL_NAMES[signal])
        return self._transitions

    def panel_ahead(self) -> bool:
        """The panel can be what the top camera reads: the robot is on the crosswalk, or the crosswalk
        ahead (seen by conde_tracking, then dead-reckoned) is within order_crosswalk_range_m."""
        range_m = self.config.order_crosswalk_range_m
        return range_m == 0.0 or self.crosswalk.at_crosswalk or self.crosswalk.ahead_within(range_m)

    def stop_near(self) -> bool:
        """The crosswalk ahead (seen by conde_tracking, then dead-reckoned) is within stop_near_m of
        its near edge: a stop read now is taken at once."""
        return self.config.stop_near_m > 0.0 and self.crosswalk.ahead_within(self.config.stop_near_m)

    def on_odometry(self, yaw_rad: float, travelled_m: Optional[float] = None) -> None:
        """The robot's heading [rad] (any branch of the angle; unwrapped here) and, if known, the
        length of the path it has driven so far by odometry [m]: distances along the road are
        then measured rather than dead-reckoned from the commanded speed (which a robot that
        lags behind its commands, e.g. on a busy machine, does not drive)."""
        self.road.on_odometry(yaw_rad, travelled_m)

    def on_lane(self, lane, time_s: float) -> DecisionOutput:
        """A lane measurement (any object with the fields of conde_msgs/LaneMeasurement) taken at
        time_s [s]; returns the control reference for it."""
        c = self.config
        self._transitions, self._events, self.notes = [], [], []
        dt_s = 0.0 if self.last_time_s is None else min(max(time_s - self.last_time_s, 0.0), c.max_step_s)
        self.last_time_s = time_s
        step_m = self.road.advance(abs(self.speed.v_mps) * dt_s)
        recovering_back = self.speed.v_mps < 0.0 and self.recovery.phase in (BACK, AHEAD, REJOIN)
        self.crosswalk.advance(-step_m if recovering_back else step_m)  # the recovery's way back
        self.crosswalk.on_sighting(lane.crosswalk_seen, lane.crosswalk_distance_m)
        self._road_direction(lane)
        tracked_lanes_left = self._tracked_lanes_left(lane)
        corners = self.corners_seen(lane, tracked_lanes_left)
        self._crosswalk_and_fork_events(time_s, corners)
        merge = self.forks.loop_exit(self.road.yaw_rad, self.road.travelled_m, corners,
                                     visible_sides(tracked_lanes_left))
        if self.forks.fallback_note:
            self.notes.append(self.forks.fallback_note)
        if merge is not None:
            self._fire(merge)
        for event in self._parking_events(lane):
            self._fire(event)
        command = self.machine.command
        if (command.distance_m is not None and not self.distance_fired
                and self.road.travelled_m - self.state_entry_m >= command.distance_m - 1e-9):
            self.distance_fired = True
            self._fire("distance_elapsed")
        command = self.machine.command
        if self._lane_aligned_in_arc(lane, command):
            self._fire("lane_aligned")
        command = self.machine.command

        arc_or_blind = command.radius_m is not None or command.speed in BLIND_SPEEDS
        holding = not arc_or_blind and self.forks.holds_course(self.crosswalk.since_left_m)
        blind_arc = arc_or_blind or holding
        lane_ok = (math.isfinite(lane.lateral_offset_m) and math.isfinite(lane.heading_error_rad)
                   and lane.confidence >= c.min_lane_confidence)
        lane_index = getattr(lane, "lane_index", UNKNOWN_LANE)
        if lane_ok and not blind_arc:
            self.forks.on_lane_measured(lane.lateral_offset_m, lane.confidence >= 1.0, c.own_lane_offset_m, lane_index)
        frame = self._lane_frame(lane, lane_ok)
        measured_offset_m = frame.own_offset_m
        if lane_ok and not blind_arc:
            self.recovery.on_confident_lane(self.road.yaw_rad, lane.heading_error_rad, measured_offset_m,
                                            self.road.travelled_m)
        if lane_ok or blind_arc:
            self.lane_bad_since_s = None
        elif self.lane_bad_since_s is None:
            self.lane_bad_since_s = time_s
        lane_lost = self.lane_bad_since_s is not None and time_s - self.lane_bad_since_s >= c.lane_lost_timeout_s
        # the tracker's own offset and index: the avoidance puts them in the own lane's frame itself
        # (the lane placed here only outside a lane change and to start one from)
        avoid = self.avoidance.step(lane.lateral_offset_m, lane_ok and not blind_arc, self.road.travelled_m,
                                    command.lane, obstacles_of(lane), lane.heading_error_rad,
                                    lane.confidence >= 1.0, lane_index,
                                    getattr(lane, "lane_spacing_m", float("nan")), self.road.yaw_rad,
                                    tracked_shift_m=frame.shift_m)
        for event in avoid.events:
            self._fire(event)
        if "lane_returned" in avoid.events:  # the tracker may still measure the lane on the left
            self.forks.doubt_tracked_lane()
            frame = self._lane_frame(lane, lane_ok)
            measured_offset_m = frame.own_offset_m
        delayed, note = self.delayed.due(self.road.travelled_m, self._takes)
        if note:
            self.notes.append(note)
        if delayed is not None:
            self._fire(delayed)
        command = self.machine.command

        may_move = (lane_lost and not blind_arc and command.speed != "stop"
                    and self.speed.target_mps(command.speed, self.crosswalk.to_near_edge_m) > 0.0)
        recovery = self.recovery.step(lane_lost, may_move, self.road.yaw_rad, self.road.travelled_m, recovering_back)
        if self.recovery.note:
            self.notes.append(self.recovery.note)
        target_mps = recovery.speed_mps if recovery.active else None
        # the lane found again (REJOIN): slowly until the follower has it
        max_mps = recovery.speed_mps if recovery.phase == REJOIN else None
        v_mps = self.speed.step(command.speed, self.crosswalk.to_near_edge_m, dt_s, hold=lane_lost,
                                target_mps=target_mps, max_mps=max_mps)
        if v_mps > 0.0:
            self.lap_counter.on_motion(time_s)

        side = {"none": 0.0, "left": 1.0, "right": -1.0}[command.branch]
        curvature_per_m = 0.0
        if blind_arc:
            bias = 0.0
            curvature_per_m = side / command.radius_m if command.radius_m is not None else 0.0
        else:
            bias = side * self._branch_shape(command)
        offset_ref_m = bias * c.branch_offset_m + avoid.control_ref_m
        heading_ref_rad = bias * c.branch_heading_rad + avoid.heading_ref_rad
        handover_offset_m, handover_heading_rad = self._handover(command, lane_ok, blind_arc, avoid.active,
                                                                 measured_offset_m)
        offset_ref_m += handover_offset_m
        heading_ref_rad += handover_heading_rad
        offset_m = measured_offset_m if lane_ok and not blind_arc else offset_ref_m
        if avoid.active and math.isfinite(avoid.own_lane_offset_m):  # a lane change: the own lane's frame
            offset_m = avoid.own_lane_offset_m
        heading_rad = lane.heading_error_rad if lane_ok and not blind_arc else heading_ref_rad
        if avoid.lane_rejected and math.isfinite(avoid.heading_error_rad):  # not the odometry's heading
            heading_rad = avoid.heading_error_rad
        on_arc = self.arc_track.step(self.road.yaw_rad, step_m) if command.radius_m is not None else None
        if on_arc is not None:  # a junction's arc tracked by odometry (arc_track.py)
            offset_m, heading_rad = on_arc
        by_odometry = (self.course_hold.step(self.road.yaw_rad, self.forks.road_direction_rad(), step_m)
                       if holding else None)
        if by_odometry is not None:  # across the junction: along the road seen before it (course_hold.py)
            offset_m, heading_rad = by_odometry
        if not holding:
            self.course_hold.release()
        if recovery.phase == REJOIN and lane_ok and not blind_arc and not avoid.active:
            # toward the lane's centre at a bounded heading, within the cameras' view (lane_recovery.py)
            heading_ref_rad += rejoin_heading_ref_rad(offset_m - offset_ref_m, self.recovery.config)
            offset_m = offset_ref_m
        if recovery.active:  # back straight, or onto the lane by odometry (lane_recovery.py)
            offset_m = recovery.lateral_offset_m if recovery.phase == AHEAD else offset_ref_m
            heading_rad, heading_ref_rad, curvature_per_m = recovery.heading_error_rad, 0.0, 0.0
        return DecisionOutput(self.state, self.last_event, offset_m, offset_ref_m, heading_rad, heading_ref_rad,
                              v_mps, curvature_per_m, list(self._transitions), list(self._events), lane_lost,
                              recovery.phase)

    # --- internals ------------------------------------------------------------------------------

    def _takes(self, event: str) -> bool:
        return event in self.machine.spec.states[self.state].transitions

    def _fire(self, event: str) -> None:
        self._events.append(event)
        # kept only when the avoidance is why the state cannot take it
        self.delayed.offer(event, self.road.travelled_m, self._takes(event) or not self.avoidance.active)
        before = self.state
        if self.machine.handle(event) is not None:
            self._transitions.append((before, event, self.state))
            self.state_entry_m = self.road.travelled_m
            self.distance_fired = False
            self.arc_end.start(self.road.yaw_rad)
            self._start_arc_track()
            if self.state != before:
                self.speed.unlatch()

    def _start_arc_track(self) -> None:
        """A state just entered: where it drives a junction's arc and arcs_by_odometry is set, the arc
        is tracked from here, along the road's direction the fork navigator saw before the turn."""
        command = self.machine.command
        self.arc_track.release()
        if (self.config.arcs_by_odometry and command.radius_m is not None and command.speed not in BLIND_SPEEDS
                and command.branch in ("left", "right")):
            side = 1.0 if command.branch == "left" else -1.0
            self.arc_track.start(self.road.yaw_rad, self.forks.turn_road_rad, command.radius_m, side)
        self.forks.turn_road_rad = None  # used up by this turn

    @property
    def right_corner_at_m(self) -> Optional[float]:
        """travelled_m at the right-turn corner in sight, the median of its sightings (None: none in sight)."""
        return self.corners.corner_at_m["right"]

    def corners_seen(self, lane, tracked_lanes_left: int = 0) -> Tuple[str, ...]:
        """The sides ("right", "left") at whose turn's corner the robot is (within corner_lead_m),
        as the cameras showed it in this lane measurement or earlier ones (junction_corners.py)."""
        return self.corners.update(lane, self.road.travelled_m, tracked_lanes_left)

    def _road_direction(self, lane) -> None:
        """The road's direction by odometry (the heading less the heading error seen with both lines,
        outside the blind manoeuvres) to the fork navigator: the loops' sweeps count from it."""
        command = self.machine.command
        direction_rad = road_direction_rad(self.road.yaw_rad, lane.heading_error_rad)
        if (direction_rad is not None and lane.confidence >= 1.0
                and command.radius_m is None and command.speed not in BLIND_SPEEDS):
            if self.forks.on_road_direction(self.crosswalk.since_left_m, direction_rad):
                self.course_hold.measured(lane.lateral_offset_m)  # where on the road: course_hold.py
            self.forks.on_exit_road_direction(self.road.travelled_m, direction_rad)

    def _lane_frame(self, lane, lane_ok: bool) -> LaneFrame:
        """The measurement in the own lane's frame (lane_frame.py): after a right fork crossed
        straight the tracker may measure the lane on the left; its lane_index says which where
        known, the offset modulo line_spacing_m where not."""
        c = self.config
        return lane_frame(lane.lateral_offset_m, getattr(lane, "lane_index", UNKNOWN_LANE),
                          getattr(lane, "lane_spacing_m", float("nan")),
                          lane_ok and self.forks.tracker_may_be_on_the_other_lane(), c.line_spacing_m)

    def _tracked_lanes_left(self, lane) -> int:
        """How many lanes left of the robot's own lane conde_tracking measures: 0, except after a
        right fork crossed straight, where it may have locked onto the lane on the left."""
        offset_m = lane.lateral_offset_m
        lane_ok = math.isfinite(offset_m) and lane.confidence >= self.config.min_lane_confidence
        return self._lane_frame(lane, lane_ok).lanes_left

    def _crosswalk_and_fork_events(self, time_s: float, corners: Tuple[str, ...] = ()) -> None:
        zone_m = self.config.crosswalk_zone_m
        if self.machine.command.speed == "stop_at_finish":  # as near as the finish's margin is nearer
            zone_m += self.config.finish_margin_m - self.config.stop_margin_m
        if self.crosswalk.reached(zone_m):
            lap_done = self.lap_counter.on_crossing(time_s)
            self._fire("crosswalk_reached")
            if lap_done:
                self._fire("lap_completed")
        # Standing at the line (stopping there) every order counts; driving, from order_latch_lead_m before it.
        stopping = self.machine.command.speed == "stop" or self.machine.command.speed in STOP_SPEEDS
        lead_m = 0.0 if stopping else self.config.order_latch_lead_m
        if ((self.crosswalk.at_crosswalk or lead_m > 0.0) and self.crosswalk.to_near_edge_m is not None
                and self.crosswalk.to_near_edge_m < lead_m):
            self.forks.on_stop_line_passed()
        if self.crosswalk.left():
            self.forks.on_crosswalk_left()
            self.speed.unlatch()
            self._fire("crosswalk_left")
        event, note = self.forks.at_fork(self.crosswalk.since_left_m, self.road.yaw_rad, corners)
        if note:
            self.notes.append(note)
        if event is not None:
            self._fire(event)

    def _parking_events(self, lane) -> List[str]:
        """The parking events of this step (parking.py): the place's event (parking_place), or in
        auto the place seen; bay_entry_near where the way into the first free bay begins."""
        c = self.config
        listens = self.machine.spec.states[self.state].transitions
        in_state_m = self.road.travelled_m - self.state_entry_m
        if self.parking_search:  # put what the cameras see of the parking areas along the road
            travelled_m = self.road.travelled_m
            self.bays.on_lines(travelled_m, getattr(lane, "bay_line_distances_m", ()))
            self.gap.on_bay_start(travelled_m, float(getattr(lane, "parallel_bay_start_m", float("nan"))))
            kinds = getattr(lane, "obstacle_kinds", ())
            fars = list(getattr(lane, "obstacle_far_distances_m", ())) or [float("nan")] * len(kinds)
            for kind, d, far, y_max in zip(kinds, getattr(lane, "obstacle_distances_m", ()), fars,
                                           getattr(lane, "obstacle_y_max_m", ())):
                if kind == "box":
                    self.bays.on_box(travelled_m, float(d), float(y_max))
                    self.gap.on_box(travelled_m, float(d), float(far), float(y_max))
        events = []
        if self.parking_event is not None:
            if self.parking_event in listens and (self.parking_event != "parking_parallel"
                                                  or in_state_m >= c.parking_search_m):
                events.append(self.parking_event)
        elif "parking_bays_seen" in listens and self.bays.bays():
            events.append("parking_bays_seen")
        elif "parking_parallel" in listens and not self.bays.lines_m and in_state_m >= c.parking_search_m:
            events.append("parking_parallel")  # no line of the bay-parking area known (one sighting is none)
        elif "parking_parallel" in listens and self.bays.lines_m and self.bays.free_bay() is None \
                and self.road.travelled_m >= self.bays.lines_m[-1] + c.bay_search_past_m:
            events.append("parking_parallel")
            self.notes.append("parking: the bay-parking area's lines seen (%s m along the road) enclose no free bay; "
                              "heading for the parallel bay" % ", ".join("%.2f" % m for m in self.bays.lines_m))
        if "bay_entry_near" in listens:
            free = self.bays.free_bay()
            lead_m = bay_entry_lead_m(self.machine.spec, self.state)
            if free is not None and lead_m is not None and self.road.travelled_m >= 0.5 * sum(free) - lead_m:
                events.append("bay_entry_near")
        if "park_entry_near" in listens:
            target_m = self.gap.target_m()
            advance_m = manoeuvre_advance_m(self.machine.spec, listens["park_entry_near"])
            if target_m is not None and advance_m is not None:
                if self.road.travelled_m >= target_m + c.park_axle_past_centre_m - advance_m:
                    events.append("park_entry_near")
                    self.notes.append("parallel parking: the free stretch's middle at %.2f m along the road (bay start "
                                      "%s, boxes %s); the manoeuvre begins at %.2f m" % (
                                          target_m, _m(self.gap.bay_start_m),
                                          ", ".join("%s-%s" % (_m(a), _m(b)) for a, b in self.gap.boxes()) or "none",
                                          self.road.travelled_m))
            else:
                command = self.machine.command
                due = command.distance_m is not None and in_state_m >= command.distance_m - 1e-9
                if due and not self.distance_fired:
                    self.notes.append("parallel parking: no free stretch of the parallel bay seen; the manoeuvre "
                                      "begins by the stored distance (%.2f m in %s)" % (command.distance_m, self.state))
        return events

    def _handover(self, command, lane_ok: bool, blind_arc: bool, avoiding: bool,
                  measured_offset_m: float) -> Tuple[float, float]:
        """The hand-over's (offset, heading) reference after a junction's blind arc (handover.py)."""
        if command.radius_m is not None or avoiding:
            self.handover.arm(command.radius_m is not None)
            return 0.0, 0.0
        return self.handover.step(lane_ok and not blind_arc, measured_offset_m, self.road.travelled_m)

    def _lane_aligned_in_arc(self, lane, command) -> bool:
        """In an arc driven blind: the cameras confirm the lane the turn leads to (both lines, several
        frames of one lane) and the robot heads along it as the lane follower would (arc_end.py)."""
        if command.radius_m is None or command.distance_m is None or command.branch == "none":
            return False
        side = 1.0 if command.branch == "left" else -1.0
        own_offset_m = self._lane_frame(lane, True).own_offset_m  # the tracker may measure the lane on the left
        return self.arc_end.update(side, command.radius_m, command.distance_m,
                                   self.road.travelled_m - self.state_entry_m, self.road.yaw_rad,
                                   own_offset_m, lane.heading_error_rad, lane.confidence)

    def _branch_shape(self, command) -> float:
        """0..1: trapezoid over the state's distance (rise 1/4, hold to 1/2, fall to the end)."""
        if command.distance_m is None:
            return 1.0
        u = (self.road.travelled_m - self.state_entry_m) / command.distance_m
        return max(0.0, min(1.0, 4.0 * u, 2.0 * (1.0 - u)))


def _m(value: Optional[float]) -> str:
    return "?" if value is None else "%.2f" % value


def obstacles_of(lane) -> List[Obstacle]:
    """The obstacles of a lane measurement (conde_msgs/LaneMeasurement's obstacle_* arrays; none
    when the object has no such fields)."""
    kinds = getattr(lane, "obstacle_kinds", ())
    return [Obstacle(k, float(d), float(lo), float(hi)) for k, d, lo, hi in
            zip(kinds, getattr(lane, "obstacle_distances_m", ()), getattr(lane, "obstacle_lane_y_min_m", ()),
                getattr(lane, "obstacle_lane_y_max_m", ()))]
