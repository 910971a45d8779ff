#!/usr/bin/env python3
"""A student-like node for the lock-step tests: one message on ~answer per image on ~image, after
sleeping ~delay_s of wall time (a slow node). The answer (geometry_msgs/PointStamped) carries the
image's stamp in its header and, in point.x, the ROS time [s] the node sees when it answers.
Prints "ready" once its subscriber and (unless ~wait_for_listener is false) its publisher are
connected, then "answer <stamp> <now>"
[s] for each answer."""
import time

import rospy
from geometry_msgs.msg import PointStamped
from sensor_msgs.msg import Image


def main():
    rospy.init_node("lockstep_answerer")
    delay_s = float(rospy.get_param("~delay_s", 0.05))
    pub = rospy.Publisher(rospy.get_param("~answer", "slow_answer"), PointStamped, queue_size=10)

    def on_image(msg):
        time.sleep(delay_s)
        out = PointStamped()
        out.header.stamp = msg.header.stamp
        out.point.x = rospy.get_rostime().to_sec()
        pub.publish(out)
        print("answer %.6f %.6f" % (msg.header.stamp.to_sec(), out.point.x), flush=True)

    sub = rospy.Subscriber(rospy.get_param("~image", "image"), Image, on_image, queue_size=1, buff_size=2 ** 22)
    wait_for_listener = rospy.get_param("~wait_for_listener", True)
    while not rospy.is_shutdown() and (sub.get_num_connections() == 0 or
                                       (wait_for_listener and pub.get_num_connections() == 0)):
        time.sleep(0.05)
    print("ready", flush=True)
    rospy.spin()


if __name__ == "__main__":
    main()
