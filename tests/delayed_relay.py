#!/usr/bin/env python3
"""A slow link for step_ack.test: republishes each geometry_msgs/Twist of ~input on ~output after
~delay_s of wall time, as a busy machine may deliver a command late."""
import threading

import rospy
from geometry_msgs.msg import Twist


def main():
    rospy.init_node("delayed_relay")
    delay_s = float(rospy.get_param("~delay_s", 1.0))
    if not delay_s >= 0:
        rospy.logfatal("delayed_relay: ~delay_s must be >= 0, got %s", delay_s)
        raise SystemExit(1)
    pub = rospy.Publisher(rospy.get_param("~output", "output"), Twist, queue_size=10)

    def later(msg):
        threading.Timer(delay_s, pub.publish, args=(msg,)).start()

    rospy.Subscriber(rospy.get_param("~input", "input"), Twist, later, queue_size=10)
    rospy.spin()


if __name__ == "__main__":
    main()
