"""The tunnel of D4 is darker: the generated world gives it a light region, and the left tracking
camera of Conde standing under the roof sees the lane lines much darker than in the open part of
the same loop (tunnel_light_checks.py, a paused conde_sim node stepped on each engine)."""
import pytest

from conde_worlds.challenge_objects import TUNNEL_LIGHT
from conftest import run_checks


@pytest.mark.parametrize("engine", ["ode", "bullet"])
def test_tracking_camera_sees_the_tunnel_darker(conde_master, engine, tmp_path):
    results = {r["place"]: r for r in run_checks("tunnel_light_checks.py", engine, tmp_path, conde_master, 180)}
    print("brightness on %s: %s" % (engine, results))
    # In the open the white lines in front of the robot are white; under the roof every surface
    # the camera sees there lies in the light region: the lines are TUNNEL_LIGHT times as bright.
    open_road, tunnel = results["open_road"]["line_brightness"], results["inside_tunnel"]["line_brightness"]
    assert open_road > 240, results
    assert tunnel == pytest.approx(TUNNEL_LIGHT * open_road, abs=4.0), results
