"""CrosswalkTracker: reaching and leaving crosswalks, sightings and their re-arming."""
import pytest

from conde_decision.crosswalk import CrosswalkTracker


def make():
    return CrosswalkTracker(length_m=0.6, zone_m=0.15, rearm_m=1.0, start_to_near_edge_m=0.0)


def test_starts_at_a_crosswalk_and_leaves_it_past_the_far_edge():
    cw = make()
    assert cw.at_crosswalk and not cw.reached()
    cw.advance(0.5)
    assert not cw.left()
    cw.advance(0.15)
    assert cw.left() and not cw.at_crosswalk
    assert cw.since_left_m == pytest.approx(0.05) and cw.to_near_edge_m is None
    assert not cw.left()  # once


def test_sightings_are_ignored_until_rearmed():
    cw = make()
    cw.advance(0.6)
    assert cw.left()
    cw.on_sighting(True, 0.5)  # the stripes just driven over
    assert cw.to_near_edge_m is None
    cw.advance(1.0)
    cw.on_sighting(False, 0.5)
    assert cw.to_near_edge_m is None
    cw.on_sighting(True, float("nan"))
    assert cw.to_near_edge_m is None
    cw.on_sighting(True, 0.9)
    assert cw.to_near_edge_m == 0.9


def past_the_first_and_sighting_the_next(distance_m):
    """Off the start crosswalk, rearmed, and the next one sighted distance_m [m] ahead."""
    cw = make()
    cw.advance(0.6)
    cw.left()
    cw.advance(1.0)
    cw.on_sighting(True, distance_m)
    return cw


def test_reaches_the_next_crosswalk_within_the_zone():
    cw = past_the_first_and_sighting_the_next(0.5)
    cw.advance(0.3)
    assert not cw.reached()
    cw.advance(0.1)
    assert cw.reached() and cw.at_crosswalk
    assert not cw.reached()  # once
    cw.on_sighting(True, 2.0)  # at a crosswalk: sightings ignored
    assert cw.to_near_edge_m == pytest.approx(0.1)


def test_reaches_within_a_zone_given_for_this_step():
    cw = past_the_first_and_sighting_the_next(0.5)
    cw.advance(0.3)  # 0.2 m to go: beyond the tracker's zone, within 0.25
    assert not cw.reached(0.1) and not cw.at_crosswalk
    assert cw.reached(0.25) and cw.at_crosswalk
