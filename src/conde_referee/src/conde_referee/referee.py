"""The referee's judgement of one run: fed with the ground-truth pose of the robot's root link,
the signalling panel's signal and (V1) the signs the robot reports, in time order, it gives the
events of the run with their penalties and, at the end, the report with the score. Pure Python
(numpy), no ROS: the node (scripts/conde_referee) only moves messages in and events out.

What is judged (thresholds and penalties from the rules file, rules.py):

- false start: the robot moves (standstill_tolerance_m) before the panel's first go signal
  (forward, left, right or parking);
- progress: the start line (0.21 m behind the crosswalk) and a gate at the far end of each loop,
  passed in the order north loop, start line southbound (west lane), south loop, start line
  northbound (east lane); each start-line passage is a half lap, two half laps a lap;
- wrong direction: the start line crossed in the lane of the opposite traffic (a gate passed out
  of order does not count as progress, but is not penalised);
- line touch: a point of the footprint on a solid boundary line of the road (once per touch: the
  robot has to be off the lines again for the next one);
- leaving the road: no point of the footprint on the road or a parking area: disqualified, the
  run ends;
- stop signal: crossing the crosswalk's far edge while "stop" is shown; a standstill near the
  crosswalk while "stop" is shown, or after "end of trial", with the robot's reference point
  outside the immobilisation zone (its lane, from stop_zone_depth_m before the crosswalk's near
  edge to 0.25 m past it);
- collisions: from the simulator's contacts (on_contacts: the objects the robot touches) once any
  contacts arrive; until then (and without a contacts topic) geometric: the footprint overlapping
  an object's footprint (boxes, cones, tunnel walls; sign faces and the tunnel roof only when lower
  than the robot's top), against the objects' start poses (an object pushed away is not followed).
  The report's collision_source says which ("contacts" or "geometric");
- wrong branch: at a loop's gate, the sense in which the loop is driven tells which way the robot
  went at the fork; a left/right order asks for the
  branch if the fork opens to that side (north fork: left; south fork: right), else for straight on.
  The order is the last direction signal shown before the robot passes the fork (used up there);
- parking (P/B challenges, or once "parking" is shown): standing still parking_stay_s with the
  whole footprint inside a free bay ends the run parked; in the occupied bay, or partly out of a
  free bay, ends it failed; touching a parking line is penalised;
- end of trial: the first standstill after "end of trial" ends the run;
- time limit: the challenge's time_limit_s after the go signal ends the run;
- V1: a reported sign is compared with the nearest sign position within sign_report_radius_m not
  reported yet.
"""
import math
from dataclasses import asdict, dataclass
from typing import List, Optional

import numpy as np

from conde_worlds import challenge_objects as co
from conde_worlds.track_variation import NOMINAL, TrackDimensions

from .course import Course, inside_box, polygons_overlap
from .footprint import Footprint
from .rules import Rules

GO_SIGNALS = ("forward", "left", "right", "parking")
GATES = ("north", "mid", "south", "start")
#: A standstill counts for the stop signal only this close to the crosswalk [m].
STOP_JUDGING_DISTANCE_M = 3.0
#: The immobilisation zone reaches this far past the crosswalk's near edge (the start pose).
ZONE_PAST_EDGE_M = 0.25
FOOTPRINT_SPACING_M = 0.02
#: An object whose centre is this far from where the layout put it has been displaced [m].
OBJECT_DISPLACED_M = 0.05
#: Wrong direction in a loop: this far driven in the lane of the opposite traffic [m] ...
WRONG_WAY_MIN_M = 0.5
#: ... between these loop angles [deg] (away from the forks), and not within OVERTAKE_M of arc of
#: an obstacle in the loop nor in a working zone (TAPER_DEG around it), where the other lane is
#: the way round.
LOOP_JUDGED_DEG = (20.0, 250.0)
OVERTAKE_M = 1.5
#: A pose this far from the previous one is a jump (a robot put elsewhere), not driving [m].
JUMP_M = 0.5


