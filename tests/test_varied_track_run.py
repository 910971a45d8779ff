"""D1 on a varied track: the competition track drawn with track_seed 3 (line widths, lane width, loop
and fork radii, straight length, dash pattern and an anisotropic stretch within the rules' +-5 %),
driven by the whole Conde stack in lock-step (conde_tournament team_run.launch: challenge.launch
with the referee). The referee's report must show two laps, the end of trial and no penalty: the
lane is measured on the varied lines and the junctions' right turns begin and end where the
cameras see them, not at the nominal track's distances."""
import json
import subprocess
import time

from conde_testing.ros_harness import stop_process

# Seed 3 had one line touch in the south loop's second lap (a right turn's arc ended 13 cm inside the
# new lane, parallel to it, and the follower's swing back put the robot's rear over the corner line);
# the arc now ends on a confirmed lane, heading back toward its centre (conde_decision's arc_end.py).
TRACK_SEED = 3
# the run takes about 2 min of wall time alone (178 s simulated; 25 min at load 45 beside seven others);
# the simulator stops at 260 s anyway
WALL_LIMIT_S = 900


def read_report(path):
    """The referee's JSON report once it is complete, else None."""
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def test_d1_on_a_varied_track_without_penalty(master, tmp_path):
    out_dir = tmp_path / "d1"
    env = dict(master, ROS_HOME=str(tmp_path))
    log_path = tmp_path / "launch.log"
    with open(log_path, "w") as log:
        launch = subprocess.Popen(["roslaunch", "conde_tournament", "team_run.launch", "challenge:=D1",
                                   f"track_seed:={TRACK_SEED}", "physics_engine:=ode", f"output_dir:={out_dir}",
                                   "max_sim_time:=260"],
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
    summary = (out_dir / "challenge.yaml").read_text()
    assert f"track_seed: {TRACK_SEED}" in summary
    details = (out_dir / "referee.md").read_text()
    assert report["laps"] == 2 and report["end"] == "end of trial", details
    assert report["penalty_total"] == 0, details
    for turn in ("merge_right", "fork_right"):  # the junctions' right turns, ended from the cameras
        assert f"--{turn}--> turn_right" in log_text and "turn_right --lane_aligned--> " in log_text, log_text[-4000:]
