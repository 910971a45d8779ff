"""A one-dimensional model of the robot on its route, to feed DecisionLogic with the inputs
conde_tracking would give.  Pure Python; shared by the decision tests.

The robot's position s [m] runs along its lane from the start (s = 0: base_footprint at the
near edge of the crosswalk, as at the spawn pose).  It meets the near edge of a crosswalk every
HALF_LAP_M (the lane-centre length of the track between two crossings).  The camera reports a
crosswalk whose near edge is between VIEW_M[0] and VIEW_M[1] ahead, with its distance.  The robot
drives at the commanded speed times `speed_scale` (1: exactly as the logic dead-reckons).

Heading (fed to on_odometry each step): north at the start; it turns with the curvature the logic
commands (the junctions' arcs) and, after a fork taken straight, around the loop beyond it:
LOOP_STRAIGHT_M of straight road, then LOOP_SWEEP_RAD along an arc of the loop's lane radius
(counter-clockwise after a fork that opens left, clockwise after one that opens right), then
straight on.  (The straight before the north loop is shortened from the track's 3.18 m so that
the loop and the turn back onto the central road fit into the model's mean half lap.)"""

import math
from dataclasses import dataclass, replace
from typing import Tuple

#: Lane-centre length between two crossings: a lap is 40.66 m (geometry YAML), split 21.5 + 19.1 m
#: or 19.1 + 21.6 m depending on the route; the model uses the mean.
HALF_LAP_M = 40.66405 / 2.0
VIEW_M = (0.15, 1.2)  # [m] range ahead in which the ground cameras see the crosswalk's near edge
DT_S = 1.0 / 30.0  # camera rate
FORK_SIDES = ("left", "right")  # the side each fork opens to, in turn from the start
LOOP_STRAIGHT_M = {"left": 1.8, "right": 3.18}  # fork to the start of the loop's arc [m]
LOOP_RADIUS_M = {"left": 2.5685, "right": 1.7865}  # the lane's radius around the loop [m]
LOOP_SWEEP_RAD = 1.5 * math.pi
NEW_LANE_SEEN_RAD = math.radians(45)  # a junction's turn shows the lane it leads to from here on
LANE_SPACING_M = 0.782  # own lane centre to the other (left) lane's centre [m]
OBSTACLE_VIEW_M = (-0.2, 2.5)  # x range [m] in which the ground cameras see objects on the floor
BAY_LINE_VIEW_M = (0.3, 1.6)  # x range [m] in which conde_tracking reports the bay lines
PARALLEL_START_VIEW_M = (0.2, 1.8)  # x range [m] in which it reports the parallel bay's start
CORNER_VIEW_M = 1.0  # a line's end is seen up to this far ahead [m] (the fit's range, less the end's gap)
OFFSET_TIME_CONSTANT_S = 0.3  # with follow_reference: the lateral offset follows its reference this fast [s]


@dataclass
class Lane:
    """The fields of conde_msgs/LaneMeasurement."""

    lateral_offset_m: float = 0.0
    heading_error_rad: float = 0.0
    crosswalk_seen: bool = False
    crosswalk_distance_m: float = 0.0
    confidence: float = 1.0
    right_line_end_m: float = float("nan")  # no junction corner in view (the model has none)
    left_line_end_m: float = float("nan")
    far_left_line_end_m: float = float("nan")
    obstacle_kinds: Tuple[str, ...] = ()
    obstacle_distances_m: Tuple[float, ...] = ()
    obstacle_lane_y_min_m: Tuple[float, ...] = ()
    obstacle_lane_y_max_m: Tuple[float, ...] = ()
    obstacle_y_max_m: Tuple[float, ...] = ()  # in base_footprint (set for the bays' boxes only)
    bay_line_distances_m: Tuple[float, ...] = ()
    lane_index: int = -1  # which lane conde_tracking measured: 0 own, 1 the one on the left, -1 not known
    lane_spacing_m: float = float("nan")  # the lanes' centres apart as it measured them [m]
    parallel_bay_start_m: float = float("nan")
    obstacle_far_distances_m: Tuple[float, ...] = ()  # set for the bays' boxes only


