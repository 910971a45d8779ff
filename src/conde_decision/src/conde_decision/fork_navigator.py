"""Forks and junctions of the track: which way to go at each fork, and where the loop driven
straight on from a fork joins the central road again.  Pure Python, no ROS.

`config` is any object with the fields fork_distance_m, fork_sides, fork_forward,
loop_lane_radii_m, loop_sweep_rad, loop_exit_tolerance_rad, loop_exit_m, junction_window_m and
junction_fallback_m (DecisionConfig; their meaning is in the docstring of decision_logic).

The last direction signal before a fork chooses: the side the fork opens to gives fork_left /
fork_right, the other side fork_straight (with a note: that order cannot be obeyed), "forward" what
fork_forward says for that fork.  The order is used up at the fork, and latched from the crosswalk's
stop line (its near edge, on_stop_line_passed) to the fork: the top camera sees the panel at an
angle while the robot drives over the crosswalk and may misread it (D2: "forward" at 0.66
confidence read on the crosswalk while the panel showed "left"), so direction signals read there
are ignored.  Before the stop line (also standing there) every direction signal counts.  Straight on, the loop beyond
the fork turns toward the fork's side; once the heading has turned through the loop's sweep (less
loop_exit_tolerance_rad) and the robot has driven loop_exit_m (plus the arc that the tolerance
leaves at the loop's lane radius) further, merge_right / merge_left fires.

What the cameras see comes first: a turn toward a side whose corners the cameras mark
(`marked_sides`, both by default: junction_corners.py) fires when the caller passes that side in
`corners_seen`, from junction_window_m before the stored distance on; the stored distance is then
only the fallback, junction_fallback_m after it (on a track drawn differently the corner may lie
further), and a turn begun by the fallback says so (the note of at_fork, `fallback_note` after
loop_exit).  Turns to other sides fire at the stored distances."""

import math
import statistics
from dataclasses import dataclass, field
from typing import List, Optional, Sequence, Tuple


@dataclass
class LoopExit:
    """The loop being driven after a fork_straight."""

    sign: float  # +1: the loop turns left (counter-clockwise), -1: right
    yaw0_rad: Optional[float]  # heading at the fork [rad] (None: no odometry yet)
    radius_m: float  # the lane's radius around the loop [m]
    merge: str  # "left" / "right": the turn onto the central road at its end
    exit_mark_m: Optional[float] = None  # distance travelled when the sweep was complete [m]
    crossed_junction: bool = False  # entered straight across a junction whose branch opens right
    # the road's direction seen on the straight between the loop's arc and the turn at its end [rad]
    exit_directions_rad: List[float] = field(default_factory=list)


