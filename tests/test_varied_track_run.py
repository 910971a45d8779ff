"""The Conde stack on varied tracks, in lock-step (conde_tournament team_run.launch: challenge.launch
with the referee). D1 with track_seed 3 (line widths, lane width, loop and fork radii, straight
length, dash pattern and an anisotropic stretch within the rules' +-5 %): the referee's report must
show two laps, the end of trial and no penalty: the lane is measured on the varied lines and the
junctions' right turns begin and end where the cameras see them, not at the nominal track's
distances. D3 on Bullet with track and placement seed 2, the first 36 s: the lane change round the
north loop's box and back without penalty."""
import json
import subprocess
import time

from conde_testing.ros_harness import run_digest, stop_process

# Seed 3 had one line touch in the south loop's second lap (a right turn's arc ended 13 cm inside the
# new lane, parallel to it, and the follower's swing back put the robot's rear over the corner line);
# the arc now ends on a confirmed lane, heading back toward its centre (conde_decision's arc_end.py).
TRACK_SEED = 3
# the run takes about 2 min of wall time alone (178 s simulated; 25 min at load 45 beside seven others);
# the simulator stops at 260 s anyway
WALL_LIMIT_S = 900
# D3 on Bullet, track and placement seed 2: the way back from the north loop's box turned the robot
# 1.1 rad off the lane, where the tracker's fits turned it round (outer line at 32.5 s, the box hit at
# 33.2 s; conde_decision's avoidance.py now does not take a fit off the odometry's heading). The way
# back ends at about 32.3 s; the run stops at 36 s simulated (about 30 s of wall time alone).
D3_SEED = 2
D3_SIM_LIMIT_S = 36


def read_report(path):
    """The referee's JSON report once it is complete, else None."""
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def run_challenge(master, tmp_path, challenge, args, sim_limit_s):
    """Runs team_run.launch for challenge with more launch args until the referee's report is written
    (at the end of trial or at sim_limit_s simulated); returns (report, output folder, launch log)."""
    out_dir = tmp_path / challenge.lower()
    env = dict(master, ROS_HOME=str(tmp_path))
    log_path = tmp_path / "launch.log"
    with open(log_path, "w") as log:
        launch = subprocess.Popen(["roslaunch", "conde_tournament", "team_run.launch", f"challenge:={challenge}",
                                   f"output_dir:={out_dir}", f"max_sim_time:={sim_limit_s}"] + args,
                                  env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    report = None
    try:
        deadline = time.monotonic() + WALL_LIMIT_S
        while report is None and launch.poll() is None and time.monotonic() < deadline:
            time.sleep(1.0)  # the run goes as fast as lock-step lets it; this only polls for its end
            report = read_report(out_dir / "referee.json")
    finally:
        stop_process(launch, timeout_s=60, group=True)
    log_text = log_path.read_text()
    assert report is not None, "no referee report:\n" + log_text[-4000:]
    return report, out_dir, log_text


def test_d1_on_a_varied_track_without_penalty(master, tmp_path):
    report, out_dir, log_text = run_challenge(master, tmp_path, "D1",
                                              [f"track_seed:={TRACK_SEED}", "physics_engine:=ode"], 260)
    summary = (out_dir / "challenge.yaml").read_text()
    assert f"track_seed: {TRACK_SEED}" in summary
    details = (out_dir / "referee.md").read_text() + "\n" + run_digest(log_text)
    assert report["laps"] == 2 and report["end"] == "end of trial", details
    assert report["penalty_total"] == 0, details
    for turn in ("merge_right", "fork_right"):  # the junctions' right turns, ended from the cameras
        assert f"--{turn}--> turn_right" in log_text and "turn_right --lane_aligned--> " in log_text, log_text[-4000:]


def test_d3_bullet_lane_change_on_a_varied_track_without_penalty(master, tmp_path):
    report, out_dir, log_text = run_challenge(
        master, tmp_path, "D3", [f"track_seed:={D3_SEED}", f"placement_seed:={D3_SEED}", "physics_engine:=bullet"],
        D3_SIM_LIMIT_S)
    assert f"track_seed: {D3_SEED}" in (out_dir / "challenge.yaml").read_text()
    details = (out_dir / "referee.md").read_text() + "\n" + run_digest(log_text)
    assert report["penalty_total"] == 0, details
    for transition in ("follow_lane --obstacle_ahead--> avoid_change_lane",
                       "avoid_pass --obstacle_passed--> avoid_return", "avoid_return --lane_returned--> follow_lane"):
        assert transition in log_text, details + log_text[-4000:]