@dataclass
class Obstacle:
    """A box or cone on the route: its near edge at s_near_m, its depth along the road, its lateral
    extent from the own lane's centre [m]."""

    kind: str
    s_near_m: float
    y_min_m: float
    y_max_m: float
    depth_m: float = 0.6


class Road:
    def __init__(self, logic, speed_scale=1.0, start_s=0.0, t0_s=100.0, odometry_distance=True,
                 new_lane_in_turns=False):
        self.logic = logic
        self.s = start_s
        self.t = t0_s
        self.speed_scale = speed_scale
        self.lane_confidence = 1.0
        self.lateral_offset_m = 0.02
        self.heading_error_rad = -0.01
        self.outputs = []  # every DecisionOutput
        self.positions = []  # s at each output
        self.yaw_rad = 0.5 * math.pi
        self.odometry_distance = odometry_distance  # odometry reports the path length (s) too
        self.forks = 0  # forks passed
        self.loop = None  # (arc start s, arc end s, signed curvature) of the loop being driven
        self.turned_rad = 0.0  # heading change in the junction's arc being driven (+ = left), 0 outside
        self.new_lane_in_turns = new_lane_in_turns  # the cameras see the new lane in the arcs' second half
        self.obstacles = []  # Obstacle on the route
        self.follow_reference = False  # the lateral offset follows the logic's reference (a lane change)
        self.own_offset_m = self.lateral_offset_m  # from the own lane's centre (follow_reference)
        self.path_m = start_s  # the robot's path length (odometry) [m]: s, less inside curves when offset
        self.relock = True  # the tracker measures against the lane whose centre the robot is nearer
        self.bay_lines_s = []  # the bay-parking area's lines across the road on the right, along the route [m]
        self.bay_boxes_s = []  # near edges of boxes in its bays, along the route [m]
        self.parallel_start_s = None  # where the parallel bay's straight part begins, along the route [m]
        self.parallel_boxes_s = []  # (near, far) ends of boxes standing in it, along the route [m]
        # junction corners the cameras see: (side, s of the corner, how far beyond it the line leaves its band [m])
        self.corners = []
        # which lane the tracker measures (0 own, 1 the lane on the left; None: the nearer one, see relock)
        self.tracked_lane = None
        self.report_lane_index = False  # the measurement says which lane (lane_index, lane_spacing_m)
        # follow_reference: the robot's offset follows what the logic gives the control (its offset
        # and reference), not the reference in the tracked lane's frame
        self.steer_on_output = False

    def _with_parallel_bay(self, lane):
        """The lane measurement with the parallel bay's start and its boxes in view (their far ends
        seen up to OBSTACLE_VIEW_M's end, their near ends from OBSTACLE_VIEW_M's start)."""
        if self.parallel_start_s is not None:
            ahead_m = self.parallel_start_s - self.s
            if PARALLEL_START_VIEW_M[0] <= ahead_m <= PARALLEL_START_VIEW_M[1]:
                lane = replace(lane, parallel_bay_start_m=ahead_m)
        seen = [(max(near - self.s, OBSTACLE_VIEW_M[0]), far - self.s) for near, far in self.parallel_boxes_s
                if near - self.s <= OBSTACLE_VIEW_M[1] and far - self.s >= OBSTACLE_VIEW_M[0]]
        if not seen:
            return lane
        n = len(lane.obstacle_kinds)
        fars = tuple(lane.obstacle_far_distances_m) or (float("nan"),) * n
        return replace(lane, obstacle_kinds=lane.obstacle_kinds + ("box",) * len(seen),
                       obstacle_distances_m=lane.obstacle_distances_m + tuple(near for near, _ in seen),
                       obstacle_lane_y_min_m=lane.obstacle_lane_y_min_m + (-1.1,) * len(seen),
                       obstacle_lane_y_max_m=lane.obstacle_lane_y_max_m + (-0.53,) * len(seen),
                       obstacle_y_max_m=(tuple(lane.obstacle_y_max_m) or (0.0,) * n) + (-0.53,) * len(seen),
                       obstacle_far_distances_m=fars + tuple(far for _, far in seen))

    def _with_bay_area(self, lane):
        """The lane measurement with the bay lines and bay boxes in view (BAY_LINE_VIEW_M ahead), and
        the parallel bay."""
        lane = self._with_parallel_bay(lane)
        if not self.bay_lines_s and not self.bay_boxes_s:
            return lane
        lines = tuple(s - self.s for s in self.bay_lines_s if BAY_LINE_VIEW_M[0] <= s - self.s <= BAY_LINE_VIEW_M[1])
        boxes = tuple(s - self.s for s in self.bay_boxes_s if OBSTACLE_VIEW_M[0] <= s - self.s <= OBSTACLE_VIEW_M[1])
        n = len(lane.obstacle_kinds)
        return replace(lane, bay_line_distances_m=lines, obstacle_kinds=lane.obstacle_kinds + ("box",) * len(boxes),
                       obstacle_distances_m=lane.obstacle_distances_m + boxes,
                       obstacle_lane_y_min_m=lane.obstacle_lane_y_min_m + (-1.6,) * len(boxes),
                       obstacle_lane_y_max_m=lane.obstacle_lane_y_max_m + (-0.9,) * len(boxes),
                       obstacle_y_max_m=(tuple(lane.obstacle_y_max_m) or (0.0,) * n) + (-0.9,) * len(boxes))

    def _tracked_shift_m(self):
        """The tracked lane's centre from the own lane's centre [m]."""
        if self.tracked_lane is not None:
            return self.tracked_lane * LANE_SPACING_M
        return LANE_SPACING_M if self.relock and self.own_offset_m > 0.5 * LANE_SPACING_M else 0.0

    def _obstacle_fields(self, shift_m):
        seen = []
        for o in self.obstacles:
            ahead_m = o.s_near_m - self.s
            if OBSTACLE_VIEW_M[0] <= ahead_m + o.depth_m and ahead_m <= OBSTACLE_VIEW_M[1]:
                seen.append((max(ahead_m, OBSTACLE_VIEW_M[0]), o))
        seen.sort(key=lambda item: item[0])
        return dict(obstacle_kinds=tuple(o.kind for _, o in seen), obstacle_distances_m=tuple(x for x, _ in seen),
                    obstacle_lane_y_min_m=tuple(o.y_min_m - shift_m for _, o in seen),
                    obstacle_lane_y_max_m=tuple(o.y_max_m - shift_m for _, o in seen))

    def next_near_edge_m(self):
        """Position of the first crosswalk near edge at least VIEW_M[0] ahead of the robot."""
        k = int((self.s + VIEW_M[0]) // HALF_LAP_M)
        edge = k * HALF_LAP_M
        return edge if edge >= self.s + VIEW_M[0] else edge + HALF_LAP_M

    def lane(self):
        """The lane measurement at the robot's place, with the line ends of the corners in view."""
        lane = self._lane()
        for side, corner_s, line_offset_m in self.corners:
            end_m = corner_s + line_offset_m - self.s
            if self.turned_rad == 0.0 and 0.0 < end_m <= CORNER_VIEW_M:
                lane = replace(lane, **{"right_line_end_m" if side == "right" else "far_left_line_end_m": end_m})
        return lane

    def _lane(self):
        ahead_m = self.next_near_edge_m() - self.s
        seen = ahead_m <= VIEW_M[1]
        if self.turned_rad == 0.0:
            if self.follow_reference or self.obstacles:
                shift_m = self._tracked_shift_m()
                index = dict(lane_index=int(round(shift_m / LANE_SPACING_M)), lane_spacing_m=LANE_SPACING_M) \
                    if self.report_lane_index else {}
                return Lane(self.own_offset_m - shift_m, self.heading_error_rad, seen, ahead_m if seen else 0.0,
                            self.lane_confidence, **self._obstacle_fields(shift_m), **index)
            return Lane(self.lateral_offset_m, self.heading_error_rad, seen, ahead_m if seen else 0.0,
                        self.lane_confidence)
        # In a junction's arc: one line of the road left behind, then (turned through more than
        # NEW_LANE_SEEN_RAD) both lines of the lane the turn leads to, 90 deg from the old one.
        if not self.new_lane_in_turns or abs(self.turned_rad) < NEW_LANE_SEEN_RAD:
            return Lane(self.lateral_offset_m, self.heading_error_rad, False, 0.0, 0.5)
        remaining = math.copysign(0.5 * math.pi, self.turned_rad) - self.turned_rad
        return Lane(self.lateral_offset_m, -remaining, False, 0.0, 1.0)

    def step(self):
        self.logic.on_odometry(self.yaw_rad, self.path_m if self.odometry_distance else None)
        out = self.logic.on_lane(self._with_bay_area(self.lane()), self.t)
        self.outputs.append(out)
        self.positions.append(self.s)
        for event in out.events:
            if event.startswith("fork_"):
                side = FORK_SIDES[self.forks % 2]
                self.forks += 1
                if event == "fork_straight":
                    start = self.s + LOOP_STRAIGHT_M[side]
                    radius = LOOP_RADIUS_M[side]
                    self.loop = (start, start + LOOP_SWEEP_RAD * radius, (1.0 if side == "left" else -1.0) / radius)
        ds = out.linear_velocity_mps * self.speed_scale * DT_S
        if self.follow_reference:
            # the reference is in the own lane's frame while the logic changes lanes, else the tracked lane's
            wanted_m = out.lateral_offset_ref_m + (0.0 if self.logic.avoidance.active else self._tracked_shift_m())
            if self.steer_on_output:
                wanted_m = self.own_offset_m - (out.lateral_offset_m - out.lateral_offset_ref_m)
            # ... plus the heading reference's drift (the lane change's ramp: the control follows it)
            moved_m = ((wanted_m - self.own_offset_m) * min(1.0, DT_S / OFFSET_TIME_CONSTANT_S)
                       + ds * math.tan(out.heading_ref_rad))
            self.own_offset_m += moved_m
            heading_error_rad = math.atan2(moved_m, ds) if ds > 0 else 0.0
            self.yaw_rad += heading_error_rad - self.heading_error_rad  # the odometry turns with the robot
            self.heading_error_rad = heading_error_rad
        self.turned_rad = self.turned_rad + out.path_curvature_per_m * ds if out.path_curvature_per_m != 0.0 else 0.0
        if out.path_curvature_per_m != 0.0:
            self.yaw_rad += out.path_curvature_per_m * ds
        elif self.loop is not None:
            start, end, curvature = self.loop
            loop_turn_rad = curvature * max(0.0, min(self.s + ds, end) - max(self.s, start))
            self.yaw_rad += loop_turn_rad
            if self.follow_reference:  # beside the own lane, inside a curve the robot drives a shorter arc
                self.path_m -= self.own_offset_m * loop_turn_rad
            if self.s + ds >= end:
                self.loop = None
        self.s += ds
        self.path_m += ds
        self.t += DT_S
        return out

    def run(self, seconds):
        outs = [self.step() for _ in range(int(round(seconds / DT_S)))]
        return outs

    def drive_m(self, distance_m, max_s=600.0):
        """Steps until the robot has moved distance_m (it must be moving)."""
        goal = self.s + distance_m
        for _ in range(int(max_s / DT_S)):
            if self.s >= goal:
                return
            self.step()
        raise AssertionError("the robot did not drive %.2f m (stuck at s = %.2f in %s)"
                             % (distance_m, self.s, self.logic.state))

    def until(self, event, max_s=600.0):
        """Steps until `event` is produced; returns that step's output."""
        for _ in range(int(max_s / DT_S)):
            out = self.step()
            if event in out.events:
                return out
        raise AssertionError("no %s within %g s (state %s, s = %.2f)" % (event, max_s, self.logic.state, self.s))

    def stand_still_at(self, seconds=3.0):
        """Runs `seconds`; asserts the robot does not move, returns where it stands."""
        s0 = self.s
        self.run(seconds)
        assert self.s == s0, "robot moved from %.3f to %.3f in %s" % (s0, self.s, self.logic.state)
        return s0
