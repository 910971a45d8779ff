"""Lap detection (conde_racing.lap_timing) on synthetic ground-truth paths, including the
racetrack's own lines driven along its centre line."""

import csv
import io
import math

import pytest

from conde_racing import racetrack as rt
from conde_racing.lap_timing import CSV_COLUMNS, Lap, LapCounter, Line, csv_text, summary_lines

FINISH = Line((0.0, -1.0), (0.0, 1.0))      # across the x axis at x = 0, forward = +x


def test_forward_and_backward_crossings():
    assert FINISH.crossing((-0.1, 0.0), (0.3, 0.0)) == (pytest.approx(0.25), 1)
    assert FINISH.crossing((0.3, 0.5), (-0.1, 0.5)) == (pytest.approx(0.75), -1)
    assert FINISH.crossing((-0.2, 0.0), (-0.1, 0.0)) is None     # not reached
    assert FINISH.crossing((-0.1, 1.5), (0.1, 1.5)) is None      # beside the line's left end
    assert FINISH.crossing((-0.1, -1.2), (0.1, -0.8)) == (pytest.approx(0.5), 1)  # through the right end
    # ending on the line counts, starting on it does not: one crossing for the two moves
    assert FINISH.crossing((-0.1, 0.0), (0.0, 0.0)) == (1.0, 1)
    assert FINISH.crossing((0.0, 0.0), (0.1, 0.0)) is None


def test_line_direction_follows_its_ends():
    reversed_line = Line((0.0, 1.0), (0.0, -1.0))  # right end at +y: forward is -x
    assert reversed_line.crossing((0.1, 0.0), (-0.1, 0.0))[1] == 1


@pytest.mark.parametrize("ends", [((0, 0), (0, 0)), ((0, math.nan), (1, 1)), ((0, 0, 0), (1, 1))])
def test_bad_lines_are_rejected(ends):
    with pytest.raises(ValueError):
        Line(*ends)


def drive(counter, points, t0=0.0, dt=0.02, speed=1.0):
    """Feeds points at a fixed period; returns the laps completed."""
    laps = []
    for k, (x, y) in enumerate(points):
        lap = counter.update(t0 + k * dt, x, y, speed if not callable(speed) else speed(k))
        if lap:
            laps.append(lap)
    return laps


def circle(n_laps, radius=2.0, samples_per_lap=200, start_angle=-math.pi / 2 - 0.1):
    """Counter-clockwise circle around (0, 2): crosses x = 0 at (0, 0) heading +x."""
    pts = []
    for k in range(int(n_laps * samples_per_lap) + 1):
        a = start_angle + 2 * math.pi * k / samples_per_lap
        pts.append((radius * math.cos(a), 2.0 + radius * math.sin(a)))
    return pts


def test_laps_on_a_circle_time_distance_and_speeds():
    counter = LapCounter("car0", FINISH)
    # 200 samples per lap at 0.02 s: a lap takes 4 s; the circle's circumference is 4 pi m
    speeds = lambda k: 1.0 + (0.5 if k == 100 else 0.0)  # noqa: E731  (one peak in lap 1)
    laps = drive(counter, circle(3.5), speed=speeds)
    assert [lap.number for lap in laps] == [1, 2, 3]
    for lap in laps:
        assert lap.time_s == pytest.approx(4.0, abs=1e-9)
        # the polygon of 200 chords is a little shorter than the circle
        assert lap.distance_m == pytest.approx(2 * 200 * 2.0 * math.sin(math.pi / 200), rel=1e-6)
        assert lap.average_speed_mps == pytest.approx(lap.distance_m / 4.0)
    # the first crossing is 0.1 rad after the start: 0.1 / (2 pi / 200) samples = 3.18 samples in
    assert laps[0].start_time_s == pytest.approx(0.02 * 0.1 / (2 * math.pi / 200), rel=1e-3)
    assert laps[0].top_speed_mps == 1.5 and laps[1].top_speed_mps == 1.0
    assert laps[1].start_time_s == laps[0].end_time_s
    assert counter.lap_in_progress and counter.abandoned == 0


