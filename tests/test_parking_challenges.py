"""Acceptance test, end to end on each engine: P2 (parallel parking between two boxes) and B2
(bay parking beside the occupied bay) with the whole Conde stack in lock-step, as fast as the
nodes answer, judged by the referee: parked in the free place with zero penalties.  The place is
not given: conde_decision's parking_place is left at auto, the place the cameras show (the
parallel bay beyond the crosswalk where P2 starts, the free one of the bays ahead in B2).

conde_eval's parking_challenge.launch runs challenge.launch (world, panel schedule `park`, referee)
with semaphore, tracking, decision and control; the run ends when the referee writes its report
(parked, failed, disqualified) or at max_sim_time (then the referee writes it at shutdown)."""
import json
import os
import subprocess
import time

import pytest
from conde_testing.ros_harness import free_port, run_digest, stop_process

ENGINES = ["ode", "bullet"]
#: (challenge, variant, the place the referee must find it in)
RUNS = [("P2", "v1", "parallel"), ("B2", "v1", "south")]  # B2 v1: the box is in the north bay
MAX_SIM_TIME_S = 60  # parked after ~22 s of simulated time
WALL_TIMEOUT_S = 400  # a slow, busy machine: ~1 min each when idle


def run_challenge(tmp_path, challenge, variant, engine):
    """Runs the challenge; returns (the referee's report, the launch log)."""
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_HOME=str(tmp_path / "ros_home"),
               ROS_IP="127.0.0.1")
    out_dir = tmp_path / "out"
    log_path = tmp_path / "launch.log"
    report_path = out_dir / "referee.json"
    with open(log_path, "w") as log:
        launch = subprocess.Popen(
            ["roslaunch", "-p", str(port), "conde_eval", "parking_challenge.launch", "challenge:=" + challenge,
             "variant:=" + variant, "physics_engine:=" + engine,
             "max_sim_time:=%d" % MAX_SIM_TIME_S, "output_dir:=" + str(out_dir)],
            env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            deadline = time.monotonic() + WALL_TIMEOUT_S
            while not report_path.exists() and launch.poll() is None and time.monotonic() < deadline:
                time.sleep(1.0)  # waiting for another process's result, not for the simulation
            time.sleep(1.0)  # the report file is written in one go; let it be closed
        finally:
            stop_process(launch, group=True)
    log_text = log_path.read_text()
    assert report_path.exists(), "no referee report within %d s:\n%s" % (WALL_TIMEOUT_S, log_text[-4000:])
    return json.loads(report_path.read_text()), log_text


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("challenge, variant, bay", RUNS, ids=[r[0] for r in RUNS])
def test_parking_challenge_passes_without_penalty(tmp_path, challenge, variant, bay, engine):
    report, log = run_challenge(tmp_path, challenge, variant, engine)
    events = [(e["kind"], e["t_s"], e["penalty"], e["detail"]) for e in report["events"]]
    print("%s %s %s: end %s, parked %s, penalties %g, events %s" % (
        challenge, variant, engine, report["end"], report["parked"], report["penalty_total"], events))
    assert report["end"] == "parked" and report["parked"] == bay, (events, log[-3000:])
    assert report["penalty_total"] == 0.0 and not report["disqualified"], (events, run_digest(log))
