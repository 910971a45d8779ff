#!/usr/bin/env python3
"""Renders what Conde's left tracking camera sees in the generated D4 world with the robot in the
outer lane of the south loop, once under the tunnel's roof and once in the open part of the same
loop, and prints one JSON line per place: the brightness (0..255, mean of R, G, B) of the white
lane lines in the lower half of the image (the road in front of the robot; its 99th percentile:
the asphalt is black, the lines are the brightest thing there) and the image's mean. The images
are saved beside the node's logs.

usage: tunnel_light_checks.py ENGINE OUTPUT_DIR   (against the ROS master of the environment)
"""
import json
import os
import subprocess
import sys

import cv2
import numpy as np
import rospy
from sensor_msgs.msg import Image

from conde_worlds import challenge_objects as co
from conde_worlds.challenge_world import write_challenge
from conde_testing.ros_harness import stop_process
from stepped_sim import SteppedSim

#: Loop angles [deg] of the two places (the D4 tunnel spans 110..200 deg of the south loop; the
#: v1 boxes stand at 60 deg in the inner lane and in the north loop).
PLACES = {"inside_tunnel": 150.0, "open_road": 25.0}


def brightness(engine, world_file, angle_deg, log_path):
    x, y, heading = co.loop_point("south", angle_deg, co.LANE_R["outer"])
    images = []
    with open(log_path, "w") as log:
        node = subprocess.Popen(["rosrun", "conde_sim", "conde_sim_node", "_world_file:=" + world_file,
                                 "_physics_engine:=" + engine, "_paused:=true", "_real_time_factor:=0",
                                 "_spawn:=%.4f %.4f %.4f" % (x, y, heading)], stdout=log, stderr=subprocess.STDOUT)
        sub = rospy.Subscriber("/conde_camera_tracking_left/image_raw", Image, images.append, queue_size=5)
        try:
            SteppedSim().step_until(lambda: images, "a tracking camera image", steps=50)
        finally:
            sub.unregister()
            stop_process(node)
    msg = images[-1]
    pixels = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.width, 3)
    cv2.imwrite(log_path[:-len(".log")] + ".png", cv2.cvtColor(pixels, cv2.COLOR_RGB2BGR))
    lower_half = pixels[msg.height // 2:].astype(float).mean(axis=2)
    return float(np.percentile(lower_half, 99)), float(pixels.mean())


def main():
    engine, out_dir = sys.argv[1], sys.argv[2]
    rospy.init_node("tunnel_light_checks")
    paths = write_challenge("D4", "v1", 0, os.path.join(out_dir, "D4_v1_0"))
    for place, angle in PLACES.items():
        lines, mean = brightness(engine, paths["world"], angle,
                                 os.path.join(out_dir, "conde_sim_%s_%s.log" % (engine, place)))
        print(json.dumps({"engine": engine, "place": place, "angle_deg": angle, "line_brightness": lines,
                          "image_mean": mean}), flush=True)


if __name__ == "__main__":
    main()