def stop_zones(depth_m: float, dims: TrackDimensions = NOMINAL) -> dict:
    """{lane: ((x_min, x_max), (y_min, y_max))} of the immobilisation zones [m] on the track dims:
    the lane from depth_m before the crosswalk to ZONE_PAST_EDGE_M into it (east lane northbound,
    west lane southbound)."""
    cw_near, cw_far = dims.crosswalk_y_m
    x, rh = dims.x_ref_m, dims.road_half_width_m
    return {"east": ((x, x + rh), (cw_near - depth_m, cw_near + ZONE_PAST_EDGE_M)),
            "west": ((x - rh, x), (cw_far - ZONE_PAST_EDGE_M, cw_far + depth_m))}


@dataclass(frozen=True)
class Event:
    n: int
    t_s: float
    kind: str
    penalty: float
    x_m: float
    y_m: float
    detail: str = ""

    def to_dict(self):
        d = asdict(self)
        d.update(t_s=round(self.t_s, 3), x_m=round(self.x_m, 3), y_m=round(self.y_m, 3))
        return d


class Referee:
    def __init__(self, rules: Rules, course: Course, footprint: Footprint):
        self.rules, self.course, self.footprint = rules, course, footprint
        self.events: List[Event] = []
        self.path = []                 # (t, x, y, yaw)
        self.panel = "none"
        self.go_at: Optional[float] = None
        self.start_xy = None
        self.moved = False
        self.next_gate = 0             # index into GATES
        self.half_laps = 0
        self.laps_done_at: Optional[float] = None
        self.pending_order: Optional[str] = None  # the last direction signal shown since the last fork
        self.order: Optional[str] = None          # the order for the loop being driven
        self.parking_ordered = course.kind == "parking"
        self.touching = False
        self.touching_parking = False
        self.colliding = set()
        self.contacts_seen = False  # True once on_contacts was called: contacts replace geometry
        self.anchor = None
        self.still_since = 0.0
        self.standstill_judged = False
        self.signs_reported = set()
        self.signs_right = 0
        self.parked: Optional[str] = None
        self.parking_failed = False
        self.over: Optional[str] = None
        self.disqualified = False
        self._last_given = {}
        # Where the objects are: their layout footprints until on_object_poses says otherwise.
        self.obstacle_polygons = {ob.name: ob.polygon for ob in course.obstacles}
        self.displaced = {}            # object name: largest distance from its layout pose [m]
        self.wrong_way_m = 0.0         # driven against the traffic of a loop lane, this stretch
        self.wrong_way_given = False

    # --- inputs -------------------------------------------------------------------------------------

    def on_panel(self, t_s: float, signal: str) -> List[Event]:
        self.panel = signal
        if signal in GO_SIGNALS and self.go_at is None:
            self.go_at = t_s
        if signal == "parking":
            self.parking_ordered = True
        if signal in ("left", "right", "forward"):
            self.pending_order = signal  # used up at the next fork
        return []

    def on_sign_report(self, t_s: float, sign: str) -> List[Event]:
        if self.over or not self.path:
            return []
        _, x, y, _ = self.path[-1]
        radius = self.rules.judging["sign_report_radius_m"]
        near = [(math.hypot(sx - x, sy - y), i) for i, (sx, sy, _) in enumerate(self.course.signs)
                if i not in self.signs_reported and math.hypot(sx - x, sy - y) <= radius]
        if not near:
            return self._give(t_s, "sign_wrong", x, y,
                              "reported %r with no unreported sign within %g m" % (sign, radius))
        _, i = min(near)
        self.signs_reported.add(i)
        truth = self.course.signs[i][2]
        if truth == sign:
            self.signs_right += 1
            return self._give(t_s, "sign_right", x, y, "sign %d: %s" % (i + 1, sign), penalty=0.0)
        return self._give(t_s, "sign_wrong", x, y, "sign %d: reported %r, it shows %r" % (i + 1, sign, truth))

    def on_contacts(self, t_s: float, touching) -> List[Event]:
        """The names of what the robot touches at t_s (world objects, other robots; never the
        ground), e.g. from /conde_sim/contacts. From the first call on, collisions are judged from
        these instead of geometrically; one event per object each time it starts being touched."""
        self.contacts_seen = True
        if self.over or not self.path:
            return []
        before = len(self.events)
        _, x, y, _ = self.path[-1]
        now = set(touching)
        for name in sorted(now - self.colliding):
            self._give(t_s, "collision", x, y, name, key="collision:" + name)
        self.colliding = now
        return self.events[before:]

    def on_object_poses(self, t_s: float, poses, robot_xy=None) -> List[Event]:
        """Where the world's objects are at t_s: {name: (x [m], y [m], yaw [rad])} (e.g. from
        the simulator's stamped model poses; unknown names are ignored). The geometric collision
        check follows them, and an object pushed more than OBJECT_DISPLACED_M from its layout pose
        is an event (once per object, no penalty of its own: the collision that pushed it has one),
        placed at robot_xy (the robot at t_s, [m]) or, without it, at the last pose judged."""
        before = len(self.events)
        if robot_xy is not None:
            x, y = robot_xy
        else:
            x, y = (self.path[-1][1], self.path[-1][2]) if self.path else (0.0, 0.0)
        for ob in self.course.obstacles:
            if ob.name not in poses:
                continue
            ox, oy, oyaw = poses[ob.name]
            self.obstacle_polygons[ob.name] = ob.moved_to(ox, oy, oyaw)
            moved_m = math.hypot(ox - ob.x_m, oy - ob.y_m)
            if moved_m <= OBJECT_DISPLACED_M:
                continue
            if ob.name not in self.displaced and not self.over:
                self._give(t_s, "object_displaced", x, y, "%s pushed %.2f m" % (ob.name, moved_m), penalty=0.0)
            self.displaced[ob.name] = max(moved_m, self.displaced.get(ob.name, 0.0))
        return self.events[before:]

    def on_pose(self, t_s: float, x: float, y: float, yaw: float) -> List[Event]:
        if self.over:
            return []
        before = len(self.events)
        prev = self.path[-1] if self.path else None
        self.path.append((t_s, x, y, yaw))
        if self.start_xy is None:
            self.start_xy = (x, y)
            self.anchor, self.still_since = (x, y), t_s
        self._false_start(t_s, x, y)
        if self.go_at is not None and t_s - self.go_at > self.course.time_limit_s:
            self._give(t_s, "time_limit", x, y, "%g s after the go signal" % self.course.time_limit_s, penalty=0.0)
            self.over = "time limit"
            return self.events[before:]
        samples = self.footprint.samples(x, y, yaw, FOOTPRINT_SPACING_M)
        if not self.course.on_surface(samples).any():
            self._give(t_s, "leave_road", x, y, "the whole footprint is off the road: disqualified")
            self.disqualified, self.over = True, "left the road"
            return self.events[before:]
        self._lines(t_s, x, y, samples)
        if not self.contacts_seen:
            self._collisions(t_s, x, y, yaw)
        if prev is not None:
            self._gates(t_s, prev[1], prev[2], x, y)
            self._loop_direction(t_s, prev[1], prev[2], x, y)
        self._standstill(t_s, x, y, samples)
        return self.events[before:]

    # --- checks -------------------------------------------------------------------------------------

    def _false_start(self, t_s, x, y):
        tol = self.rules.judging["standstill_tolerance_m"]
        if not self.moved and math.hypot(x - self.start_xy[0], y - self.start_xy[1]) > tol:
            self.moved = True
            if self.go_at is None:
                self._give(t_s, "false_start", x, y, "moved before the go signal (panel: %s)" % self.panel)

    def _lines(self, t_s, x, y, samples):
        def bulge_entry(stroke, pts):
            # Once parking is ordered, the east line beside the parking areas is their entry.
            if not (self.parking_ordered and stroke.name.startswith("central_east")):
                return np.zeros(len(pts), dtype=bool)
            entry = np.zeros(len(pts), dtype=bool)
            for y0, y1 in (self.course.dims.bulge_dashed_y_m, self.course.dims.bay_area_y_m):
                entry |= (pts[:, 1] >= y0) & (pts[:, 1] <= y1)
            return entry

        hits = self.course.touches(samples, self.course.boundary_lines, bulge_entry)
        if hits and not self.touching:
            self._give(t_s, "line_touch", x, y, ", ".join(sorted(hits)))
        self.touching = bool(hits)
        if self.parking_ordered:
            hits = self.course.touches(samples, self.course.parking_lines)
            if hits and not self.touching_parking:
                self._give(t_s, "parking_line_touch", x, y, ", ".join(sorted(hits)))
            self.touching_parking = bool(hits)

    def _collisions(self, t_s, x, y, yaw):
        corners = self.footprint.corners(x, y, yaw)
        now = set()
        for ob in self.course.obstacles:
            if ob.z_bottom_m < self.footprint.z_max_m and polygons_overlap(corners, self.obstacle_polygons[ob.name]):
                now.add(ob.name)
                if ob.name not in self.colliding:
                    self._give(t_s, "collision", x, y, ob.name, key="collision:" + ob.name)
        self.colliding = now

    def _gates(self, t_s, px, py, x, y):
        crossed = []
        d = self.course.dims
        start_y = self.course.start_line_y_m
        if py < start_y <= y:
            crossed.append("start" if x > d.x_ref_m else None)
        elif py >= start_y > y:
            crossed.append("mid" if x < d.x_ref_m else None)
        cw_near, cw_far = d.crosswalk_y_m
        if (py < cw_far <= y and x > d.x_ref_m) or (py > cw_near >= y and x < d.x_ref_m):
            if self.panel == "stop" and self.go_at is not None:
                self._give(t_s, "stop_not_respected", x, y, "crossed the crosswalk while the panel shows stop")
        if abs(x - d.x_ref_m) <= d.road_half_width_m and (py < d.fork_y_m <= y or py > -d.fork_y_m >= y):
            self.order, self.pending_order = self.pending_order, None  # at a fork
        lcx = d.loop_centre_x_m
        for gate, sign in (("north", 1.0), ("south", -1.0)):
            cy = sign * d.loop_centre_y_m
            if (px - lcx) * (x - lcx) < 0 or (x == lcx != px):
                if 0.0 < sign * (y - cy) < self.course.gate_length_m:
                    crossed.append(gate)
                    self._branch(t_s, gate, x, y, east=x > px)
        for gate in crossed:
            if gate is None:
                self._give(t_s, "wrong_direction", x, y, "crossed the start line against the traffic of the lane")
            elif gate == GATES[self.next_gate % 4]:  # gates out of order do not count
                self.next_gate += 1
                if gate in ("mid", "start"):
                    self.half_laps += 1
                    if self.half_laps == 2 * int(self.rules.scoring["laps"]) and self.laps_done_at is None:
                        self.laps_done_at = t_s
                        self._give(t_s, "laps_done", x, y, "%d laps" % self.rules.scoring["laps"], penalty=0.0)

    def _loop_direction(self, t_s, px, py, x, y):
        """Traffic keeps right: a loop driven counter-clockwise in its outer lane, clockwise in its
        inner lane. WRONG_WAY_MIN_M the other way is one wrong_direction, until the robot is back
        in a right lane."""
        dx, dy = x - px, y - py
        step_m = math.hypot(dx, dy)
        if step_m > JUMP_M:
            self.wrong_way_m = 0.0
            return
        if step_m < 1e-6:
            return
        where = self.course.loop_position(x, y)
        if where is None or self._lane_change_allowed(*where):
            self.wrong_way_m = 0.0
            return
        loop, angle_deg, radius_m = where
        cx, cy = co.loop_centre(loop, self.course.dims)
        divider_r = self.course.dims.loop_radius_m
        counter_clockwise = (x - cx) * dy - (y - cy) * dx > 0.0
        if counter_clockwise == (radius_m > divider_r):  # the right lane
            self.wrong_way_m, self.wrong_way_given = 0.0, False
            return
        self.wrong_way_m += step_m
        if self.wrong_way_m >= WRONG_WAY_MIN_M and not self.wrong_way_given:
            self.wrong_way_given = True
            lane = "outer" if radius_m > divider_r else "inner"
            self._give(t_s, "wrong_direction", x, y, "%s loop, %s lane, against its traffic (%.0f deg)"
                       % (loop, lane, angle_deg), key="wrong_direction:loop")

    def _lane_change_allowed(self, loop, angle_deg, radius_m) -> bool:
        lo, hi = LOOP_JUDGED_DEG
        if not lo <= angle_deg <= hi:
            return True
        zone = self.course.features.get("working_zone")
        if zone and zone["loop"] == loop and (zone["from_deg"] - co.TAPER_DEG <= angle_deg
                                              <= zone["to_deg"] + co.TAPER_DEG):
            return True
        margin_deg = math.degrees(OVERTAKE_M / self.course.dims.loop_radius_m)
        return any(o["loop"] == loop and abs(o["angle_deg"] - angle_deg) <= margin_deg
                   for o in self.course.features.get("obstacles", []))

    def _branch(self, t_s, gate, x, y, east):
        # Driving a loop clockwise (eastward at its far end) means the branch was taken at its fork.
        took_branch = east
        fork_side = "left" if gate == "north" else "right"
        if self.order in ("left", "right"):
            wanted_branch = self.order == fork_side
            if took_branch != wanted_branch:
                self._give(t_s, "wrong_branch", x, y, "order %s: expected %s at the %s fork" % (
                    self.order, "the branch" if wanted_branch else "straight on", gate))
        self.order = None

    def _standstill(self, t_s, x, y, samples):
        j = self.rules.judging
        if math.hypot(x - self.anchor[0], y - self.anchor[1]) > j["standstill_tolerance_m"]:
            self.anchor, self.still_since, self.standstill_judged = (x, y), t_s, False
            return
        still_s = t_s - self.still_since
        if self.go_at is None or self.standstill_judged:
            return
        if self.parking_ordered and still_s >= self.rules.scoring["parking_stay_s"]:
            if self._judge_parking(t_s, x, y, samples):
                self.standstill_judged = True
                return
        if still_s < j["standstill_s"] or self.panel not in ("stop", "end_of_trial"):
            return
        in_zone, near = self._in_stop_zone(x, y)
        if self.panel == "end_of_trial":
            self.standstill_judged = True
            if not in_zone:
                self._give(t_s, "stopped_outside_zone", x, y, "stopped after the end of trial outside the zone")
            self._give(t_s, "trial_end", x, y, "stopped after the end-of-trial signal", penalty=0.0)
            self.over = "end of trial"
        elif near:
            self.standstill_judged = True
            if not in_zone:
                self._give(t_s, "stopped_outside_zone", x, y, "stopped for the stop signal outside the zone")

    def _in_stop_zone(self, x, y):
        d = self.course.dims
        on_straight = abs(x - d.x_ref_m) <= d.road_half_width_m
        cw_near, cw_far = d.crosswalk_y_m
        near = on_straight and cw_near - STOP_JUDGING_DISTANCE_M <= y <= cw_far + STOP_JUDGING_DISTANCE_M
        zones = stop_zones(self.rules.judging["stop_zone_depth_m"], d).values()
        in_zone = any(inside_box([(x, y)], box)[0] for box in zones)
        return in_zone, near

    def _judge_parking(self, t_s, x, y, samples) -> bool:
        """True when the standstill was in a parking place (judged: the run ends)."""
        centre = samples.mean(axis=0, keepdims=True)
        for name, box in self.course.free_bays().items():
            if inside_box(samples, box).all():
                self.parked = name
                self._give(t_s, "parked", x, y, "inside the free %s bay" % name, penalty=0.0)
                self.over = "parked"
                return True
        from conde_worlds.challenge_objects import parking_bays
        occupied = self.course.occupied_bay
        if occupied and inside_box(centre, parking_bays(self.course.dims)[occupied]).all():
            return self._fail_parking(t_s, "parked_in_occupied_bay", x, y,
                                      "the %s bay is occupied" % self.course.occupied_bay)
        for name, box in self.course.free_bays().items():
            if inside_box(centre, box).all():
                return self._fail_parking(t_s, "parked_outside_bay", x, y, "not entirely inside the %s bay" % name)
        return False

    def _fail_parking(self, t_s, kind, x, y, detail) -> bool:
        """Ends the run as a failed parking (an event without penalty); True, for _judge_parking."""
        self.parking_failed = True
        self._give(t_s, kind, x, y, detail, penalty=0.0)
        self.over = "parking failed"
        return True

    # --- events and report --------------------------------------------------------------------------

    def _give(self, t_s, kind, x, y, detail, penalty=None, key=None):
        key = key or kind
        if penalty is None:
            last = self._last_given.get(key)
            if last is not None and t_s - last < self.rules.scoring["repeat_debounce_s"]:
                return []
            self._last_given[key] = t_s
            penalty = self.rules.penalties[kind]
        event = Event(len(self.events) + 1, t_s, kind, penalty, x, y, detail)
        self.events.append(event)
        return [event]

    def finish(self, t_s: Optional[float] = None) -> dict:
        """Ends the run (if it has not ended) and returns the report."""
        if t_s is None:
            t_s = self.path[-1][0] if self.path else 0.0
        if not self.over:
            self.over = "stopped"
        return self.report(t_s)

    def report(self, t_s: float) -> dict:
        """The report as it stands at t_s (the score so far while the run goes on)."""
        s = self.rules.scoring
        penalty = sum(e.penalty for e in self.events)
        target = 2 * int(s["laps"])
        driving_s = None
        if self.go_at is not None:
            driving_s = (self.laps_done_at if self.laps_done_at is not None else t_s) - self.go_at
        kind = self.course.kind
        if self.disqualified:
            score = 0.0
        elif kind == "parking":
            score = s["parking_points"] - penalty if self.parked else 0.0
        elif kind == "signs":
            score = s["sign_points"] * self.signs_right - penalty
        else:
            score = s["points_per_half_lap"] * min(self.half_laps, target) - penalty
            if self.laps_done_at is not None:
                score += target * s["reference_half_lap_s"] - driving_s
        return {
            "challenge": self.course.challenge, "seed": self.course.seed, "track_seed": self.course.track_seed,
            "kind": kind, "rules": self.rules.name,
            "score": round(score, 3), "penalty_total": penalty, "disqualified": self.disqualified,
            "end": self.over, "laps": self.half_laps // 2, "half_laps": self.half_laps,
            "driving_time_s": None if driving_s is None else round(driving_s, 3),
            "parked": self.parked, "signs_right": self.signs_right,
            "objects_displaced_m": {k: round(v, 3) for k, v in sorted(self.displaced.items())},
            "collision_source": "contacts" if self.contacts_seen else "geometric",
            "footprint_m": [self.footprint.x_min_m, self.footprint.x_max_m, self.footprint.y_min_m,
                            self.footprint.y_max_m],
            "events": [e.to_dict() for e in self.events],
        }


def judge_recorded(referee: Referee, poses, panel=(), reports=()) -> dict:
    """Feeds a recorded run to `referee` in time order (at equal times: panel, then reports, then
    poses) and returns its report. poses [(t, x, y, yaw)], panel [(t, signal name)], reports
    [(t, sign name)]."""
    inputs = [(t, 0, referee.on_panel, (s,)) for t, s in panel]
    inputs += [(t, 1, referee.on_sign_report, (s,)) for t, s in reports]
    inputs += [(p[0], 2, referee.on_pose, tuple(p[1:])) for p in poses]
    for t, _, call, args in sorted(inputs, key=lambda item: (item[0], item[1])):
        call(t, *args)
    return referee.finish()
