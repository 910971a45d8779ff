"""The scoring library with scripted paths: each check fires once with its rules-file penalty."""
import json
import math

from conde_worlds import challenge_objects as co
from conde_worlds import track_geometry as tg
from conde_worlds.traffic_signs import SIGNS
from referee_paths import EAST_LANE_X, WEST_LANE_X, judge, kinds, laps, line, stand, straight

NORTH = math.pi / 2


def test_two_clean_laps_score_no_penalty():
    _, report = judge("D1", stand(EAST_LANE_X, -0.33, NORTH, 1.0) + laps(n=2), panel=[(0.0, "stop"), (1.0, "forward")])
    assert kinds(report) == ["laps_done"]
    assert report["penalty_total"] == 0 and report["laps"] == 2 and report["half_laps"] == 4
    # 4 half laps x 50 points + (4 x 35 s - T)
    assert abs(report["score"] - (200 + 140 - report["driving_time_s"])) < 1e-6


def test_the_branch_route_is_clean_too():
    _, report = judge("D1", laps("north_cw", n=1))
    assert kinds(report) == [] and report["half_laps"] == 2


def test_same_input_gives_the_same_report():
    a = judge("D3", laps(n=1), variant="v2")[1]
    b = judge("D3", laps(n=1), variant="v2")[1]
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


def test_false_start():
    _, report = judge("D1", straight(EAST_LANE_X, -0.33, -0.1), panel=[(0.0, "stop"), (5.0, "forward")])
    assert kinds(report) == ["false_start"] and report["penalty_total"] == 10


def test_line_touch_is_one_event():
    path = line([(EAST_LANE_X, -4.0), (EAST_LANE_X, -3.5), (2.45, -3.0), (2.45, -2.6), (EAST_LANE_X, -2.2),
                 (EAST_LANE_X, -1.5)])
    _, report = judge("D1", path)
    assert kinds(report) == ["line_touch"] and report["penalty_total"] == 10
    assert report["events"][0]["detail"].startswith("central_east")


def test_leaving_the_road_disqualifies():
    path = line([(EAST_LANE_X, -4.5), (EAST_LANE_X, -4.0), (4.0, -4.0), (EAST_LANE_X, -4.0)])
    _, report = judge("D1", path)
    assert kinds(report) == ["line_touch", "leave_road"]
    assert report["disqualified"] and report["score"] == 0 and report["end"] == "left the road"
    assert report["events"][1]["penalty"] == 20


def test_running_the_stop_signal():
    path = stand(EAST_LANE_X, -0.33, NORTH, 3.0) + straight(EAST_LANE_X, -0.33, 1.5)
    _, report = judge("D2", path, panel=[(0.0, "stop"), (1.0, "forward"), (2.0, "stop")])
    assert kinds(report) == ["stop_not_respected"] and report["penalty_total"] == 60


def test_stopping_outside_the_immobilisation_zone():
    path = straight(EAST_LANE_X, -4.0, -2.8) + stand(EAST_LANE_X, -2.8, NORTH, 2.0)
    _, report = judge("D2", path, panel=[(0.0, "forward"), (1.0, "stop")])
    assert kinds(report) == ["stopped_outside_zone"] and report["penalty_total"] == 10
    path = straight(EAST_LANE_X, -4.0, -0.6) + stand(EAST_LANE_X, -0.6, NORTH, 2.0)
    assert kinds(judge("D2", path, panel=[(0.0, "forward"), (1.0, "stop")])[1]) == []


def test_end_of_trial_ends_the_run():
    path = straight(EAST_LANE_X, -4.0, -0.5) + stand(EAST_LANE_X, -0.5, NORTH, 2.0) + straight(EAST_LANE_X, -0.5, 2.0)
    _, report = judge("D1", path, panel=[(0.0, "forward"), (1.0, "end_of_trial")])
    assert kinds(report) == ["trial_end"] and report["end"] == "end of trial"


def test_wrong_direction_on_the_start_line():
    _, report = judge("D1", straight(EAST_LANE_X, 0.0, -1.5))
    assert kinds(report) == ["wrong_direction"] and report["penalty_total"] == 25


def test_wrong_branch_after_a_left_order():
    # "left" at the crosswalk: the north fork opens to the left, so the branch (loop clockwise) is due.
    panel = [(0.0, "forward"), (0.05, "left")]
    _, report = judge("D2", laps("north_ccw", n=1), panel=panel)
    assert kinds(report) == ["wrong_branch"] and report["penalty_total"] == 25
    assert "order left: expected the branch at the north fork" == report["events"][0]["detail"]
    assert kinds(judge("D2", laps("north_cw", n=1), panel=panel)[1]) == []


def test_collisions_with_the_boxes():
    # D3 v1: a box in the north loop's outer lane and one in the south loop's inner lane, the lanes
    # that the straight-on route drives.
    _, report = judge("D3", laps("north_ccw", n=1), variant="v1")
    assert kinds(report) == ["collision", "collision"]
    assert [e["detail"] for e in report["events"]] == ["obstacle_1", "obstacle_2"]
    assert report["penalty_total"] == 20
    assert kinds(judge("D3", laps("north_cw", n=1), variant="v1")[1]) == []


