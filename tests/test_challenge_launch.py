"""launch/challenge.launch (conde_bringup) as a user runs it: the generated world, the robot at the
challenge's start pose, the panel controller with the challenge's schedule and the referee, for
Conde and Major Alvega; a bad challenge stops roslaunch with the generator's message."""
import subprocess

import pytest
import yaml


def roslaunch(env, tmp_path, *args, timeout_s=120):
    env = dict(env, ROS_HOME=str(tmp_path))
    return subprocess.run(["roslaunch", "conde_bringup", "challenge.launch", *args], env=env, capture_output=True,
                          text=True, timeout=timeout_s)


@pytest.mark.parametrize("challenge,variant,seed,robot,engine", [
    ("D4", "v2", "3", "conde", "bullet"),
    ("B2", "v1", "0", "major_alvega", "ode"),
])
def test_challenge_launch_runs_the_world_with_the_robot_and_the_panel(master, tmp_path, challenge, variant, seed,
                                                                      robot, engine):
    out = roslaunch(master, tmp_path, "challenge:=" + challenge, "variant:=" + variant, "seed:=" + seed,
                    "robot:=" + robot, "physics_engine:=" + engine, "real_time_factor:=0", "max_sim_time:=2")
    log = out.stdout + out.stderr
    assert out.returncode == 0, log[-4000:]
    name = "challenge_%s_%s_seed%s" % (challenge, variant, seed)
    assert "conde_sim: world '%s'" % name in log and "engine %s" % engine in log, log[-4000:]
    assert "process[signalling_panel_controller" in log, log[-4000:]
    assert "process[conde_referee" in log, log[-4000:]
    assert "process has died" not in log, log[-4000:]  # the panel controller took the schedule
    if robot == "major_alvega":
        assert "process[ackermann_controller" in log, log[-4000:]
    out_dir = tmp_path / "conde_challenges" / ("%s_%s_seed%s_track0" % (challenge, variant, seed))
    summary = yaml.safe_load((out_dir / "challenge.yaml").read_text())
    assert summary["challenge"] == challenge and summary["seed"] == int(seed)
    world = yaml.safe_load((out_dir / "world.yaml").read_text())
    assert world["spawn"][robot] == summary["start"][robot]


def test_unknown_challenge_stops_roslaunch_with_the_message(master, tmp_path):
    out = roslaunch(master, tmp_path, "challenge:=D9")
    assert out.returncode != 0
    assert ("generate_challenge: challenges.yaml: unknown challenge 'D9' "
            "(expected one of: B1, B2, D1, D2, D3, D4, P1, P2, V1)") in out.stdout + out.stderr


def test_bad_seed_stops_roslaunch_with_the_message(master, tmp_path):
    out = roslaunch(master, tmp_path, "challenge:=D3", "seed:=-4")
    assert out.returncode != 0
    assert "generate_challenge: seed: expected an integer >= 0, got '-4'" in out.stdout + out.stderr


def test_unknown_variant_stops_roslaunch_with_the_message(master, tmp_path):
    out = roslaunch(master, tmp_path, "challenge:=D3", "variant:=v3")
    assert out.returncode != 0
    assert ("generate_challenge: challenges.yaml: challenges.D3: unknown variant 'v3' (expected one of: v1, v2)"
            in out.stdout + out.stderr)
