"""What rviz shows of the referee (visualization_msgs/MarkerArray, frame `world`): the course's
gates (start line, loop gates), the immobilisation zones, the parking bays (free: green, occupied:
red), one marker and a text per event where it happened, and the score. Pure functions of the
course, the rules and the referee's events: the node only publishes what they build.

Namespaces (rviz lists them under the display): referee_gates, referee_zones, referee_bays,
referee_events, referee_event_labels, referee_score.
"""
from typing import List, Sequence

from geometry_msgs.msg import Point, Quaternion
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker

from conde_worlds import challenge_objects as co

from .course import Course
from .referee import Event, stop_zones

FRAME = "world"
#: Colours (r, g, b, alpha 0..1) of what the markers show.
RGBA = {"gate": (1.0, 0.85, 0.0, 1.0), "zone": (0.2, 0.5, 1.0, 0.35), "free_bay": (0.1, 0.9, 0.2, 0.35),
        "occupied_bay": (1.0, 0.1, 0.1, 0.35), "penalty": (1.0, 0.15, 0.15, 1.0), "progress": (0.1, 0.9, 0.2, 1.0),
        "text": (1.0, 1.0, 1.0, 1.0)}
LINE_WIDTH_M = 0.04
AREA_HEIGHT_M = 0.01
EVENT_DIAMETER_M = 0.2
EVENT_TEXT_M = 0.18
SCORE_TEXT_M = 0.35
#: The score is written above the west loops (in the middle of challenge.rviz's view) [m].
SCORE_XYZ_M = (-0.8, 0.0, 1.5)


def _marker(ns: str, marker_id: int, kind: int, rgba: Sequence[float]) -> Marker:
    m = Marker()
    m.header.frame_id = FRAME
    m.ns, m.id, m.type, m.action = ns, marker_id, kind, Marker.ADD
    m.pose.orientation = Quaternion(0.0, 0.0, 0.0, 1.0)
    m.color = ColorRGBA(*rgba)
    m.frame_locked = True
    return m


def _segment(ns: str, marker_id: int, a, b, rgba) -> Marker:
    m = _marker(ns, marker_id, Marker.LINE_STRIP, rgba)
    m.scale.x = LINE_WIDTH_M
    m.points = [Point(a[0], a[1], 0.02), Point(b[0], b[1], 0.02)]
    return m


def _area(ns: str, marker_id: int, box, rgba) -> Marker:
    (x0, x1), (y0, y1) = box
    m = _marker(ns, marker_id, Marker.CUBE, rgba)
    m.pose.position = Point((x0 + x1) / 2.0, (y0 + y1) / 2.0, AREA_HEIGHT_M / 2.0)
    m.scale.x, m.scale.y, m.scale.z = x1 - x0, y1 - y0, AREA_HEIGHT_M
    return m


def gates(course: Course) -> List[Marker]:
    """The start line across the straight and the line at each loop's far end."""
    d, y = course.dims, course.start_line_y_m
    out = [_segment("referee_gates", 0, (d.x_ref_m - d.road_half_width_m, y),
                    (d.x_ref_m + d.road_half_width_m, y), RGBA["gate"])]
    for i, loop in enumerate(("north", "south"), start=1):
        cx, cy = co.loop_centre(loop, d)
        sign = 1.0 if loop == "north" else -1.0
        out.append(_segment("referee_gates", i, (cx, cy), (cx, cy + sign * course.gate_length_m), RGBA["gate"]))
    return out


def zones(stop_zone_depth_m: float, course: Course = None) -> List[Marker]:
    """The immobilisation zones before the crosswalk, one per lane (on the course's track)."""
    boxes = stop_zones(stop_zone_depth_m, course.dims) if course else stop_zones(stop_zone_depth_m)
    return [_area("referee_zones", i, box, RGBA["zone"]) for i, (_, box) in enumerate(sorted(boxes.items()))]


def bays(course: Course) -> List[Marker]:
    """The places the robot may park (green) and the occupied bay (red); none outside P and B."""
    if course.kind != "parking":
        return []
    free = sorted(course.free_bays().items())
    out = [_area("referee_bays", i, box, RGBA["free_bay"]) for i, (_, box) in enumerate(free)]
    if course.occupied_bay:
        occupied = co.parking_bays(course.dims)[course.occupied_bay]
        out.append(_area("referee_bays", len(out), occupied, RGBA["occupied_bay"]))
    return out


def course_markers(course: Course, stop_zone_depth_m: float) -> List[Marker]:
    return gates(course) + zones(stop_zone_depth_m, course) + bays(course)


def event_markers(events: Sequence[Event]) -> List[Marker]:
    """Per event: a sphere where it happened (red with a penalty, green without) and its number,
    kind and penalty written above it, e.g. "3 line_touch -10"."""
    out = []
    for e in events:
        dot = _marker("referee_events", e.n, Marker.SPHERE, RGBA["penalty"] if e.penalty else RGBA["progress"])
        dot.pose.position = Point(e.x_m, e.y_m, EVENT_DIAMETER_M / 2.0)
        dot.scale.x = dot.scale.y = dot.scale.z = EVENT_DIAMETER_M
        label = _marker("referee_event_labels", e.n, Marker.TEXT_VIEW_FACING, RGBA["text"])
        label.pose.position = Point(e.x_m, e.y_m, EVENT_DIAMETER_M + EVENT_TEXT_M)
        label.scale.z = EVENT_TEXT_M
        label.text = "%d %s" % (e.n, e.kind) + (" -%g" % e.penalty if e.penalty else "")
        out += [dot, label]
    return out


def score_text(report: dict) -> str:
    """E.g. "D1 score 93.0 | penalties 10 | 1 laps | running" (from Referee.report)."""
    return "%s score %.1f | penalties %g | %d laps | %s" % (report["challenge"], report["score"],
                                                            report["penalty_total"], report["laps"],
                                                            report["end"] or "running")


def score_marker(report: dict) -> Marker:
    m = _marker("referee_score", 0, Marker.TEXT_VIEW_FACING, RGBA["text"])
    m.pose.position = Point(*SCORE_XYZ_M)
    m.scale.z = SCORE_TEXT_M
    m.text = score_text(report)
    return m


def all_markers(course: Course, stop_zone_depth_m: float, events: Sequence[Event], report: dict) -> List[Marker]:
    """Everything rviz shows, as one array (the topic is latched: a late rviz gets it all)."""
    return course_markers(course, stop_zone_depth_m) + event_markers(events) + [score_marker(report)]
