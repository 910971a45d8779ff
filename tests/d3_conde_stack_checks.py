#!/usr/bin/env python3
"""Checks of d3_conde_stack.test: waits (wall clock, bounded) for the referee's report of the D3 run
and asserts its result: two laps, not disqualified, zero penalties, no object displaced."""
import json
import time
import unittest

import rospy
import rostest
from std_msgs.msg import String

REPORT_TOPIC = "/conde_referee/report"
WAIT_S = 1500.0  # wall clock: the lock-step run's speed depends on the machine's load


class D3CondeStackTest(unittest.TestCase):
    def test_two_laps_without_penalty(self):
        rospy.init_node("d3_conde_stack_test")
        reports = []
        rospy.Subscriber(REPORT_TOPIC, String, lambda m: reports.append(json.loads(m.data)))
        deadline = time.monotonic() + WAIT_S
        while not reports and time.monotonic() < deadline and not rospy.is_shutdown():
            time.sleep(0.5)
        self.assertTrue(reports, "no referee report on %s within %g s of wall time" % (REPORT_TOPIC, WAIT_S))
        report = reports[-1]
        events = [(e["kind"], e["t_s"], e["detail"]) for e in report["events"] if e.get("penalty", 0) > 0]
        self.assertFalse(report["disqualified"], report["end"])
        self.assertEqual(report["laps"], 2, report["end"])
        self.assertEqual(report["penalty_total"], 0.0, events)
        self.assertEqual(report["objects_displaced_m"], {})


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "d3_conde_stack", D3CondeStackTest)
