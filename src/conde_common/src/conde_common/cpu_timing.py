"""CPU time of a node's main callback per frame, and the timing line the benchmarks read:

    "<node>: timing: <N> frames, mean <A> ms, max <B> ms CPU per frame"

Callbacks measure themselves with time.thread_time() (the calling thread's CPU time, waits not
counted) and add() it; the line is logged every `log_period_s` of wall time (the simulation may be
paused) and once at shutdown."""
import threading
import time


class CpuTiming:
    def __init__(self, node_name, log_period_s=30.0, log=None):
        """log(line): where the line goes (default: rospy.loginfo, and once more at shutdown)."""
        self.node_name = node_name
        self.log_period_s = log_period_s
        self.frames, self.total_s, self.max_s = 0, 0.0, 0.0
        self._lock = threading.Lock()
        self._logged_wall_s = time.monotonic()
        if log is None:
            import rospy  # here: the timing itself needs no ROS

            log = rospy.loginfo
            rospy.on_shutdown(self.log)
        self._log = log

    def add(self, cpu_s):
        with self._lock:
            self.frames += 1
            self.total_s += cpu_s
            self.max_s = max(self.max_s, cpu_s)
            due = time.monotonic() - self._logged_wall_s >= self.log_period_s
        if due:
            self.log()

    def line(self):
        with self._lock:
            mean_ms = 1e3 * self.total_s / self.frames if self.frames else 0.0
            return "%s: timing: %d frames, mean %.2f ms, max %.2f ms CPU per frame" % (
                self.node_name, self.frames, mean_ms, 1e3 * self.max_s)

    def log(self):
        self._logged_wall_s = time.monotonic()
        self._log(self.line())
