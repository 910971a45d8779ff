"""Lap timing and lane keeping of the autonomous-run evaluation, on paths built from the track
geometry itself."""
import math

import numpy as np
import pytest

from conde_eval import run_evaluation
from conde_worlds import track_geometry as tg


@pytest.fixture(scope="module")
def lane():
    centres = tg.build_track().lane_centres(spacing=0.05)["north_ccw"]
    return centres["xy"]


def drive(timer, xy, speed_mps=0.5, t0_s=0.0):
    t = t0_s
    timer.feed(t, xy[0][0], xy[0][1])
    for a, b in zip(xy, xy[1:]):
        t += math.hypot(*(b - a)) / speed_mps
        timer.feed(t, b[0], b[1])
    return t


def test_two_laps_of_the_lane_centre_are_two_laps_of_the_route_length(lane):
    start = np.array([[2.169, -0.33]])
    path = np.vstack([start, lane, lane, lane[:10]])  # the route starts at y = 0 going north
    # Laps: from the first motion to the line 0.21 m before the crosswalk, then line to line.
    timer = run_evaluation.LapTimer()
    drive(timer, path)
    route_length_m = tg.build_track().lane_centres()["north_ccw"]["length"]
    assert len(timer.laps_s) == 2
    for lap in timer.laps_s:
        assert lap == pytest.approx(route_length_m / 0.5, rel=0.01)
    assert timer.motion_start_s == 0.0 and len(timer.crossings_s) == 2
    assert timer.top_speed_mps == pytest.approx(0.5, rel=1e-6)


def test_southbound_crossings_are_not_laps(lane):
    timer = run_evaluation.LapTimer()
    drive(timer, np.array([[1.387, 1.0], [1.387, -1.0]]))  # west lane, southbound
    drive(timer, np.array([[1.387, -1.0], [1.387, 1.0]]))  # northbound, but in the west lane
    assert timer.crossings_s == []


def test_the_lane_centre_stays_in_its_lane(lane):
    result = run_evaluation.lane_keeping(lane)
    assert result["stayed_in_lane"]
    assert result["max_offset_m"] < 0.005
    assert result["off_road_points"] == 0


def test_a_path_beside_the_road_leaves_its_lane(lane):
    beside = lane.copy()
    beside[100:120, 0] += 1.5  # a detour off the road
    result = run_evaluation.lane_keeping(beside)
    assert not result["stayed_in_lane"]
    assert result["max_offset_m"] > run_evaluation.LANE_HALF_WIDTH_M
    assert result["in_lane_fraction"] < 1.0


def test_plot_is_written(tmp_path, lane):
    texture = tmp_path / "t.png"
    import matplotlib.pyplot as plt
    plt.imsave(texture, np.zeros((20, 10, 3)))
    out = tmp_path / "path.png"
    run_evaluation.plot_path(lane, str(texture), (-3.475, 3.975, -8.35, 8.35), str(out), "test")
    assert out.stat().st_size > 1000


def timed_path(pieces, rate_hz=50.0):
    """Samples (t, x, y) at rate_hz along pieces of (duration_s, vx_mps, vy_mps) from (1.387, 3.0)."""
    samples, t, x, y = [(0.0, 1.387, 3.0)], 0.0, 1.387, 3.0
    for duration_s, vx, vy in pieces:
        for _ in range(int(round(duration_s * rate_hz))):
            t, x, y = t + 1.0 / rate_hz, x + vx / rate_hz, y + vy / rate_hz
            samples.append((t, x, y))
    return samples


def test_a_stop_between_two_drives_is_one_standstill_where_and_when_it_happened():
    # Southbound at 0.5 m/s for 5.5 s (2.75 m), 10 s standing, on again.
    samples = timed_path([(5.5, 0.0, -0.5), (10.0, 0.0, 0.0), (4.0, 0.0, -0.5)])
    found = run_evaluation.standstills(samples)
    assert len(found) == 1
    stop = found[0]
    assert stop.start_s == pytest.approx(5.5) and stop.end_s == pytest.approx(15.5)
    assert stop.duration_s == pytest.approx(10.0)
    assert (stop.x_m, stop.y_m) == pytest.approx((1.387, 0.25))
    assert stop.drift_m == pytest.approx(0.0, abs=1e-9)


def test_standing_at_the_start_and_at_the_end_are_standstills():
    found = run_evaluation.standstills(timed_path([(3.0, 0.0, 0.0), (2.0, 0.5, 0.0), (2.0, 0.0, 0.0)]))
    assert [(s.start_s, s.end_s) for s in found] == [pytest.approx((0.0, 3.0)), pytest.approx((5.0, 7.0))]
    assert found[1].x_m == pytest.approx(1.387 + 1.0)


def test_pauses_shorter_than_the_minimum_duration_are_not_standstills():
    samples = timed_path([(2.0, 0.0, -0.5), (0.8, 0.0, 0.0), (2.0, 0.0, -0.5)])
    assert run_evaluation.standstills(samples, min_duration_s=1.0) == []
    assert len(run_evaluation.standstills(samples, min_duration_s=0.5)) == 1


def test_creeping_faster_than_the_threshold_is_not_standing_but_jitter_below_it_is():
    creep = timed_path([(5.0, 0.0, -2.0 * run_evaluation.STANDSTILL_SPEED_MPS)])
    assert run_evaluation.standstills(creep) == []
    rng = np.random.default_rng(1)
    jitter = [(t, x + rng.uniform(-2e-5, 2e-5), y + rng.uniform(-2e-5, 2e-5))
              for t, x, y in timed_path([(5.0, 0.0, 0.0)])]  # at most 0.004 m/s at 50 Hz
    found = run_evaluation.standstills(jitter)
    assert len(found) == 1 and found[0].duration_s == pytest.approx(5.0)
    assert 0.0 < found[0].drift_m < 5e-5


def test_repeated_times_are_skipped_and_unsorted_samples_are_refused():
    samples = timed_path([(1.0, 0.0, -0.5), (3.0, 0.0, 0.0), (1.0, 0.0, -0.5)])
    doubled = sorted(samples + samples[::7])  # some samples twice, same time and place
    assert run_evaluation.standstills(doubled) == run_evaluation.standstills(samples)
    with pytest.raises(ValueError, match="sorted by time"):
        run_evaluation.standstills(samples[::-1])
    assert run_evaluation.standstills([]) == []
    assert run_evaluation.standstills(samples[:1]) == []
