#!/usr/bin/env python3
"""Probe for test_racing.py: drives a paused racetrack.launch (4 cars, drivers disabled) by the
step service and prints what it measured as JSON on stdout; test_racing.py judges it.

1. Which cars publish ground truth.
2. car1 alone is commanded (0.5 m/s for 1 s): how far each car moved.
3. Every TF edge seen meanwhile: parent, child, publishing node.
4. The world is reset and car1..car3 are moved off the track; car0's reference driver is
   enabled and the simulation is stepped one scan period (25 ms) at a time, each step waiting
   for the driver's command on that scan, until the lap timer reports car0's first lap or the
   simulated-time limit: the lap row, the simulated and wall time it took, car0's largest
   distance from the centre line, the parked cars' moves.
"""
import argparse
import json
import math
import sys
import time

import rosgraph
import rospy
from conde_msgs.msg import AckermannDriveStamped
from conde_msgs.srv import SetStartPose
from nav_msgs.msg import Odometry
from std_msgs.msg import String
from std_srvs.srv import Empty, SetBool
from tf2_msgs.msg import TFMessage

from conde_racing import racetrack as rt
from stepped_sim import WALL_TIMEOUT_S, Latest, SteppedSim, connected, send, wait_for

SCAN_PERIOD_STEPS = 25       # 40 Hz LiDAR at 1 ms steps
PARKING = {"car1": (2.0, -2.2), "car2": (3.0, -2.2), "car3": (4.0, -2.2)}  # south of the main straight


def xy(odom):
    p = odom.pose.pose.position
    return p.x, p.y


class TfRecorder:
    def __init__(self):
        self.edges = set()
        self.subs = [rospy.Subscriber(topic, TFMessage, self.on_tf, callback_args=topic, queue_size=1000)
                     for topic in ("/tf", "/tf_static")]

    def on_tf(self, msg, topic):
        caller = msg._connection_header.get("callerid", "?")
        for t in msg.transforms:
            self.edges.add((t.header.frame_id, t.child_frame_id, caller, topic))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cars", type=int, default=4)
    parser.add_argument("--sim-time-limit", type=float, default=90.0, help="simulated seconds for the lap")
    args = parser.parse_args()
    rospy.init_node("racing_checks")
    cars = ["car%d" % k for k in range(args.cars)]
    out = {}

    sim = SteppedSim()
    truth = {car: Latest("/%s/ground_truth/odom" % car, Odometry) for car in cars}
    for latest in truth.values():
        connected(latest.sub, latest.topic)
    tf = TfRecorder()
    for sub in tf.subs:
        connected(sub, sub.name)
    sim.step(200)
    for latest in truth.values():
        latest.wait_until_stamped(sim.time_s, 0.02)
    topics = [name for name, _ in rosgraph.Master("/racing_checks").getPublishedTopics("")]
    out["cars_with_ground_truth"] = sorted(t.split("/")[1] for t in topics if t.endswith("/ground_truth/odom"))

    # --- only car1 answers car1's command
    start = {car: xy(truth[car].last) for car in cars}
    drive = rospy.Publisher("/car1/ackermann_cmd", AckermannDriveStamped, queue_size=1)
    cmd = AckermannDriveStamped()
    cmd.drive.speed = 0.5
    send(drive, cmd, "/car1/ackermann_cmd")
    sim.run(1.0, before_chunk=lambda: drive.publish(cmd))
    moved = {}
    for car in cars:
        end = xy(truth[car].wait_until_stamped(sim.time_s, 0.02))
        moved[car] = math.hypot(end[0] - start[car][0], end[1] - start[car][1])
    out["moved_when_car1_commanded_m"] = moved
    sim.run(1.0)  # car1 brakes after its command timeout; TF keeps coming
    out["tf_edges"] = sorted(tf.edges)
    for sub in tf.subs:
        sub.unregister()

    # --- a lap of car0 with its reference driver
    rospy.ServiceProxy("/conde_sim/reset_world", Empty)()
    set_start = rospy.ServiceProxy("/conde_sim/set_start_pose", SetStartPose)
    for car, (x, y) in PARKING.items():
        if car in cars:
            response = set_start(car, x, y, 0.0)
            assert response.success, response.message
    sim.step(100)
    for latest in truth.values():
        latest.wait_until_stamped(sim.time_s, 0.02)
    parked = {car: xy(truth[car].last) for car in PARKING if car in cars}

    commands = Latest("/car0/ackermann_cmd", AckermannDriveStamped)
    laps = Latest("/lap_timer/laps", String)
    connected(laps.sub, "/lap_timer/laps")
    rospy.wait_for_service("/car0/gap_follower/enable", timeout=WALL_TIMEOUT_S)
    rospy.ServiceProxy("/car0/gap_follower/enable", SetBool)(True)
    line = rt.CentreLine()
    lap_start_sim_s, wall_start = sim.time_s, time.monotonic()
    # The driver subscribes to the scan when enabled; until the simulator sees it, no scan comes.
    for _ in range(200):
        sim.step(SCAN_PERIOD_STEPS)
        try:
            wait_for(lambda: commands.messages and commands.last.header.stamp.to_sec() >= sim.time_s - 1e-6,
                     "car0's first command", timeout_s=1.0)
            break
        except AssertionError:
            continue
    max_lateral_m, reversing_commands, top_command_mps = 0.0, 0, 0.0
    while not any(row.data.startswith("car0,") for row in laps.messages):
        if sim.time_s - lap_start_sim_s > args.sim_time_limit:
            break
        sim.step(SCAN_PERIOD_STEPS)
        wait_for(lambda: commands.last.header.stamp.to_sec() >= sim.time_s - 1e-6,
                 "car0's command on the scan of %.3f s" % sim.time_s, timeout_s=WALL_TIMEOUT_S)
        reversing_commands += commands.last.drive.speed < 0
        top_command_mps = max(top_command_mps, commands.last.drive.speed)
        if truth["car0"].last is not None:
            max_lateral_m = max(max_lateral_m, abs(line.project(*xy(truth["car0"].last))[1]))
        if len(commands.messages) > 1000:
            del commands.messages[:-10]
    if not any(row.data.startswith("car0,") for row in laps.messages):  # the lap ended in the last step
        try:
            wait_for(lambda: any(row.data.startswith("car0,") for row in laps.messages), "car0's lap", 5.0)
        except AssertionError:
            pass
    rospy.ServiceProxy("/car0/gap_follower/enable", SetBool)(False)
    out["lap_rows"] = [row.data for row in laps.messages]
    out["lap_sim_time_s"] = sim.time_s - lap_start_sim_s
    out["lap_wall_time_s"] = time.monotonic() - wall_start
    out["car0_max_abs_lateral_m"] = max_lateral_m
    out["car0_reversing_commands"] = reversing_commands
    out["car0_top_commanded_speed_mps"] = top_command_mps
    out["parked_cars_moved_m"] = {
        car: math.hypot(xy(truth[car].last)[0] - p[0], xy(truth[car].last)[1] - p[1]) for car, p in parked.items()}
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
