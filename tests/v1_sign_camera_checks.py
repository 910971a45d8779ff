#!/usr/bin/env python3
"""Checks of V1 with Conde's sign camera (see v1_sign_camera.test): Conde is put on its lap before the
north loop's signs and before the south loop's and driven along the lap (a path follower on the ground
truth: the lap's curvature plus corrections of the lateral and heading errors), stepping the simulation.
The signs inside the loops (8, 9, 11, 12), which face away from the lane driven and are never in the top
camera's view from it (sign_visibility), are recognised in the rear-left sign camera's images (the node's
detections name the camera); the referee counts every report right."""
import json
import math
import unittest

import numpy as np
import rospy
import rostest
from conde_msgs.srv import SetStartPose
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import String
from std_srvs.srv import Empty
from visualization_msgs.msg import MarkerArray

from conde_traffic_sign.sign_visibility import condes_route
from conde_worlds.track_geometry import build_track
from conde_worlds.traffic_signs import SIGNS
from stepped_sim import Latest, SteppedSim, connected, wait_for

REAR_IMAGES = "/conde_camera_signs_rear/image_raw"
SPACING_M = 0.02  # of the lap's points
# (first, last lap point, signs judged there): from before sign 2 to past sign 8 on the north loop, from
# before sign 4 to past sign 11 on the south loop (sign_visibility with the rear camera: 9 from point 538,
# 8 from 760, 12 from 1566, 11 from 1811)
SEGMENTS = ((390, 820, (2, 3, 9, 8)), (1400, 1840, (4, 12, 11)))
INNER = (8, 9, 11, 12)
SPEED_MPS = 0.6
LATERAL_GAIN = 4.0  # [rad/s per m]
HEADING_GAIN = 3.0  # [1/s]
STEPS = 33  # per command: one camera frame (1 ms steps)


def wrap(angle_rad):
    return (angle_rad + math.pi) % (2 * math.pi) - math.pi


class V1SignCameraTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("v1_sign_camera_test")
        cls.xy, cls.heading = condes_route(build_track().lane_centres(SPACING_M))
        cls.sim = SteppedSim()
        for name, service, kind in (("set_pose", "/conde_sim/set_start_pose", SetStartPose),
                                    ("forget_tracks", "/conde_traffic_sign/forget_tracks", Empty)):
            rospy.wait_for_service(service, timeout=60)
            setattr(cls, name, rospy.ServiceProxy(service, kind))
        cls.events, cls.detections, cls.truth = (Latest(topic, kind) for topic, kind in (
            ("/conde_referee/events", String), ("/conde_traffic_sign/detections", String),
            ("/ground_truth/odom", Odometry)))
        cls.cmd_vel = rospy.Publisher("/cmd_vel", Twist, queue_size=10)
        connected(cls.cmd_vel, "/cmd_vel")
        cls.curvature = np.gradient(np.unwrap(cls.heading)) / SPACING_M

    def follow(self, last):
        """One command along the lap from the ground-truth pose; the lap point nearest to the robot."""
        p = self.truth.last.pose.pose
        x, y = p.position.x, p.position.y
        yaw = 2.0 * math.atan2(p.orientation.z, p.orientation.w)
        i = int(np.argmin(np.hypot(self.xy[:, 0] - x, self.xy[:, 1] - y)))
        h = self.heading[i]
        lateral = -math.sin(h) * (x - self.xy[i, 0]) + math.cos(h) * (y - self.xy[i, 1])  # left of the lap
        twist = Twist()
        twist.linear.x = SPEED_MPS if i < last else 0.0
        twist.angular.z = (SPEED_MPS * self.curvature[i] - LATERAL_GAIN * lateral
                           - HEADING_GAIN * wrap(yaw - h)) if i < last else 0.0
        self.cmd_vel.publish(twist)
        return i

    def judged(self):
        events = [json.loads(m.data) for m in self.events.messages]
        return [e for e in events if e["kind"] in ("sign_right", "sign_wrong")]

    def test_the_inner_signs_are_read_by_the_rear_camera_and_judged_right(self):
        markers = Latest("/conde_referee/markers", MarkerArray)
        wait_for(lambda: markers.messages, "the referee's markers")
        for first, last, signs in SEGMENTS:
            self.assertTrue(self.set_pose("", float(self.xy[first, 0]), float(self.xy[first, 1]),
                                          float(self.heading[first])).success)
            self.forget_tracks()  # set_start_pose restarted the odometry
            self.sim.step(200)
            wait_for(lambda: self.truth.messages, "the ground truth")
            point = first

            def judged_or_drive():
                nonlocal point
                done = {int(e["detail"].split(":")[0].split()[1]) for e in self.judged()}
                if set(signs) <= done:
                    return True
                self.assertLess(point, last, "signs %s judged by the end of the segment: %s" % (signs, sorted(done)))
                point = self.follow(last)
                return False

            self.sim.step_until(judged_or_drive, "signs %s judged" % (signs,), steps=STEPS, timeout_s=300)
            self.cmd_vel.publish(Twist())
        judged = self.judged()
        self.assertEqual([e["kind"] for e in judged], ["sign_right"] * len(judged), judged)
        numbers = {int(e["detail"].split(":")[0].split()[1]) for e in judged}
        self.assertTrue({2, 3, 4, 8, 9, 11, 12} <= numbers, judged)
        seen = {}
        for m in self.detections.messages:
            for d in json.loads(m.data):
                seen.setdefault(d["camera"], set()).add(d["name"])
        for n in INNER:  # the listed layout: sign n shows SIGNS[n - 1]
            self.assertIn(SIGNS[n - 1], seen.get(REAR_IMAGES, set()), seen)


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "v1_sign_camera", V1SignCameraTest)