def _bay_centre(bay):
    (x0, x1), (y0, y1) = co.parking_bays()[bay]
    return 0.5 * (x0 + x1), 0.5 * (y0 + y1)


def _park(x, y, stay_s=6.0):
    return (straight(EAST_LANE_X, -4.6, y) + line([(EAST_LANE_X, y), (x, y)])
            + stand(x, y, 0.0, stay_s))


def test_parking_in_the_free_bay():
    x, y = _bay_centre("south")
    _, report = judge("B2", _park(x, y), variant="v1", panel=[(0.0, "parking")])
    assert kinds(report) == ["parked"] and report["parked"] == "south" and report["score"] == 60


def test_parking_partly_outside_the_free_bay():
    _, y = _bay_centre("south")
    x = co.parking_bays()["south"][0][0] + 0.1  # the footprint's back sticks out over the west line
    _, report = judge("B2", _park(x, y), variant="v1", panel=[(0.0, "parking")])
    assert kinds(report) == ["parked_outside_bay"] and report["score"] == 0


def test_parking_in_the_occupied_bay_fails():
    x, y = _bay_centre("north")
    _, report = judge("B2", _park(x, y), variant="v1", panel=[(0.0, "parking")])
    assert kinds(report) == ["collision", "parked_in_occupied_bay"] and report["score"] == 0


def test_d2_parking_order_after_two_laps_parks_in_the_parallel_bay():
    """D2's parking order comes near the end of the second lap: the robot drives on past the
    crosswalk and parks in the parallel bay, which counts in a D challenge as well as the bays."""
    (x0, x1), (y0, y1) = co.parallel_bay()
    x, y = (x0 + x1) / 2, (y0 + y1) / 2
    path = laps(n=2) + line([(EAST_LANE_X, 0.0), (EAST_LANE_X, y - 0.6), (x, y)]) + stand(x, y, NORTH, 6.0)
    _, report = judge("D2", path, panel=[(0.0, "forward"), (150.0, "parking")])
    assert report["laps"] == 2 and report["parked"] == "parallel"
    assert "parked" in kinds(report) and report["penalty_total"] == 0


def test_touching_a_parking_line():
    x, y = _bay_centre("south")
    y = co.parking_bays()["south"][1][1] - 0.1  # the footprint's side on the dashed divider
    _, report = judge("B1", _park(x, y), panel=[(0.0, "parking")])
    assert kinds(report)[0] == "parking_line_touch" and report["events"][0]["penalty"] == 10


def test_v1_sign_reports_right_and_wrong():
    # Sign position 1 is (2.8, 5.0), position 7 (0.0, 4.0); seed 0 shows SIGNS in order.
    path = straight(EAST_LANE_X, 4.0, 4.5) + stand(EAST_LANE_X, 4.5, NORTH, 1.0) + line(
        [(EAST_LANE_X, 4.5), (WEST_LANE_X, 4.0)]) + stand(WEST_LANE_X, 4.0, NORTH, 1.0)
    wrong = SIGNS[0]
    _, report = judge("V1", path, reports=[(1.5, SIGNS[0]), (4.0, wrong)])
    assert kinds(report) == ["sign_right", "sign_wrong"]
    assert report["events"][1]["detail"] == "sign 7: reported %r, it shows %r" % (wrong, SIGNS[6])
    assert report["score"] == 10 - 5


def test_time_limit():
    _, report = judge("P1", stand(EAST_LANE_X, -0.33, NORTH, 125.0), panel=[(0.0, "parking")])
    assert kinds(report) == ["time_limit"] and report["end"] == "time limit"


def test_start_line_is_behind_the_start_pose():
    assert -0.33 > -0.55 > tg.CROSSWALK_Y[0] - 1.0


def test_report_files(tmp_path):
    from conde_referee.report import write_report

    referee, report = judge("D3", laps("north_ccw", n=1), variant="v1")
    paths = write_report(report, referee.path, referee.course, str(tmp_path))
    with open(paths["json"]) as f:
        data = json.load(f)
    assert [e["kind"] for e in data["events"]] == ["collision", "collision"] and len(data["path_t_x_y"]) > 100
    md = open(paths["md"]).read()
    assert "| 1 |" in md and "obstacle_1" in md and "| penalties | 20.0 |" in md
    import matplotlib.image as mpimg
    png = mpimg.imread(paths["png"])
    assert png.shape[0] > 1000 and (png[..., :3].mean(axis=2) < 0.1).mean() > 0.3  # the dark track texture


def test_the_report_names_the_track_seed():
    """A report and its plot title say which track was driven: "track seed N" on a varied track,
    nothing more on the nominal one (and on reports written before the field existed)."""
    from conde_referee.report import markdown, seeds_text

    _, report = judge("D1", laps(n=1))
    assert report["track_seed"] == 0 and seeds_text(report) == "seed 0"
    assert markdown(report).startswith("## Referee: D1 (seed 0)\n")
    assert seeds_text(dict(report, seed=2, track_seed=6)) == "seed 2, track seed 6"
    assert seeds_text({k: v for k, v in report.items() if k != "track_seed"}) == "seed 0"