class ForkNavigator:
    def __init__(self, config, marked_sides: Sequence[str] = ("right", "left")):
        self.config = config
        self.marked_sides = tuple(marked_sides)  # the sides whose corners the cameras mark
        self.direction_order = "forward"  # the last direction signal, used up at the next fork
        self.fork_pending = False  # the robot left a crosswalk and has not reached the fork after it
        self.forks_passed = 0
        self.loop: Optional[LoopExit] = None
        self.order_latched = False  # past the crosswalk's stop line, before its fork: orders ignored
        self.crossing_end_m: Optional[float] = None  # since_crosswalk_m where a right fork crossed straight ends
        self.tracked_lane_unsure = False  # conde_tracking may measure the lane on the left (after such a crossing)
        self.ignored_order = ""  # the last order ignored while latched
        self.fallback_note = ""  # set by loop_exit when a merge began at the fallback, not at a corner seen
        self.road_directions_rad: List[float] = []  # the road's direction seen before the next fork [rad]
        # the road's direction seen before the turn just begun (fork_left / fork_right / a merge), None
        # when too few measurements showed it: the arc of the turn starts along it (arc_track.py) [rad]
        self.turn_road_rad: Optional[float] = None

    def on_direction(self, order: str) -> str:
        """A direction signal: "forward", "left" or "right".  Returns a note when it is ignored
        (the order is latched), else ""."""
        if self.order_latched:
            if order in (self.direction_order, self.ignored_order):  # noted once per order
                return ""
            self.ignored_order = order
            return "direction signal %s ignored: past the crosswalk's stop line the order %s is kept" % (
                order, self.direction_order)
        self.direction_order = order
        return ""

    def on_stop_line_passed(self) -> None:
        """The robot drove past the near edge of the crosswalk it is at: the order is latched until
        the fork after it."""
        self.order_latched = True

    def on_crosswalk_left(self) -> None:
        self.fork_pending = True
        self.road_directions_rad = []

    def on_road_direction(self, since_crosswalk_m: Optional[float], direction_rad: float) -> bool:
        """The road's direction [rad] (unwrapped, in the odometry's frame: the robot's heading less
        the heading error the cameras measured, from a measurement with both lines) at
        since_crosswalk_m [m] past the crosswalk.  Kept on the straight road between the crosswalk
        and junction_window_m before the fork: the loop's sweep counts from their median, not from
        the robot's heading at the fork (in D2 the robot pointed about 6 deg left there, after its
        lane follower swerved at the fork, and the sweep never completed).  True when it is kept."""
        c = self.config
        if (self.fork_pending and since_crosswalk_m is not None and math.isfinite(direction_rad)
                and since_crosswalk_m <= c.fork_distance_m - c.junction_window_m):
            self.road_directions_rad.append(direction_rad)
            return True
        return False

    def on_exit_road_direction(self, travelled_m: float, direction_rad: float) -> None:
        """The road's direction [rad] (as in on_road_direction) at travelled_m [m]: kept on the
        straight at the end of a loop, from where the loop's arc ends (loop_exit_tolerance_rad x the
        lane's radius past the mark of its sweep) to junction_window_m before the stored turn: the
        merge's arc starts along their median."""
        c, loop = self.config, self.loop
        if loop is None or loop.exit_mark_m is None or not math.isfinite(direction_rad):
            return
        driven_m = travelled_m - loop.exit_mark_m
        arc_left_m = c.loop_exit_tolerance_rad * loop.radius_m
        if arc_left_m <= driven_m <= arc_left_m + c.loop_exit_m - c.junction_window_m:
            loop.exit_directions_rad.append(direction_rad)

    def road_direction_rad(self) -> Optional[float]:
        """The median of the road directions seen since the crosswalk [rad]; None below
        min_road_direction_samples of them."""
        return self._median(self.road_directions_rad)

    def _median(self, directions_rad: Sequence[float]) -> Optional[float]:
        if len(directions_rad) < self.config.min_road_direction_samples:
            return None
        return statistics.median(directions_rad)

    def _next_fork(self) -> Tuple[int, str, str]:
        """(index in fork_sides, the side it opens to, the way the order takes there: a side or "forward")."""
        c = self.config
        fork = self.forks_passed % len(c.fork_sides)
        side, order = c.fork_sides[fork], self.direction_order
        if order == "forward" and c.fork_forward[fork] == "branch":
            order = side
        return fork, side, order

    def at_fork(self, since_crosswalk_m: Optional[float], yaw_rad: Optional[float],
                corners_seen: Sequence[str] = ()) -> Tuple[Optional[str], str]:
        """(event, note) once the robot is fork_distance_m past the crosswalk's far edge, or up to
        junction_window_m earlier where the cameras see the corner of the branch it takes
        (corners_seen: "left" / "right"): the event is fork_left, fork_right or fork_straight, the
        note says why an order was not obeyed ("" if it was).  (None, "") before the fork."""
        c = self.config
        if not self.fork_pending or since_crosswalk_m is None:
            return None, ""
        fork, side, order = self._next_fork()
        marked = order == side and side in self.marked_sides
        seen = marked and side in corners_seen and since_crosswalk_m >= c.fork_distance_m - c.junction_window_m
        due_m = c.fork_distance_m + (c.junction_fallback_m if marked else 0.0)
        if not (seen or since_crosswalk_m >= due_m):
            return None, ""
        self.fork_pending = False
        self.order_latched, self.ignored_order = False, ""
        self.forks_passed += 1
        self.direction_order = "forward"
        if order == side:
            self.turn_road_rad = self.road_direction_rad()
            return "fork_" + side, "" if seen or not marked else fallback_note("fork_" + side, due_m)
        note = ""
        if order != "forward":
            note = "the panel ordered %s, but this fork opens to the %s: keeping straight" % (order, side)
        if side == "right":
            self.crossing_end_m = c.fork_distance_m + c.straight_crossing_m
        # Straight on: the loop turns toward the fork's side and comes back to the fork, where its
        # road joins the central road with a turn to the other side.  Its sweep counts from the road's
        # direction seen before the fork (the robot's heading there when none was seen).
        road_rad = self.road_direction_rad()
        self.loop = LoopExit(sign=1.0 if side == "left" else -1.0, yaw0_rad=yaw_rad if road_rad is None else road_rad,
                             radius_m=c.loop_lane_radii_m[fork],
                             merge="right" if side == "left" else "left", crossed_junction=side == "right")
        return "fork_straight", note

    def holds_course(self, since_crosswalk_m: Optional[float]) -> bool:
        """True while the robot crosses straight on the junction of a fork that opens to the right,
        from junction_window_m before the stored fork distance to straight_crossing_m past it: the
        lane's right edge line turns away into the branch there (and the centre line has a gap), so
        a lane follower would take the branch; the robot holds its course instead."""
        c = self.config
        if since_crosswalk_m is None:
            return False
        if self.crossing_end_m is not None:
            if since_crosswalk_m < self.crossing_end_m:
                return True
            self.crossing_end_m = None
            self.tracked_lane_unsure = True
            return False
        if not self.fork_pending:
            return False
        _, side, order = self._next_fork()
        return side == "right" and order != side and since_crosswalk_m >= c.fork_distance_m - c.junction_window_m

    def tracker_may_be_on_the_other_lane(self) -> bool:
        """After holding the course across a right fork taken straight, until the tracker measures
        the own lane again after the loop beyond it (on_lane_measured): conde_tracking, whose lines
        went out of sight in the junction, may have locked onto the lane on the left (measured on
        the south fork's crossing in D2: -0.81 m, and the robot swerved onto it; it still measured
        that lane after the loop's left turn), so the caller takes its offset modulo the line
        spacing."""
        return self.tracked_lane_unsure

    def doubt_tracked_lane(self) -> None:
        """After a lane change and back (avoidance.py, lane_returned): conde_tracking may still measure
        the lane on the left, its fit kept on the lines it followed there (D3, track seed 11, the north
        loop's west side, both engines: lane_index 1 at -0.80 m after the return; taken as the own lane's
        offset, the follower turned the robot round into the box it had passed).  The same doubt as after
        a right fork crossed straight, ended the same way (on_lane_measured)."""
        self.tracked_lane_unsure = True

    def on_lane_measured(self, offset_m: float, both_lines: bool, own_lane_m: float, lane_index: int = -1) -> None:
        """A lane measurement's offset [m] (as measured) and lane_index (conde_tracking's: 1 = the
        lane on the left): once the loop is over, one with both lines within own_lane_m of the lane's
        centre, not said to be the lane on the left, is against the own lane: the doubt ends."""
        if (self.tracked_lane_unsure and self.loop is None and both_lines and abs(offset_m) <= own_lane_m
                and lane_index != 1):
            self.tracked_lane_unsure = False

    def loop_exit(self, yaw_rad: Optional[float], travelled_m: float,
                  corners_seen: Sequence[str] = (), visible: Sequence[str] = ("right", "left")) -> Optional[str]:
        """merge_left / merge_right where the loop driven after a fork_straight turns back onto the
        central road (up to junction_window_m earlier where the cameras see that turn's corner,
        corners_seen), else None; yaw_rad: unwrapped heading [rad], travelled_m: distance [m].
        visible: the sides whose corners the lane measured now can show (junction_corners.py); a
        marked merge that cannot be seen now (the tracker on the lane on the left cannot show the
        right turn's corner) begins at the stored distance, not at the late fallback."""
        c, loop = self.config, self.loop
        self.fallback_note = ""
        if loop is None or yaw_rad is None:
            return None
        if loop.yaw0_rad is None:  # no odometry at the fork yet: count from the first heading
            loop.yaw0_rad = yaw_rad
        if loop.exit_mark_m is None:
            if loop.sign * (yaw_rad - loop.yaw0_rad) >= c.loop_sweep_rad - c.loop_exit_tolerance_rad:
                loop.exit_mark_m = travelled_m
            return None
        exit_m = c.loop_exit_m + c.loop_exit_tolerance_rad * loop.radius_m
        driven_m = travelled_m - loop.exit_mark_m
        if loop.merge in self.marked_sides and loop.merge in visible:
            seen = loop.merge in corners_seen and driven_m >= exit_m - c.junction_window_m
            due = driven_m >= exit_m + c.junction_fallback_m
        else:
            seen, due = False, driven_m >= exit_m
        if seen or due:
            self.loop = None
            self.turn_road_rad = self._median(loop.exit_directions_rad)
            if not seen and loop.merge in self.marked_sides and loop.merge in visible:
                self.fallback_note = fallback_note("merge_" + loop.merge, exit_m + c.junction_fallback_m,
                                                   "past the end of the loop's sweep")
            return "merge_" + loop.merge
        return None


def fallback_note(event: str, at_m: float, after: str = "past the crosswalk") -> str:
    """The note of a turn begun at its stored distance's fallback: no corner was seen."""
    return "%s at the fallback %.2f m %s: the cameras saw no corner" % (event, at_m, after)
