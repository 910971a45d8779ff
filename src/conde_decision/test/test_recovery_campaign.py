"""recovery_campaign.py's 42 starts at the unit tests' narrow camera view (0.35 rad): the robot is back
on its lane from every start it saw within recovery_max_offset_m of the lane's centre (before the
rejoin's heading bound: 13 of 42), and neither the creep ahead nor the rejoin takes it more than a few
cm beyond that bound."""

from recovery_campaign import SEEN_M, campaign
from test_decision_logic import CONFIG


def test_back_on_the_lane_from_every_start_within_the_creep_bound():
    results = campaign(0.35)
    assert len(results) == 42
    within = [r for r in results if r.seen_m < CONFIG.recovery_max_offset_m]
    assert len(within) == 42 - 7 and max(SEEN_M) == CONFIG.recovery_max_offset_m
    assert [r for r in within if not r.back_on_lane] == []
    assert sum(r.back_on_lane for r in results) >= 34
    assert max(r.max_offset_m for r in results) <= CONFIG.recovery_max_offset_m + 0.03
