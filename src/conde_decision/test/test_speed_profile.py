"""SpeedProfile: targets of the speed commands, the crosswalk stop and the ramp."""
import math

import pytest

from conde_decision.speed_profile import SpeedProfile

DT_S = 0.1


def make():
    return SpeedProfile(cruise_speed_mps=0.5, ramp_mps2=1.0, brake_decel_mps2=0.5, stop_margin_m=0.1)


def test_ramps_to_cruise_and_back_to_stop():
    profile = make()
    speeds = [profile.step("cruise", None, DT_S) for _ in range(7)]
    assert speeds == pytest.approx([0.1, 0.2, 0.3, 0.4, 0.5, 0.5, 0.5])
    assert profile.step("stop", None, DT_S) == pytest.approx(0.4)
    assert profile.step("cruise", None, DT_S, hold=True) == pytest.approx(0.3)
    assert profile.v_mps == pytest.approx(0.3)


def test_stop_at_crosswalk_brakes_to_stand_before_the_margin():
    profile = make()
    assert profile.target_mps("stop_at_crosswalk", None) == 0.5  # no crosswalk known
    assert profile.target_mps("stop_at_crosswalk", 2.0) == 0.5  # far: cruise
    assert profile.target_mps("stop_at_crosswalk", 0.2) == pytest.approx(math.sqrt(2 * 0.5 * 0.1))
    profile.step("stop_at_crosswalk", 0.2, DT_S)  # driving by it commits to the crosswalk
    assert profile.stop_latched
    assert profile.target_mps("stop_at_crosswalk", 0.05) == 0.0
    assert profile.target_mps("stop_at_crosswalk", -0.05) == 0.0  # latched: overshoot still stops


def test_asking_for_the_target_does_not_commit_to_the_crosswalk():
    """target_mps is a query (the lane recovery asks whether the state wants to move): only a step
    that drives by the command latches.  Before, the query latched, so a lost lane (the only time
    the recovery asks) committed to the crosswalk where the plain hold does not."""
    profile = make()
    assert profile.target_mps("stop_at_crosswalk", 0.3) == pytest.approx(math.sqrt(2 * 0.5 * 0.2))
    assert profile.target_mps("stop_at_finish", 0.3) == pytest.approx(math.sqrt(2 * 0.5 * 0.2))
    assert not profile.stop_latched
    assert profile.target_mps("stop_at_crosswalk", -0.05) == 0.5  # not committed: drives on to the next one


def test_a_capped_step_drives_by_the_command_and_commits():
    profile = make()
    speeds = [profile.step("stop_at_crosswalk", 2.0, DT_S, max_mps=0.15) for _ in range(3)]
    assert speeds == pytest.approx([0.1, 0.15, 0.15])  # the command's cruise, capped
    assert profile.stop_latched
    assert profile.step("stop_at_crosswalk", -0.05, DT_S, max_mps=0.15) == pytest.approx(0.05)  # committed: stops
    assert make().step("cruise", None, DT_S, max_mps=0.15, target_mps=-0.15) == pytest.approx(-0.1)  # target wins


def test_stop_at_finish_brakes_to_stand_before_the_finish_margin():
    profile = SpeedProfile(cruise_speed_mps=0.5, ramp_mps2=1.0, brake_decel_mps2=0.5, stop_margin_m=0.8,
                           finish_margin_m=0.25)
    assert profile.target_mps("stop_at_finish", 0.35) == pytest.approx(math.sqrt(2 * 0.5 * 0.1))
    assert profile.target_mps("stop_at_crosswalk", 0.35) == 0.0  # the stop margin: already there
    assert profile.target_mps("stop_at_finish", 0.25) == 0.0
    assert make().target_mps("stop_at_finish", 0.2) == pytest.approx(math.sqrt(2 * 0.5 * 0.1))  # default: stop_margin_m


def test_on_the_crosswalk_when_the_state_begins_drives_on_to_the_next():
    profile = make()
    assert profile.target_mps("stop_at_crosswalk", -0.05) == 0.5 and not profile.stop_latched
    profile.step("stop_at_crosswalk", -0.05, DT_S)
    assert not profile.stop_latched
    profile.step("stop_at_crosswalk", 0.3, DT_S)
    assert profile.stop_latched
    profile.unlatch()
    assert profile.target_mps("stop_at_crosswalk", -0.05) == 0.5


def test_hold_does_not_commit_to_a_crosswalk():
    profile = make()
    profile.step("stop_at_crosswalk", 0.3, DT_S, hold=True)
    assert not profile.stop_latched and profile.v_mps == 0.0


def test_the_decision_ramps_at_conde_controls_acceleration_limit():
    """The decision dead-reckons with its own copy of the ramp: it must be the limit that
    conde_control applies (its config/control.yaml and the default of ControlConfig)."""
    import os

    from conde_control.control_law import ControlConfig, load_config
    from conde_decision.decision_logic import DecisionConfig

    here = os.path.dirname(os.path.abspath(__file__))
    control_yaml = os.path.join(here, "..", "..", "conde_control", "config", "control.yaml")
    ramp_mps2 = DecisionConfig().speed_ramp_mps2
    assert ramp_mps2 == load_config(control_yaml).max_linear_accel_mps2
    assert ramp_mps2 == ControlConfig().max_linear_accel_mps2
