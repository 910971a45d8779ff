"""LapCounter: laps of crossings_per_lap crossings, timed from the first motion."""
import pytest

from conde_decision.lap_counter import LapCounter


def test_laps_and_times():
    laps = LapCounter(crossings_per_lap=2)
    laps.on_motion(10.0)
    laps.on_motion(11.0)  # only the first motion starts the lap
    assert laps.on_crossing(50.0) is False and laps.crossings == 1 and laps.laps == 0
    assert laps.on_crossing(90.0) is True and laps.laps == 1
    assert not laps.on_crossing(130.0)
    assert laps.on_crossing(175.5)
    assert laps.lap_times_s == pytest.approx([80.0, 85.5]) and laps.crossings == 4


def test_a_lap_without_motion_takes_no_time():
    laps = LapCounter(crossings_per_lap=1)
    assert laps.on_crossing(5.0) and laps.lap_times_s == [0.0]
