"""The NAO walks (nao_walk through the joint-trajectory controller) on each engine: a 1 m walk at
80 % of the maximum speed in a fresh, stepped simulation completes without a fall, covers a
distance within a band, and a second fresh run gives exactly the same result (deterministic).
The 7-repeat campaign is `rosrun conde_humanoid walk_report`, not a test."""

import pytest

from conde_humanoid.walk_campaign import run_sequence
from conde_testing.ros_harness import workspace_env

ENGINES = ['ode', 'bullet']
SPEC = 'walk:1:0.8'


@pytest.fixture(scope='module', autouse=True)
def ros_env(monkeypatch_module):
    for key, value in workspace_env('conde_humanoid').items():
        monkeypatch_module.setenv(key, value)


@pytest.fixture(scope='module')
def monkeypatch_module():
    with pytest.MonkeyPatch.context() as mp:
        yield mp


@pytest.mark.parametrize('engine', ENGINES)
def test_one_metre_walk_at_80_percent_is_complete_and_deterministic(engine, tmp_path):
    runs = [run_sequence(engine, [SPEC], log_path=str(tmp_path / ('run%d.log' % i))) for i in range(2)]
    first, second = runs[0][0], runs[1][0]
    assert not first['fell'], first
    # Open loop, feet slipping: short of the goal, as in the seed (ODE 70-80 %), little drift.
    assert 0.6 <= first['x_m'] <= 1.05, first
    assert abs(first['y_m']) < 0.15, first
    assert first['sim_s'] > 10
    for key in ('x_m', 'y_m', 'turned_rad', 'fell', 'sim_s', 'final'):
        assert second[key] == first[key], key