def test_checkpoints_must_be_crossed_in_order():
    # A checkpoint across the top of the circle (x = 0, y = 3.5 .. 4.5), forward = -x there.
    top = Line((0.0, 4.5), (0.0, 3.5))
    counter = LapCounter("car0", FINISH, [top])
    assert len(drive(counter, circle(2.2))) == 2
    # A path that crosses the start line forward twice without going round (a wiggle back and
    # forth across the line, the backward crossing abandoning the lap) gives no lap.
    counter = LapCounter("car0", FINISH, [top])
    wiggle = [(-0.2, 0.0), (0.2, 0.0), (-0.2, 0.0), (0.2, 0.0), (0.4, 0.0)]
    assert drive(counter, wiggle) == [] and counter.abandoned == 1


def test_a_short_cut_that_misses_a_checkpoint_is_no_lap():
    top = Line((0.0, 4.5), (0.0, 3.5))
    counter = LapCounter("car0", FINISH, [top])
    # out of the line, a small loop that stays below the checkpoint, back over the line
    loop = [(-0.1, 0.0)] + [(1.0 * math.sin(a), 1.0 - math.cos(a)) for a in
                            [2 * math.pi * k / 100 for k in range(1, 101)]] + [(0.1, 0.0)]
    assert drive(counter, loop) == []
    assert counter.abandoned == 1 and counter.lap_in_progress  # the second crossing started a lap


def test_reset_jump_and_time_going_back_abandon_the_lap():
    counter = LapCounter("car0", FINISH, max_jump_m=0.5)
    pts = circle(0.6)
    drive(counter, pts)
    assert counter.lap_in_progress
    counter.update(100.0, -1.0, -1.0, 0.0)  # teleported back to the grid
    assert not counter.lap_in_progress and counter.abandoned == 1
    # time going backwards (a restarted simulation) abandons too
    counter.update(100.02, -0.1, 0.0, 1.0)
    counter.update(100.04, 0.1, 0.0, 1.0)
    assert counter.lap_in_progress
    counter.update(1.0, 0.2, 0.0, 1.0)
    assert not counter.lap_in_progress and counter.abandoned == 2


def test_non_finite_samples_are_ignored():
    counter = LapCounter("car0", FINISH)
    for t, x in ((0.0, -0.1), (0.02, math.nan), (0.04, 0.1)):
        counter.update(t, x, 0.0, 1.0)
    assert counter.lap_in_progress


def test_the_racetrack_lines_time_a_lap_along_the_centre_line():
    line = rt.CentreLine()
    start = Line(*line.line_across(rt.START_LINE_S_M))
    checkpoints = [Line(*line.line_across(s)) for s in rt.CHECKPOINT_S_M]
    counter = LapCounter("car3", start, checkpoints)
    # from the pole position, 2.5 laps at 2 m/s, 0.2 m left of the centre line, 50 Hz samples
    s0 = rt.grid_poses(line)[0].x_m
    speed, dt = 2.0, 0.02
    laps = []
    for k in range(int(2.5 * line.length_m / (speed * dt))):
        x, y = line.point_at(s0 + k * speed * dt, 0.2)
        lap = counter.update(k * dt, x, y, speed)
        if lap:
            laps.append(lap)
    assert len(laps) == 2
    # the path 0.2 m left of the centre is shorter by 0.2 m x the total turning (2 pi)
    expected_m = line.length_m - 0.2 * 2 * math.pi
    for lap in laps:
        assert lap.distance_m == pytest.approx(expected_m, rel=0.002)
        assert lap.time_s == pytest.approx(line.length_m / speed, rel=0.002)


def test_csv_and_summary():
    laps = [Lap("car0", 1, 1.0, 18.5, 30.0, 2.25), Lap("car1", 1, 1.5, 20.0, 29.5, 2.0)]
    rows = list(csv.reader(io.StringIO(csv_text(laps))))
    assert tuple(rows[0]) == CSV_COLUMNS
    assert rows[1] == ["car0", "1", "1.000", "18.500", "17.500", "30.000", "1.714", "2.250"]
    counter = LapCounter("car0", FINISH)
    counter.laps.extend(laps[:1])
    idle = LapCounter("car5", FINISH)
    table = summary_lines([counter, idle])
    assert table[1].split() == ["car0", "1", "17.500", "17.500", "2.25", "0"]
    assert table[2].split() == ["car5", "0", "-", "-", "-", "0"]
