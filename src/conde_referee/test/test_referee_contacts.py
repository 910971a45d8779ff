"""Collisions from the simulator's contacts (Referee.on_contacts) instead of the geometric check."""
from referee_paths import FOOTPRINT, judge, kinds, laps

from conde_referee.course import Course
from conde_referee.referee import Referee, judge_recorded
from conde_referee.rules import load_rules


def d3_v1():
    return Referee(load_rules(), Course.from_layout("D3", "v1", 0), FOOTPRINT)


def test_without_contacts_the_check_is_geometric():
    _, report = judge("D3", laps("north_ccw", n=1), variant="v1")
    assert kinds(report) == ["collision", "collision"] and report["collision_source"] == "geometric"


def test_with_contacts_only_real_contacts_count():
    # The same route through both boxes' lanes: with a contacts topic that reports nothing, no
    # collision (in the simulator the robot would have pushed the boxes or stopped).
    referee = d3_v1()
    referee.on_contacts(0.0, [])
    poses = [(i * 0.1,) + tuple(p) for i, p in enumerate(laps("north_ccw", n=1))]
    report = judge_recorded(referee, poses, panel=[(0.0, "forward")])
    assert kinds(report) == [] and report["collision_source"] == "contacts"


def test_a_contact_is_one_collision_until_it_ends():
    referee = d3_v1()
    referee.on_contacts(0.0, [])
    referee.on_pose(0.0, 2.0, -3.0, 1.57)
    assert [e.kind for e in referee.on_contacts(0.1, ["obstacle_1"])] == ["collision"]
    assert referee.on_contacts(0.2, ["obstacle_1"]) == []  # still touching
    assert referee.on_contacts(0.3, []) == []
    assert referee.on_contacts(0.4, ["obstacle_1"]) == []  # within repeat_debounce_s (2 s)
    referee.on_contacts(3.0, [])
    events = referee.on_contacts(3.1, ["obstacle_1", "crate"])
    assert [(e.kind, e.detail) for e in events] == [("collision", "crate"), ("collision", "obstacle_1")]
    report = referee.finish()
    assert report["collision_source"] == "contacts" and report["penalty_total"] == 30
