#!/usr/bin/env python3
"""Loads every challenge world (each variant, and random layouts of a few seeds) in turn into a
paused conde_sim node with the Conde robot on one engine, steps it RUN_S simulated seconds and
prints one JSON line per world: the robot's ground-truth pose before and after (it must stand
still at its start pose: no command is sent), for V1 what the signalling-panel camera sees of
the sign in front of it (pixels of the sign families' red and blue), then how far it drives in
DRIVE_S at DRIVE_MPS (nothing is in its way).

usage: challenge_world_checks.py ENGINE OUTPUT_DIR   (against the ROS master of the environment)
"""
import json
import math
import os
import subprocess
import sys

import numpy as np
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image

from conde_worlds import challenge_objects as co
from conde_worlds.challenge_world import write_challenge
from conde_worlds.challenges import load_challenges
from conde_testing.ros_harness import stop_process
from stepped_sim import SteppedSim, connected, wait_for

RUN_S = 2.0
DRIVE_S = 1.5
DRIVE_MPS = 0.3
STEP_S = 0.001
#: The robot stands 1.0 m in front of sign position 0, facing it (the face points along -y).
SIGN_X, SIGN_Y, _ = co.SIGN_POSES[0]
SIGN_VIEW_SPAWN = "%g %g %g" % (SIGN_X, SIGN_Y - 1.0, math.pi / 2)
EXTRA = [("D3", "v1", 7), ("D4", "v2", 11), ("B2", "v1", 3), ("V1", "v1", 5)]


def worlds():
    challenges = load_challenges()
    out = [(c, v, 0) for c, ch in challenges.challenges.items() for v in ch.variants]
    return out + EXTRA


def colour_counts(msg):
    img = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    red = int(np.sum((r > 150) & (g < 90) & (b < 90)))
    blue = int(np.sum((b > 120) & (r < 60) & (g > 60) & (g < 160)))
    return red, blue


def save_image(msg, path):
    import cv2
    img = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3)
    cv2.imwrite(path, cv2.cvtColor(img, cv2.COLOR_RGB2BGR))


def check_world(engine, out_dir, cmd_pub, challenge, variant, seed):
    paths = write_challenge(challenge, variant, seed, os.path.join(out_dir, "%s_%s_%d" % (challenge, variant, seed)))
    spawn = SIGN_VIEW_SPAWN if challenge == "V1" else "conde"
    log_path = os.path.join(paths["dir"], "conde_sim_%s.log" % engine)
    log = open(log_path, "w")
    node = subprocess.Popen(["rosrun", "conde_sim", "conde_sim_node", "_world_file:=" + paths["world"],
                             "_physics_engine:=" + engine, "_paused:=true", "_real_time_factor:=0",
                             "_spawn:=" + spawn], stdout=log, stderr=subprocess.STDOUT)
    odoms = []
    images = []
    subs = [rospy.Subscriber("/ground_truth/odom", Odometry, odoms.append, queue_size=200)]
    if challenge == "V1":
        subs.append(rospy.Subscriber("/conde_camera_signalling_panel/image_raw", Image, images.append, queue_size=5))
    result = {"challenge": challenge, "variant": variant, "seed": seed, "engine": engine}
    try:
        sim = SteppedSim()
        sim.step_until(lambda: odoms, "the first ground-truth pose")
        first = odoms[-1].pose.pose.position
        sim.run(RUN_S, every_s=0.25, step_s=STEP_S)
        wait_for(lambda: odoms[-1].header.stamp.to_sec() >= sim.time_s - 0.03, "the last ground-truth pose")
        last = odoms[-1].pose.pose.position
        result.update(sim_time_s=sim.time_s, start=[first.x, first.y, first.z], end=[last.x, last.y, last.z])
        if challenge == "V1":
            sim.step_until(lambda: images, "a signalling-panel camera image", steps=50)
            result["sign_red_px"], result["sign_blue_px"] = colour_counts(images[-1])
            if os.environ.get("CHALLENGE_CHECKS_SAVE_IMAGES"):
                save_image(images[-1], os.path.join(paths["dir"], "sign_view.png"))
        # Then drive straight on for DRIVE_S: the robot moves in the world (nothing is in its way).
        start_drive = odoms[-1].pose.pose.position
        cmd = Twist()
        cmd.linear.x = DRIVE_MPS
        connected(cmd_pub, "/cmd_vel")
        sim.run(DRIVE_S, every_s=0.1, before_chunk=lambda: cmd_pub.publish(cmd), step_s=STEP_S)
        wait_for(lambda: odoms[-1].header.stamp.to_sec() >= sim.time_s - 0.03, "the ground-truth pose after driving")
        moved = odoms[-1].pose.pose.position
        result["driven_m"] = math.hypot(moved.x - start_drive.x, moved.y - start_drive.y)
        result["node_alive"] = node.poll() is None
    finally:
        for s in subs:
            s.unregister()
        stop_process(node)
        log.close()
        with open(log_path) as f:
            result["node_output_tail"] = f.read()[-600:]
    return result


def main():
    engine, out_dir = sys.argv[1], sys.argv[2]
    rospy.init_node("challenge_world_checks")
    cmd_pub = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
    for challenge, variant, seed in worlds():
        print(json.dumps(check_world(engine, out_dir, cmd_pub, challenge, variant, seed)), flush=True)


if __name__ == "__main__":
    main()
