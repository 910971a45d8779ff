"""Every challenge world (conde_worlds' generator: each variant and a few random seeds) loads into
the simulator and runs a few simulated seconds on ODE and on Bullet with Conde standing still at
the start pose, then drives a short way; in V1 the signalling-panel camera sees the sign in front
of it; in D3 and D4 the ground (tracking) cameras see a box and a cone in front. D3 also runs on a
varied track (track seed 5): the robot stands at that track's start pose, in its east lane. One
process per engine loads the worlds in turn (challenge_world_checks.py), stepping a paused node."""

import math

import pytest
from conde_worlds import track_geometry as tg
from conde_worlds.challenge_objects import sign_order
from conde_worlds.track_variation import track_dimensions
from conde_worlds.traffic_signs import FAMILY, SIGNS
from conftest import run_checks


@pytest.mark.parametrize("engine", ["ode", "bullet"])
def test_every_challenge_world_loads_and_runs(conde_master, engine, tmp_path):
    lines = run_checks("challenge_world_checks.py", engine, tmp_path, conde_master, 360)
    results = [r for r in lines if "challenge" in r]
    views = {r["view"]: r for r in lines if "view" in r}
    # The ground cameras, 0.8 m before the box (0.6 m wide, 0.2 m tall) and the cone (0.23 m):
    # thousands of the box's green pixels, about a thousand of the cones' orange (the first cone
    # and the next ones of the row), none of the other colour.
    assert set(views) == {"D3", "D4"}, views
    assert views["D3"]["green_px"] > 2000 and views["D3"]["orange_px"] == 0, views["D3"]
    assert views["D4"]["orange_px"] > 400 and views["D4"]["green_px"] == 0, views["D4"]
    names = {(r["challenge"], r["variant"], r["seed"], r["track_seed"]) for r in results}
    assert {c for c, _, _, _ in names} == {"D1", "D2", "D3", "D4", "P1", "P2", "B1", "B2", "V1"}
    assert {("D3", "v1", 0, 0), ("D3", "v2", 0, 0), ("D4", "v1", 0, 0), ("D4", "v2", 0, 0), ("B2", "v1", 0, 0),
            ("B2", "v2", 0, 0), ("D3", "v1", 7, 0), ("V1", "v1", 5, 0), ("D3", "v1", 0, 5)} <= names
    for r in results:
        what = "%s %s seed %d track seed %d on %s: %s" % (
            r["challenge"], r["variant"], r["seed"], r["track_seed"], engine, r["node_output_tail"])
        assert r["node_alive"], what
        assert r["sim_time_s"] >= 2.0, what
        (x0, y0, z0), (x1, y1, z1) = r["start"], r["end"]
        # No command: the robot stays at its start pose, on the floor (objects do not push it).
        assert abs(x1 - x0) < 0.02 and abs(y1 - y0) < 0.02 and abs(z1 - z0) < 0.02, what
        if r["challenge"] != "V1":  # (V1 puts the robot before a sign)
            # It stands where the world file spawns it: on a varied track, that track's start pose.
            sx, sy = r["spawn"]["xyz"][:2]
            assert math.hypot(x0 - sx, y0 - sy) < 0.02, what
        if r["track_seed"]:
            track = tg.build_track(track_dimensions(r["track_seed"]))
            nominal = tg.build_track()
            at, at_nominal = track.locate([(x0, y0)]), nominal.locate([tg.SPAWNS["conde"][:2]])
            # In the varied east lane, heading north, as far from its centre as on the nominal track.
            assert at["heading"][0] == pytest.approx(math.pi / 2), what
            assert abs(at["lateral"][0] - at_nominal["lateral"][0]) < 0.02, what
            assert abs(x0 - tg.SPAWNS["conde"][0]) > 0.01, what  # (the varied lane is elsewhere)
        # Then it drives 0.3 m/s for 1.5 s: about 0.45 m (spin-up and the engines' differences).
        assert 0.25 < r["driven_m"] < 0.5, what
        if r["challenge"] == "V1":
            # The sign the seed put at position 0 fills about 40 x 40 px of the 320 x 240 image:
            # red for a danger triangle, blue for the others.
            sign = sign_order(SIGNS, r["seed"])[0]
            red, blue = r["sign_red_px"], r["sign_blue_px"]
            if FAMILY[sign] == "danger":
                assert red > 150 and blue < 50, (sign, what)
            else:
                assert blue > 150 and red < 50, (sign, what)
    v1_signs = {sign_order(SIGNS, r["seed"])[0] for r in results if r["challenge"] == "V1"}
    assert {FAMILY[s] for s in v1_signs} == {"danger", "mandatory"}  # seeds 0 and 5 show both colours
