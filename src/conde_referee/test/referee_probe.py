#!/usr/bin/env python3
"""The referee node against the simulator, stepped (no sleeping on simulated time): a D1 world
with Conde at the start pose, the panel played by this probe. Conde drives over the crosswalk
while "stop" is shown, is then put with /conde_sim/set_start_pose on the straight's west line,
and stands there when "end of trial" is shown. Prints one JSON line: the events the referee
published, its report, the report files and its last rviz markers.

Scenario moved_box (D3 v1): the north loop's box is moved 0.3 m with /gazebo/set_model_state while
the robot stands at its start; the referee follows it from /conde_sim/model_poses.

Scenario push (D3 v1): Conde drives into that box and pushes it (real contacts).

usage: referee_probe.py ENGINE OUTPUT_DIR [stop_run|moved_box|push]   (against the ROS master of the environment)
"""
import json
import math
import os
import subprocess
import sys

import rospy
from conde_msgs.msg import PanelSignal
from conde_msgs.srv import SetStartPose
from geometry_msgs.msg import Twist
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import MarkerArray

from conde_testing.ros_harness import stop_process
from conde_worlds import challenge_objects as co
from conde_worlds.challenge_world import layout, objects_of, write_challenge
from conde_worlds.challenges import load_challenges
from gazebo_msgs.msg import ModelState
from gazebo_msgs.srv import SetModelState

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "tests"))
from stepped_sim import SteppedSim, connected, send, wait_for  # noqa: E402

STEP_S = 0.001


def stop_run(stepped, show, events, cmd_pub):
    """D1: over the crosswalk while "stop" is shown, then on the west line, then end of trial."""
    show(PanelSignal.STOP)
    stepped.run(1.0, every_s=0.1, step_s=STEP_S)
    show(PanelSignal.FORWARD)
    stepped.run(0.2, every_s=0.1, step_s=STEP_S)
    show(PanelSignal.STOP)  # too late to stop before the crosswalk: the robot drives on
    cmd = Twist()
    cmd.linear.x = 0.4
    connected(cmd_pub, "/cmd_vel")
    stepped.run(3.0, every_s=0.1, before_chunk=lambda: cmd_pub.publish(cmd), step_s=STEP_S)
    stepped.step_until(lambda: any(e["kind"] == "stop_not_respected" for e in events), "stop_not_respected")
    cmd_pub.publish(Twist())
    show(PanelSignal.FORWARD)
    rospy.wait_for_service("/conde_sim/set_start_pose")
    # On the west line of the straight, heading north, 2 m before the crosswalk.
    answer = rospy.ServiceProxy("/conde_sim/set_start_pose", SetStartPose)("", 1.05, -2.0, 1.5708)
    assert answer.success, answer.message
    stepped.run(0.5, every_s=0.1, step_s=STEP_S)
    stepped.step_until(lambda: any(e["kind"] == "line_touch" for e in events), "line_touch")
    show(PanelSignal.END_OF_TRIAL)


def moved_box(stepped, show, events, cmd_pub):
    """D3 v1: the robot stands at its start; the north loop's box is moved 0.3 m along its lane
    with /gazebo/set_model_state (as if pushed); then end of trial."""
    stepped.run(0.5, every_s=0.1, step_s=STEP_S)
    show(PanelSignal.FORWARD)
    box = next(o for o in objects_of(layout(load_challenges(), "D3", "v1", 0)[3], 0)[0] if o["name"] == "obstacle_1")
    (x, y, z), yaw = box["pose"]["xyz"], box["pose"]["rpy"][2]
    state = ModelState(model_name="obstacle_1", reference_frame="world")
    state.pose.position.x, state.pose.position.y, state.pose.position.z = x + 0.3 * math.cos(yaw), \
        y + 0.3 * math.sin(yaw), z
    state.pose.orientation.z, state.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    rospy.wait_for_service("/gazebo/set_model_state")
    answer = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)(state)
    assert answer.success, answer.status_message
    stepped.step_until(lambda: any(e["kind"] == "object_displaced" for e in events), "object_displaced")
    show(PanelSignal.END_OF_TRIAL)


