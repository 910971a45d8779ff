"""challenge.launch with output_dir (the tournament's jobs): the generator runs once, for the world,
and the schedule and summary parameters name the files it wrote there (roslaunch --dump-params
reads the launch files and runs their commands; no node starts). conde_tournament team_run.launch
hands its control_config to conde_control."""
import os
import subprocess

import yaml


def test_schedule_and_summary_are_the_generated_files(tmp_path):
    out_dir = tmp_path / "job" / "challenge"
    env = dict(os.environ, ROS_HOME=str(tmp_path / "ros"))
    done = subprocess.run(["roslaunch", "--dump-params", "conde_bringup", "challenge.launch", "challenge:=P1",
                           "output_dir:=" + str(out_dir)], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    params = yaml.safe_load(done.stdout)
    assert params["/conde_sim/world_file"] == str(out_dir / "world.yaml")
    assert params["/signalling_panel_controller/schedule"] == str(out_dir / "schedule.yaml")
    assert params["/challenge/summary_file"] == str(out_dir / "challenge.yaml")
    summary = yaml.safe_load((out_dir / "challenge.yaml").read_text())
    assert summary["challenge"] == "P1" and summary["schedule_file"] == str(out_dir / "schedule.yaml")
    assert yaml.safe_load((out_dir / "schedule.yaml").read_text())["steps"]
    assert not (tmp_path / "ros" / "conde_challenges").exists()  # nothing generated elsewhere


def test_team_run_passes_the_control_gains_file(tmp_path):
    # conde_tournament team_run.launch control_config:= reaches conde_control's ~config; the default
    # is conde_control's own file.
    env = dict(os.environ, ROS_HOME=str(tmp_path / "ros"))
    gains = tmp_path / "gains.yaml"
    configs = []
    for extra in ([], ["control_config:=%s" % gains]):
        done = subprocess.run(["roslaunch", "--dump-params", "conde_tournament", "team_run.launch", "challenge:=P1",
                               "output_dir:=" + str(tmp_path / "job")] + extra,
                              env=env, capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
        configs.append(yaml.safe_load(done.stdout)["/conde_control/config"])
    assert configs[0].endswith("/conde_control/config/control.yaml") and os.path.isfile(configs[0])
    assert configs[1] == str(gains)
