"""The campaign's specs and statistics (conde_humanoid/walk_campaign.py), without a simulation."""

import math

import pytest

from conde_humanoid.walk_campaign import campaign_specs, parse_spec, summarize


def test_the_seed_campaign_has_nine_walks_and_four_turns():
    specs = campaign_specs()
    assert len(specs) == 13
    assert 'walk:3:0.4' in specs and 'turn:-270:1' in specs and 'turn:360:1' in specs
    assert campaign_specs(quick=True) == ['walk:0.5:0.4', 'walk:0.5:0.8', 'walk:0.5:1', 'turn:90:1', 'turn:-180:1']


def test_specs_parse_to_metres_and_radians():
    spec = parse_spec('turn:-180:0.8')
    assert spec.angle_rad == pytest.approx(-math.pi) and spec.distance_m == 0 and spec.speed_fraction == 0.8
    assert parse_spec('walk:1:0.8').distance_m == 1.0


@pytest.mark.parametrize('text', ['walk:1', 'run:1:0.5', 'walk:one:0.5'])
def test_bad_specs_name_the_text(text):
    with pytest.raises(ValueError, match="bad trial spec '%s'" % text):
        parse_spec(text)


def trial(x, y=0.0, turned=0.0, fell=False):
    return dict(x_m=x, y_m=y, turned_rad=turned, fell=fell, sim_s=10.0, wall_s=5.0)


def test_summary_leaves_falls_out_of_the_spread():
    row = summarize('walk:1:0.8', [trial(0.8, 0.01), trial(0.9, 0.03), trial(0.1, fell=True)])
    assert row['n'] == 3 and row['falls'] == 1
    assert row['mean'] == pytest.approx(0.85) and row['span'] == pytest.approx(0.1)
    assert row['ratio'] == pytest.approx(0.85) and row['y_mean'] == pytest.approx(0.02)
    assert row['real_time_factor'] == pytest.approx(2.0)


def test_turn_summary_is_in_degrees_and_identical_repeats_have_no_spread():
    row = summarize('turn:90:1', [trial(0.0, turned=math.radians(80))] * 3)
    assert row['mean'] == pytest.approx(80) and row['sd'] == 0 and row['span'] == 0
