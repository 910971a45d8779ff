#!/usr/bin/env python3
"""The ROS side of test_decision_node.py, run as its own process (rospy allows one node per
process): it owns /clock, feeds conde_decision lane measurements and panel signals, and prints
what came out as one JSON object on stdout."""

import json
import time

import rospy
from conde_msgs.msg import ControlReference, DecisionState, LaneMeasurement, PanelSignal
from rosgraph_msgs.msg import Clock
from visualization_msgs.msg import Marker

from conde_testing.ros_harness import publishes_to, wait_or_exit

WAIT_S = 60.0  # wall-clock patience for anything to arrive (a busy machine)


def wait_for(condition, what):
    wait_or_exit("decision_probe", condition, what, WAIT_S, poll_s=0.005)


def main():
    rospy.init_node("decision_probe")
    refs, states, markers = [], [], []
    clock_pub = rospy.Publisher("/clock", Clock, queue_size=10)
    lane_pub = rospy.Publisher("/conde_lane", LaneMeasurement, queue_size=100)
    signal_pub = rospy.Publisher("/conde_signal", PanelSignal, queue_size=10)
    subs = [rospy.Subscriber("/conde_control_reference", ControlReference, refs.append),
            rospy.Subscriber("/conde_decision/state", DecisionState, states.append),
            rospy.Subscriber("/conde_decision/marker", Marker, markers.append)]
    now = rospy.Time(1, 0)

    def set_clock(t):
        clock_pub.publish(Clock(clock=t))

    wait_for(lambda: clock_pub.get_num_connections() > 0 and lane_pub.get_num_connections() > 0
             and signal_pub.get_num_connections() > 0 and all(s.get_num_connections() > 0 for s in subs)
             and publishes_to("/conde_decision", "/conde_control_reference", rospy.get_name()),
             "the connections to conde_decision")
    set_clock(now)
    wait_for(lambda: states and markers, "the latched state and marker")

    shown = [PanelSignal.NONE]  # the signal on the panel: sent with every measurement, as conde_semaphore
    #                             sends one per camera image, so the node in lock-step knows one is owed

    def lane_step(t, clock_late=False):
        signal = PanelSignal(signal=shown[0], confidence=1.0 if shown[0] != PanelSignal.NONE else 0.0)
        signal.header.stamp = t
        msg = LaneMeasurement()
        msg.header.stamp = t
        msg.header.frame_id = "base_footprint"
        msg.lateral_offset_m = 0.05
        msg.heading_error_rad = 0.02
        msg.confidence = 1.0
        count = len(refs)
        if not clock_late:
            set_clock(t)
        signal_pub.publish(signal)
        lane_pub.publish(msg)
        wait_for(lambda: len(refs) > count, "a control reference")
        if clock_late:
            set_clock(t)

    step = rospy.Duration(0, 33333333)
    for _ in range(9):  # no signal yet: wait at the start
        now += step
        lane_step(now)
    count = len(states)
    # The go signal comes with measurement 10 (index 9); the node applies it at measurement 11 (the
    # frame after its stamp's), having waited for it there (lock-step, ~input_wait_s) if it travelled
    # slower than that measurement on its own connection.
    shown[0] = PanelSignal.FORWARD
    now += step
    lane_step(now)
    now += step
    # The clock of this frame reaches the node only after its measurement (on a busy machine the
    # /clock connection can lag): the change of state must still carry the measurement's stamp.
    lane_step(now, clock_late=True)
    wait_for(lambda: len(states) > count, "the state after the go signal")
    for _ in range(29):
        now += step
        lane_step(now)
    # The state again at 1 Hz of ROS time: 3.5 s of clock without any input, sent in bursts of half
    # a second, so that the node's clock has often moved past a whole second by the time its
    # repeating thread runs (the repeats must still carry the whole seconds).
    count = len(states)
    for i in range(35):
        now += rospy.Duration(0, 100000000)
        set_clock(now)
        if i % 5 == 4:
            time.sleep(0.05)
    wait_for(lambda: len(states) >= count + 3, "the periodic state messages")

    print(json.dumps({
        "refs": [[r.header.stamp.to_sec(), r.header.frame_id, r.lateral_offset_m, r.lateral_offset_ref_m,
                  r.heading_error_rad, r.heading_ref_rad, r.linear_velocity_mps] for r in refs],
        "states": [[s.header.stamp.to_sec(), s.state, s.last_event, s.signal] for s in states],
        "markers": [[m.header.frame_id, m.type, m.text, m.pose.position.z] for m in markers],
    }))


if __name__ == "__main__":
    main()
