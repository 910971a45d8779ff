"""Acceptance test, end to end on each engine: a stop signal shown while the robot approaches the
crosswalk makes it stop before the crosswalk, and it goes on when the go signal returns.

conde_eval/autonomous_run drives one lap with the whole stack (simulator, signalling panels,
semaphore, tracking, decision, control) playing schedules/stop_and_go.yaml: "stop" is shown
while the robot drives the north loop, so it meets it on its way south toward the crosswalk in
the west lane; "forward" returns while it stands there.  The run's bag holds the ground truth
(/ground_truth/odom), the panel's signal as shown (/signalling_panel/signal) and the decision
state; the verdict comes from the ground truth.  Run with /usr/bin/python3 -m pytest -s to see
the measured stop."""
import os
import subprocess

import pytest
import rosbag
import rospkg
from conde_msgs.msg import PanelSignal

from conde_eval import run_evaluation
from conde_worlds import track_geometry as tg

ENGINES = ["ode", "bullet"]
CROSSWALK_SOUTH_EDGE_Y_M, CROSSWALK_NORTH_EDGE_Y_M = tg.CROSSWALK_Y  # -0.340, 0.252
WEST_LANE_X_M = tg.X_REF - tg.LANE_OFFSET  # 1.387, the southbound lane of the central straight
#: The stop spot: before the crosswalk's near edge (southbound: its north edge), at most this far.
MAX_STOP_BEFORE_EDGE_M = 0.35
#: The robot stands for at least this share of the time from reaching the stop to the go signal.
MIN_STANDING_SHARE = 0.8
#: A standing robot moves less than this [m] (it does creep slowly in the simulator).
MAX_STANDING_DRIFT_M = 0.05
#: After the go signal it moves off within this [s, sim] (the semaphore must see the panel first)
#: and is past the crosswalk within this [s, sim].
MAX_START_DELAY_S = 5.0
MAX_CROSSING_DELAY_S = 15.0


def read_run(bag_path):
    """From the run's bag: ground truth [(t_s, x_m, y_m)], panel changes [(t_s, code)] and
    decision-state changes [(t_s, name)], by header stamp (simulated time)."""
    samples, panel, states = [], [], []
    with rosbag.Bag(bag_path) as bag:
        for topic, msg, _ in bag.read_messages(
                topics=["/ground_truth/odom", "/signalling_panel/signal", "/conde_decision/state"]):
            t_s = msg.header.stamp.to_sec()
            if topic == "/ground_truth/odom":
                samples.append((t_s, msg.pose.pose.position.x, msg.pose.pose.position.y))
            elif topic == "/signalling_panel/signal":
                if not panel or panel[-1][1] != msg.signal:
                    panel.append((t_s, msg.signal))
            elif not states or states[-1][1] != msg.state:
                states.append((t_s, msg.state))
    return sorted(samples), panel, states


def first_after(changes, t_s, value):
    """Time of the first change to `value` at or after t_s, or None."""
    return next((t for t, v in changes if t >= t_s and v == value), None)


@pytest.mark.parametrize("engine", ENGINES)
def test_stop_before_the_crosswalk_and_go_on(engine, tmp_path):
    schedule = os.path.join(rospkg.RosPack().get_path("conde_eval"), "schedules", "stop_and_go.yaml")
    run = subprocess.run(["rosrun", "conde_eval", "autonomous_run", "--engine", engine, "--schedule", schedule,
                          "--laps", "1", "--sim-time-limit", "180",
                          "--output-dir", str(tmp_path)], capture_output=True, text=True, timeout=1800)
    out = run.stdout + run.stderr
    assert run.returncode == 0 and "RESULT: PASS" in out, out[-4000:]

    samples, panel, states = read_run(str(tmp_path / f"autonomous_run_{engine}.bag"))
    # The panel: stop at the start, forward, then the stop under test and forward again.
    start_go_s = first_after(panel, 0.0, PanelSignal.FORWARD)
    assert start_go_s is not None, panel
    stop_shown_s = first_after(panel, start_go_s, PanelSignal.STOP)
    assert stop_shown_s is not None, panel
    go_shown_s = first_after(panel, stop_shown_s, PanelSignal.FORWARD)
    assert go_shown_s is not None, panel
    # The stack reached its stop before the go signal (the decision node says so; the ground truth
    # below says whether it is true).
    reached_s = first_after(states, stop_shown_s, "stopped")
    assert reached_s is not None and reached_s < go_shown_s, states

    # It stood still for most of the time from reaching the stop to the go signal ...
    stops = run_evaluation.standstills(samples)

    def overlap_s(stop):
        return max(0.0, min(stop.end_s, go_shown_s) - max(stop.start_s, reached_s))

    stop = max(stops, key=overlap_s, default=None)
    assert stop is not None and overlap_s(stop) >= MIN_STANDING_SHARE * (go_shown_s - reached_s), (stops, reached_s)
    before_edge_m = stop.y_m - CROSSWALK_NORTH_EDGE_Y_M
    print(f"\n[{engine}] stop shown {stop_shown_s:.1f} s, reached (decision) {reached_s:.1f} s, go shown "
          f"{go_shown_s:.1f} s; stood {stop.start_s:.1f} .. {stop.end_s:.1f} s ({stop.duration_s:.1f} s) at "
          f"x {stop.x_m:.3f} m, y {stop.y_m:.3f} m = {before_edge_m * 100:.1f} cm before the crosswalk, "
          f"drift {stop.drift_m * 100:.1f} cm")
    assert stop.drift_m < MAX_STANDING_DRIFT_M, stop
    # ... in the west lane, just before the crosswalk ...
    assert 0.0 < before_edge_m < MAX_STOP_BEFORE_EDGE_M, stop
    assert abs(stop.x_m - WEST_LANE_X_M) < run_evaluation.LANE_HALF_WIDTH_M, stop
    # ... and never entered the crosswalk while the stop was shown.
    while_stop = [(t, x, y) for t, x, y in samples if stop_shown_s <= t <= go_shown_s]
    assert while_stop and min(y for _, _, y in while_stop) > CROSSWALK_NORTH_EDGE_Y_M, \
        min(while_stop, key=lambda s: s[2])

    # It went on when the go signal returned, not before, and drove over the crosswalk.
    assert go_shown_s <= stop.end_s < go_shown_s + MAX_START_DELAY_S, (stop, go_shown_s)
    past_s = next((t for t, _, y in samples if t > go_shown_s and y < CROSSWALK_SOUTH_EDGE_Y_M), None)
    assert past_s is not None and past_s < go_shown_s + MAX_CROSSING_DELAY_S, (past_s, go_shown_s)
