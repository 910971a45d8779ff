"""The rviz markers of the referee (conde_referee.markers): course, events and score, built from
scripted runs (pure, no ROS master)."""
import pytest
from visualization_msgs.msg import Marker

from conde_worlds import challenge_objects as co
from conde_worlds import track_geometry as tg
from conde_referee import markers as mk
from conde_referee.course import START_LINE_Y_M, Course
from conde_referee.referee import stop_zones
from referee_paths import EAST_LANE_X, judge, line, straight

DEPTH_M = 1.0


def by_ns(markers):
    out = {}
    for m in markers:
        out.setdefault(m.ns, []).append(m)
    return out


def test_driving_course_has_gates_and_zones_but_no_bays():
    ms = by_ns(mk.course_markers(Course.from_layout("D1"), DEPTH_M))
    assert sorted(ms) == ["referee_gates", "referee_zones"]
    start, north, south = ms["referee_gates"]
    assert [(p.x, p.y) for p in start.points] == [(tg.X_REF - tg.ROAD_HALF_WIDTH, START_LINE_Y_M),
                                                  (tg.X_REF + tg.ROAD_HALF_WIDTH, START_LINE_Y_M)]
    assert north.points[1].y > north.points[0].y and south.points[1].y < south.points[0].y
    assert north.points[0].x == pytest.approx(co.loop_centre("north")[0])
    for marker, (_, ((x0, x1), (y0, y1))) in zip(ms["referee_zones"], sorted(stop_zones(DEPTH_M).items())):
        assert marker.type == Marker.CUBE
        assert (marker.pose.position.x, marker.pose.position.y) == pytest.approx(((x0 + x1) / 2, (y0 + y1) / 2))
        assert (marker.scale.x, marker.scale.y) == pytest.approx((x1 - x0, y1 - y0))
    all_ids = [(m.ns, m.id) for m in mk.course_markers(Course.from_layout("D1"), DEPTH_M)]
    assert len(set(all_ids)) == len(all_ids)


def test_bays_free_green_and_occupied_red():
    ms = by_ns(mk.course_markers(Course.from_layout("B2", "v1"), DEPTH_M))["referee_bays"]
    assert len(ms) == 2
    free, occupied = ms
    (x0, x1), (y0, y1) = co.parking_bays()["south"]  # v1 occupies the north bay
    assert (free.pose.position.x, free.pose.position.y) == pytest.approx(((x0 + x1) / 2, (y0 + y1) / 2))
    assert free.color.g > 0.5 and free.color.r < 0.5
    assert occupied.color.r > 0.5 and occupied.color.g < 0.5
    (px0, px1), _ = co.parallel_bay()
    [parallel] = by_ns(mk.course_markers(Course.from_layout("P1"), DEPTH_M))["referee_bays"]
    assert parallel.pose.position.x == pytest.approx((px0 + px1) / 2)


def test_each_event_is_a_dot_and_a_label_where_it_happened():
    # Over the west line of the straight (line touch), then leaving the road: disqualified.
    poses = line([(EAST_LANE_X, -0.33), (EAST_LANE_X, 0.5)]) + straight(tg.X_REF - tg.ROAD_HALF_WIDTH, 0.5, 1.0)
    poses += straight(tg.X_REF - tg.ROAD_HALF_WIDTH - 0.6, 1.0, 1.5)
    referee, report = judge("D1", poses)
    ms = by_ns(mk.event_markers(referee.events))
    assert [m.text for m in ms["referee_event_labels"]] == ["1 line_touch -10", "2 leave_road -20"]
    for dot, label, event in zip(ms["referee_events"], ms["referee_event_labels"], referee.events):
        assert dot.id == label.id == event.n
        assert (dot.pose.position.x, dot.pose.position.y) == (event.x_m, event.y_m)
        assert dot.color.r == 1.0 and dot.color.g < 0.5  # a penalty: red
    assert mk.score_text(report) == "D1 score 0.0 | penalties 30 | 0 laps | left the road"


def test_score_while_running_and_the_whole_array():
    referee, _ = judge("D1", line([(EAST_LANE_X, -0.33), (EAST_LANE_X, 0.5)]))
    referee.over = None  # as seen during the run, before finish()
    report = referee.report(1.0)
    assert mk.score_text(report) == "D1 score 0.0 | penalties 0 | 0 laps | running"
    ms = mk.all_markers(referee.course, DEPTH_M, referee.events, report)
    assert ms[-1].ns == "referee_score" and ms[-1].type == Marker.TEXT_VIEW_FACING
    assert {m.header.frame_id for m in ms} == {"world"}
