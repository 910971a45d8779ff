"""The order the competition starts its challenges in: the long ones first."""
from conde_tournament.competition import CHALLENGES
from conde_tournament.competition_run import challenge_time_limits_s, start_order


def test_longest_first_equal_ones_as_given():
    limits = {"D1": 300, "D2": 300, "D4": 360, "P1": 120, "V1": 300}
    assert start_order(["D1", "D2", "D4", "P1", "V1"], limits) == ["D4", "D1", "D2", "V1", "P1"]
    assert start_order(["P1", "X9"], limits) == ["P1", "X9"]  # unknown: last


def test_the_competition_starts_the_driving_challenges_and_v1_before_parking():
    order = start_order(CHALLENGES, challenge_time_limits_s())
    assert sorted(order) == sorted(CHALLENGES)
    assert order.index("V1") < min(order.index(c) for c in ("P1", "P2", "B1", "B2"))
