#!/usr/bin/env python3
"""Checks of d4_working_zone.test: Conde, from the challenge's start at the crosswalk (the go on the
panel at 3 s: the robot must be where its top camera sees the panel), drives with the reference stack
into the north loop and through its working zone (cones closing the outer lane from 40 to 150 deg) on
the inner lane and back into the outer lane; the referee, judging from the ground truth, gives no
penalty and no cone is touched or moved. The robot's way is followed on the ground truth
(/ground_truth/odom) by its loop angle; the test ends there (the lap is D4's full run, not this test)."""
import json
import math
import unittest

import rospy
import rostest
from conde_msgs.msg import DecisionState
from nav_msgs.msg import Odometry
from std_msgs.msg import Header, String

from conde_referee.course import Course
from conde_worlds import challenge_objects as co
from stepped_sim import Latest, wait_for

AVOIDING = ("avoid_change_lane", "avoid_pass", "avoid_return")  # conde_states.yaml
# back in the own lane: the decision following it again, the robot within this of its centre line [m],
# heading along it [rad]; then driven on for DRIVE_ON_S [s of simulated time] (the way back ends in the lane)
BACK_OFFSET_M = 0.1
BACK_HEADING_RAD = 0.2
DRIVE_ON_S = 1.5
SIM_LIMIT_S = 60.0  # [s of simulated time] the robot must be through by then (about 30 s at 0.5 m/s)
WALL_LIMIT_S = 540.0  # [s] lock-step on a slow, busy machine (d4_working_zone.test's time-limit is 600)


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def angle_diff(a, b):
    return math.atan2(math.sin(a - b), math.cos(a - b))


class D4WorkingZoneTest(unittest.TestCase):
    def test_through_the_working_zone_without_penalty(self):
        rospy.init_node("d4_working_zone_test")
        course = Course.from_layout("D4", rospy.get_param("~variant"))
        zone = course.features["working_zone"]  # north loop, outer lane, 40..150 deg
        self.assertEqual((zone["loop"], zone["lane"]), ("north", "outer"))
        own_lane_r = co.lane_radii(course.dims)["outer"]
        other_lane_r = co.lane_radii(course.dims)["inner"]
        events = Latest("/conde_referee/events", String)
        judged_until = Latest("/conde_referee/judged_until", Header)
        states = Latest("/conde_decision/state", DecisionState)
        avoided = []  # stamps [s] of the decision's states while avoiding

        def on_state(msg):
            if msg.state in AVOIDING:
                avoided.append(msg.header.stamp.to_sec())

        rospy.Subscriber("/conde_decision/state", DecisionState, on_state, queue_size=100)
        poses = []  # (t [s], loop angle [deg] or None, radius [m], heading error to the loop's sense [rad])

        def on_odom(msg):
            p = msg.pose.pose.position
            where = course.loop_position(p.x, p.y)
            if where is None or where[0] != "north":
                poses.append((msg.header.stamp.to_sec(), None, 0.0, 0.0))
                return
            _, angle_deg, r = where
            along = co.loop_point("north", angle_deg, r, course.dims)[2]
            heading_error = angle_diff(yaw_of(msg.pose.pose.orientation), along)
            poses.append((msg.header.stamp.to_sec(), angle_deg, r, heading_error))

        rospy.Subscriber("/ground_truth/odom", Odometry, on_odom, queue_size=200)

        def penalties():
            judged = [json.loads(m.data) for m in events.messages]
            return [e for e in judged if e.get("penalty", 0) > 0 or e["kind"] in ("collision", "object_displaced")]

        back = []  # the stamp [s] at which the robot was back in its lane after the zone

        def done():
            self.assertEqual(penalties(), [])  # at once: a run that went wrong need not be driven on
            if not poses:
                return False
            t_s, angle_deg, r, heading_error = poses[-1]
            state = states.last and states.last.state
            self.assertLess(t_s, SIM_LIMIT_S, "not through the working zone and back in its lane by %g s: %s, "
                            "decision %s" % (SIM_LIMIT_S, poses[-1], state))
            if not back and (angle_deg is not None and angle_deg > zone["to_deg"] and avoided and state == "follow_lane"
                             and abs(r - own_lane_r) < BACK_OFFSET_M and abs(heading_error) < BACK_HEADING_RAD):
                back.append(t_s)
            return bool(back) and t_s >= back[0] + DRIVE_ON_S

        wait_for(done, "the robot through the working zone", WALL_LIMIT_S)
        done_s = poses[-1][0]
        wait_for(lambda: judged_until.last and judged_until.last.stamp.to_sec() >= done_s,
                 "the referee judging up to %.2f s" % done_s)
        # on the inner lane beside the cones, in the own lane after them
        beside = [r for _, a, r, _ in poses if a is not None and zone["from_deg"] + 25 <= a <= zone["to_deg"] - 25]
        self.assertTrue(beside)
        self.assertLess(max(abs(r - other_lane_r) for r in beside), 0.15, "not on the inner lane beside the cones")
        self.assertEqual(penalties(), [])
        rospy.loginfo("back in the lane after the working zone at %.2f s (%.0f deg); referee events %s", back[0],
                      next(a for t, a, _, _ in poses if t >= back[0]),
                      [(e["kind"], e["t_s"]) for e in (json.loads(m.data) for m in events.messages)])


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "d4_working_zone", D4WorkingZoneTest)
