"""The referee with scripted paths: wrong direction inside the loops (not only at the start line),
overtaking an obstacle through the other lane is not one, and pushed objects are followed."""
import math

import numpy as np

from conde_worlds import challenge_objects as co
from conde_referee.referee import OBJECT_DISPLACED_M, OVERTAKE_M
from referee_paths import judge, kinds, laps


def swap_lanes(poses, loop, from_deg, to_deg):
    """The poses, with those in `loop` between the two loop angles moved to the other lane (the
    same heading: driving that lane the way of the original one)."""
    cx, cy = co.loop_centre(loop)
    out = []
    for x, y, yaw in poses:
        r = math.hypot(x - cx, y - cy)
        a = math.degrees(math.atan2((y - cy) if loop == "north" else (cy - y), x - cx)) % 360.0
        if abs(r - co.DIVIDER_R) < 0.5 and from_deg <= a <= to_deg:
            k = (2.0 * co.DIVIDER_R - r) / r
            x, y = cx + k * (x - cx), cy + k * (y - cy)
        out.append((x, y, yaw))
    return out


def test_wrong_lane_inside_a_loop_is_one_wrong_direction_each_way_round():
    for route, loop in (("north_ccw", "north"), ("north_cw", "south"), ("north_cw", "north")):
        _, report = judge("D1", swap_lanes(laps(route, n=1), loop, 60, 200))
        assert kinds(report) == ["wrong_direction"], (route, loop, report["events"])
        event = report["events"][0]
        assert event["penalty"] == 25 and event["detail"].startswith(loop + " loop"), event
        assert report["half_laps"] == 2  # the lap still counts


def test_two_stretches_against_the_traffic_are_two_events():
    path = swap_lanes(swap_lanes(laps("north_ccw", n=1), "north", 60, 120), "south", 60, 120)
    _, report = judge("D1", path)
    assert kinds(report) == ["wrong_direction", "wrong_direction"]
    assert [e["detail"].split()[0] for e in report["events"]] == ["north", "south"]


def test_overtaking_a_box_through_the_other_lane_is_allowed():
    # D3 v1 blocks the straight-on route's lanes (north loop at 150 deg, south loop at 180 deg):
    # driving past each box in the other lane collides with nothing and is not a wrong direction.
    obstacles = {o["loop"]: o["angle_deg"] for o in co_features("D3", "v1")["obstacles"]}
    margin = math.degrees((OVERTAKE_M - 0.3) / co.DIVIDER_R)
    path = laps("north_ccw", n=1)
    for loop, angle in obstacles.items():
        path = swap_lanes(path, loop, angle - margin, angle + margin)
    _, report = judge("D3", path, variant="v1")
    assert kinds(report) == [], report["events"]
    # Staying in the other lane well past the box is a wrong direction again.
    path = laps("north_ccw", n=1)
    for loop, angle in obstacles.items():
        path = swap_lanes(path, loop, angle - margin, min(250.0, angle + 3 * margin))
    assert "wrong_direction" in kinds(judge("D3", path, variant="v1")[1])


def co_features(challenge, variant):
    from conde_worlds.challenge_world import layout
    from conde_worlds.challenges import load_challenges
    return layout(load_challenges(), challenge, variant, 0)[3]


def test_a_pushed_box_is_reported_once_and_followed():
    referee, _ = judge("D3", laps("north_ccw", n=1)[:5], variant="v1")
    referee.over = None  # go on judging after judge()'s finish
    box = next(ob for ob in referee.course.obstacles if ob.name == "obstacle_1")
    assert box.dynamic
    # Pushed along its lane (u: the lane's direction there), nudged less than the threshold: nothing;
    # then 0.3 m and turned 20 deg, then 0.4 m.
    spec = co_features("D3", "v1")["obstacles"][0]
    _, _, heading = co.loop_point(spec["loop"], spec["angle_deg"], co.LANE_R[spec["lane"]])
    ux, uy = math.cos(heading), math.sin(heading)

    def along(d_m):
        return box.x_m + d_m * ux, box.y_m + d_m * uy

    assert referee.on_object_poses(10.0, {"obstacle_1": along(0.5 * OBJECT_DISPLACED_M) + (box.yaw_rad,),
                                          "someone_else": (0.0, 0.0, 0.0)}) == []
    events = referee.on_object_poses(11.0, {"obstacle_1": along(0.3) + (box.yaw_rad + 0.35,)})
    assert [(e.kind, e.penalty, e.detail) for e in events] == [("object_displaced", 0.0, "obstacle_1 pushed 0.30 m")]
    assert referee.on_object_poses(12.0, {"obstacle_1": along(0.4) + (box.yaw_rad,)}) == []  # once
    report = referee.report(12.0)
    assert report["objects_displaced_m"] == {"obstacle_1": 0.4}
    # The geometric collision check follows it: a robot over where it stood (0.4 m back, overlapping
    # its layout footprint) touches nothing, where it is now collides.
    polygon = referee.obstacle_polygons["obstacle_1"]
    assert np.allclose(polygon.mean(axis=0), along(0.4))
    assert referee.on_pose(13.0, *along(-0.4), heading) == []
    hit = referee.on_pose(14.0, *along(0.4), heading)
    assert [e.kind for e in hit] == ["collision"]
