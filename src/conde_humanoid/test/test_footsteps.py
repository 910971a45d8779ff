"""Footstep plans (conde_humanoid/footsteps.py)."""

import math

import pytest

from conde_humanoid import footsteps as fs


def test_straight_plan_has_equal_steps_no_longer_than_asked_and_ends_alongside():
    steps = fs.plan_straight(1.0, 0.032, 0.1)
    assert len(steps) == 32 + 1
    assert [s.side for s in steps[:3]] == ['R', 'L', 'R']
    xs = [s.x_m for s in steps[:-1]]
    assert all(b - a == pytest.approx(1.0 / 32) for a, b in zip(xs, xs[1:]))
    last, before = steps[-1], steps[-2]
    assert last.side != before.side and last.x_m == pytest.approx(1.0) and before.x_m == pytest.approx(1.0)
    assert {round(s.y_m, 9) for s in steps} == {0.05, -0.05}


def test_backwards_is_negative_distance():
    steps = fs.plan_straight(-0.1, 0.04, 0.1)
    assert len(steps) == 4 and steps[-1].x_m == pytest.approx(-0.1)


@pytest.mark.parametrize('angle, first', [(math.pi / 2, 'L'), (-math.pi, 'R')])
def test_turn_opens_the_foot_on_the_side_of_the_turn_and_ends_at_the_angle(angle, first):
    steps = fs.plan_turn(angle, 0.16, 0.1)
    assert steps[0].side == first
    assert len(steps) == math.ceil(abs(angle) / 0.16) + 1
    yaws = [s.yaw_rad for s in steps]
    assert all(abs(b - a) <= 0.16 + 1e-12 for a, b in zip([0.0] + yaws, yaws))
    assert steps[-1].yaw_rad == steps[-2].yaw_rad == pytest.approx(angle)
    # the feet stay beside the body, which turns on the spot
    assert steps[-1].x_m + steps[-2].x_m == pytest.approx(0.0, abs=1e-12)


def test_zero_is_no_steps_and_bad_sizes_are_refused():
    assert fs.plan_straight(0.0, 0.04, 0.1) == []
    with pytest.raises(ValueError):
        fs.plan_turn(1.0, 0.0, 0.1)
