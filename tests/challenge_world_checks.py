#!/usr/bin/env python3
"""Loads every challenge world (each variant, and random layouts of a few seeds) in turn into a
paused conde_sim node with the Conde robot on one engine, steps it RUN_S simulated seconds and
prints one JSON line per world: the robot's ground-truth pose before and after (it must stand
still at its start pose: no command is sent), for V1 what the signalling-panel camera sees of
the sign in front of it (pixels of the sign families' red and blue), then how far it drives in
DRIVE_S at DRIVE_MPS (nothing is in its way). Last, for D3 and D4, the robot is put in front of
the first box (along its lane) and of the first cone: the pixels of the box's green and the cone's
orange that the two tracking cameras (the ground cameras) see. One world is on a varied track
(track seed > 0).

usage: challenge_world_checks.py ENGINE OUTPUT_DIR   (against the ROS master of the environment)
"""
import contextlib
import json
import math
import os
import subprocess
import sys

import numpy as np
import rospy
import yaml
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
#: (challenge, variant, seed, track seed): the last on a varied track (conde_worlds track_variation).
EXTRA = [("D3", "v1", 7, 0), ("D4", "v2", 11, 0), ("B2", "v1", 3, 0), ("V1", "v1", 5, 0), ("D3", "v1", 0, 5)]
#: (challenge, object-name prefix): the robot's centre OBJECT_VIEW_M before the object, facing it.
OBJECT_VIEWS = [("D3", "obstacle_"), ("D4", "cone_")]
OBJECT_VIEW_M = 0.8
TRACKING_TOPICS = ["/conde_camera_tracking_left/image_raw", "/conde_camera_tracking_right/image_raw"]


def worlds():
    challenges = load_challenges()
    out = [(c, v, 0, 0) for c, ch in challenges.challenges.items() for v in ch.variants]
    return out + EXTRA


def colour_counts(msg):
    img = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    red = int(np.sum((r > 150) & (g < 90) & (b < 90)))
    blue = int(np.sum((b > 120) & (r < 60) & (g > 60) & (g < 160)))
    return red, blue


def object_colour_counts(msg):
    """Pixels of the boxes' green (0, 1, 0) and of the cones' orange (1, 0.27, 0), lit or shaded."""
    img = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3).astype(int)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    green = int(np.sum((g > 80) & (r < 0.3 * g) & (b < 0.3 * g)))
    orange = int(np.sum((r > 80) & (g > 0.12 * r) & (g < 0.45 * r) & (b < 0.15 * r)))
    return green, orange


def object_view_spawn(world_path, prefix):
    """'x y yaw' OBJECT_VIEW_M before the first object named prefix*, facing it: along the object's
    heading (a box lies along its lane), or from the track's centre outwards for a round cone."""
    with open(world_path) as f:
        objects = yaml.safe_load(f)["objects"]
    obj = next(o for o in objects if o["name"].startswith(prefix))
    x, y = obj["pose"]["xyz"][0], obj["pose"]["xyz"][1]
    yaw = obj["pose"]["rpy"][2] if obj["shape"] == "box" else math.atan2(y, x)
    return obj["name"], "%g %g %g" % (x - OBJECT_VIEW_M * math.cos(yaw), y - OBJECT_VIEW_M * math.sin(yaw), yaw)


@contextlib.contextmanager
def challenge_node(paths, engine, spawn, log_name, subs, result):
    """A paused conde_sim node on the challenge's world with the robot at `spawn`; on the way out
    the subscribers `subs` are dropped, the node stopped and its output's tail put in `result`."""
    log_path = os.path.join(paths["dir"], log_name)
    with open(log_path, "w") as log:
        node = subprocess.Popen(["rosrun", "conde_sim", "conde_sim_node", "_world_file:=" + paths["world"],
                                 "_physics_engine:=" + engine, "_paused:=true", "_real_time_factor:=0",
                                 "_spawn:=" + spawn], stdout=log, stderr=subprocess.STDOUT)
        try:
            yield node
        finally:
            for sub in subs:
                sub.unregister()
            stop_process(node)
    with open(log_path) as f:
        result["node_output_tail"] = f.read()[-600:]


def check_object_view(engine, out_dir, challenge, prefix):
    """Loads the challenge with the robot in front of an object; steps until both tracking cameras
    have drawn a frame and returns what they see of the object's colour."""
    paths = write_challenge(challenge, "v1", 0, os.path.join(out_dir, "%s_view" % challenge))
    name, spawn = object_view_spawn(paths["world"], prefix)
    images = {topic: [] for topic in TRACKING_TOPICS}
    subs = [rospy.Subscriber(topic, Image, images[topic].append, queue_size=5) for topic in TRACKING_TOPICS]
    result = {"view": challenge, "object": name, "engine": engine}
    with challenge_node(paths, engine, spawn, "conde_sim_view_%s.log" % engine, subs, result):
        sim = SteppedSim()
        sim.step_until(lambda: all(images.values()), "an image of each tracking camera", steps=50)
        counts = [object_colour_counts(images[topic][-1]) for topic in TRACKING_TOPICS]
        result["green_px"] = sum(c[0] for c in counts)
        result["orange_px"] = sum(c[1] for c in counts)
        if os.environ.get("CHALLENGE_CHECKS_SAVE_IMAGES"):
            for topic in TRACKING_TOPICS:
                save_image(images[topic][-1], os.path.join(paths["dir"], topic.split("/")[1] + ".png"))
    return result


def save_image(msg, path):
    import cv2
    img = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3)
    cv2.imwrite(path, cv2.cvtColor(img, cv2.COLOR_RGB2BGR))


def check_world(engine, out_dir, cmd_pub, challenge, variant, seed, track_seed):
    name = "%s_%s_%d_track%d" % (challenge, variant, seed, track_seed)
    paths = write_challenge(challenge, variant, seed, os.path.join(out_dir, name), track_seed=track_seed)
    spawn = SIGN_VIEW_SPAWN if challenge == "V1" else "conde"
    odoms = []
    images = []
    subs = [rospy.Subscriber("/ground_truth/odom", Odometry, odoms.append, queue_size=200)]
    if challenge == "V1":
        subs.append(rospy.Subscriber("/conde_camera_signalling_panel/image_raw", Image, images.append, queue_size=5))
    result = {"challenge": challenge, "variant": variant, "seed": seed, "track_seed": track_seed, "engine": engine}
    with open(paths["world"]) as f:
        result["spawn"] = yaml.safe_load(f)["spawn"]["conde"]
    with challenge_node(paths, engine, spawn, "conde_sim_%s.log" % engine, subs, result) as node:
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
    return result


def main():
    engine, out_dir = sys.argv[1], sys.argv[2]
    rospy.init_node("challenge_world_checks")
    cmd_pub = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
    for challenge, variant, seed, track_seed in worlds():
        print(json.dumps(check_world(engine, out_dir, cmd_pub, challenge, variant, seed, track_seed)), flush=True)
    for challenge, prefix in OBJECT_VIEWS:
        print(json.dumps(check_object_view(engine, out_dir, challenge, prefix)), flush=True)


if __name__ == "__main__":
    main()