def push(stepped, show, events, cmd_pub):
    """D3 v1: put 0.7 m before the north loop's box in its lane, facing its centre, the robot drives
    0.5 m/s into it until the referee reports it displaced (PUSH_S at most); then end of trial."""
    spec = layout(load_challenges(), "D3", "v1", 0)[3]["obstacles"][0]
    lane_r = co.LANE_R[spec["lane"]]
    x, y, _ = co.loop_point(spec["loop"], spec["angle_deg"] - math.degrees(0.7 / lane_r), lane_r)
    box_x, box_y, _ = co.loop_point(spec["loop"], spec["angle_deg"], lane_r)
    stepped.run(0.5, every_s=0.1, step_s=STEP_S)
    show(PanelSignal.FORWARD)
    rospy.wait_for_service("/conde_sim/set_start_pose")
    answer = rospy.ServiceProxy("/conde_sim/set_start_pose", SetStartPose)("", x, y, math.atan2(box_y - y, box_x - x))
    assert answer.success, answer.message
    cmd = Twist()
    cmd.linear.x = 0.5
    connected(cmd_pub, "/cmd_vel")
    for _ in range(int(PUSH_S / 0.1)):
        stepped.run(0.1, every_s=0.05, before_chunk=lambda: cmd_pub.publish(cmd), step_s=STEP_S)
        if any(e["kind"] == "object_displaced" for e in events):
            break
    cmd_pub.publish(Twist())
    stepped.step_until(lambda: any(e["kind"] == "object_displaced" for e in events), "object_displaced")
    show(PanelSignal.END_OF_TRIAL)


PUSH_S = 6.0
SCENARIOS = {"stop_run": ("D1", stop_run), "moved_box": ("D3", moved_box), "push": ("D3", push)}


def main():
    engine, out_dir = sys.argv[1], sys.argv[2]
    challenge, scenario = SCENARIOS[sys.argv[3] if len(sys.argv) > 3 else "stop_run"]
    paths = write_challenge(challenge, "v1", 0, os.path.join(out_dir, challenge))
    rospy.set_param("/challenge/summary_file", paths["summary"])
    rospy.init_node("referee_probe")
    log = open(os.path.join(out_dir, "nodes_%s.log" % engine), "w")
    sim = subprocess.Popen(["rosrun", "conde_sim", "conde_sim_node", "_world_file:=" + paths["world"],
                            "_physics_engine:=" + engine, "_paused:=true", "_real_time_factor:=0", "_spawn:=conde",
                            "_model_poses_rate_hz:=10"],  # as conde_bringup challenge.launch sets it
                           stdout=log, stderr=subprocess.STDOUT)
    referee = subprocess.Popen(["rosrun", "conde_referee", "conde_referee", "_output_dir:=" + out_dir],
                               stdout=log, stderr=subprocess.STDOUT)
    events, reports = [], []
    rospy.Subscriber("/conde_referee/events", String, lambda m: events.append(json.loads(m.data)), queue_size=50)
    rospy.Subscriber("/conde_referee/report", String, lambda m: reports.append(json.loads(m.data)), queue_size=1)
    markers, pose_stamps_s = [], []
    rospy.Subscriber("/conde_referee/markers", MarkerArray, markers.append, queue_size=20)
    rospy.Subscriber("/conde_sim/model_poses", TFMessage,
                     lambda m: pose_stamps_s.append(m.transforms[0].header.stamp.to_sec()), queue_size=1000)
    panel = rospy.Publisher("/signalling_panel/signal", PanelSignal, queue_size=10, latch=True)
    cmd_pub = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
    try:
        stepped = SteppedSim()
        wait_for(lambda: panel.get_num_connections() > 0, "the referee on the panel topic")

        def show(signal):
            send(panel, PanelSignal(signal=signal, confidence=1.0), "/signalling_panel/signal")

        scenario(stepped, show, events, cmd_pub)
        stepped.step_until(lambda: reports, "the referee's report", steps=100)
        stepped.step_until(lambda: markers and any(m.ns == "referee_score" and "end of trial" in m.text
                                                   for m in markers[-1].markers), "the final markers", steps=100)
        result = {"engine": engine, "events": events, "report": reports[-1], "files": sorted(os.listdir(out_dir)),
                  "referee_alive": referee.poll() is None, "pose_stamps_s": pose_stamps_s,
                  "markers": [{"ns": m.ns, "id": m.id, "type": m.type, "text": m.text, "frame": m.header.frame_id,
                               "xy": [round(m.pose.position.x, 3), round(m.pose.position.y, 3)]}
                              for m in markers[-1].markers]}
    finally:
        stop_process(referee)
        stop_process(sim)
        log.close()
    print(json.dumps(result), flush=True)


if __name__ == "__main__":
    main()
