#!/usr/bin/env python3
"""The ROS side of test_control_node.py, run as its own process (rospy allows one node per
process): it owns /clock and advances it one control period at a time, publishes control
references for a while and then stops, and prints every /cmd_vel (with the clock and the phase)
as JSON on stdout."""

import json
import time

import rospy
from conde_msgs.msg import ControlReference
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock

from conde_testing.ros_harness import publishes_to, wait_or_exit

WAIT_S = 60.0  # wall-clock patience (a busy machine)
PERIOD = rospy.Duration(0, 33333334)  # one period of the node's 30 Hz loop (rounded up)


def wait_for(condition, what):
    wait_or_exit("control_probe", condition, what, WAIT_S, poll_s=0.002)


def main():
    rospy.init_node("control_probe")
    cmds = []
    clock_pub = rospy.Publisher("/clock", Clock, queue_size=10)
    ref_pub = rospy.Publisher("/conde_control_reference", ControlReference, queue_size=10)
    sub = rospy.Subscriber("/cmd_vel", Twist, cmds.append)
    wait_for(lambda: clock_pub.get_num_connections() > 0 and ref_pub.get_num_connections() > 0
             and sub.get_num_connections() > 0 and publishes_to("/conde_control", "/cmd_vel", rospy.get_name()),
             "the connections to conde_control")
    now = rospy.Time(10, 0)
    clock_pub.publish(Clock(clock=now))
    # The node ticks once when the clock jumps to 10 s (a brake command: no reference yet) and then
    # once per period. Commands are taken by their index, never as "the newest": on a busy machine
    # one may arrive after the next period's, and the newest would then skip one.
    # The node's /clock connection is not among those checked above (the probe's own subscription
    # counts too): the first clock message is sent again until the node answers it (the same time
    # again gives no second tick).
    deadline = time.monotonic() + WAIT_S
    while not cmds and time.monotonic() < deadline and not rospy.is_shutdown():
        clock_pub.publish(Clock(clock=now))
        time.sleep(0.05)
    wait_for(lambda: len(cmds) >= 1, "the command at the first clock message")
    taken = 1

    log = []
    for phase, steps in (("follow", 60), ("silent", 60)):
        for i in range(steps):
            if phase == "follow":
                ref = ControlReference()
                ref.header.stamp = now
                ref.lateral_offset_m = 0.1  # left of the lane centre
                ref.linear_velocity_mps = 0.5
                ref_pub.publish(ref)
                # Let it arrive before the clock moves on. The node times the reference by its
                # arrival, and the test checks the braking to the period after the last one: that
                # one gets far more time (nothing tells the probe that it has arrived).
                time.sleep(0.5 if i == steps - 1 else 0.005)
            now += PERIOD
            clock_pub.publish(Clock(clock=now))
            taken += 1
            wait_for(lambda: len(cmds) >= taken, "the command of the tick at %.3f s" % now.to_sec())
            cmd = cmds[taken - 1]
            log.append([phase, now.to_sec(), cmd.linear.x, cmd.angular.z])
    print(json.dumps(log))


if __name__ == "__main__":
    main()
