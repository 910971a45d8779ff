"""Acknowledged delivery to the simulator: a node that publishes a command to a paused conde_sim
and then calls its ~step knows that the simulator received the command, and that its plugin
handled it, before the steps run (conde_sim's ~wait_for_messages, conde_msgs/WaitForMessages).
No wall-clock wait stands in for the delivery: the command takes effect in the first step.

    cmd = AcknowledgedPublisher(rospy.Publisher("/cmd_vel", Twist, queue_size=1))  # connected first
    cmd.send(twist)        # publishes, returns once the simulator has it
    step_service(20)

The simulator counts, per topic and publishing node, the messages it received since the first
request naming the topic; the publisher counts what it sent since its baseline (taken when it is
made). Take it before this node publishes anything unacknowledged on the topic: a message still in
flight at the baseline would count as a later one."""

import rospy

from conde_msgs.srv import WaitForMessages

TIMEOUT_S = 30.0  # wall time a message may take to reach the simulator on a slow, busy machine


class ReceivedCount:
    """The simulator's count of the messages on `topic` from the node `publisher` ("" = this node):
    wait(count) returns once it has received that many (and its plugins handled them), or raises
    RuntimeError naming the service, the topic and the counts after timeout_s of wall time. The
    first request (wait(0), the baseline) starts the simulator's count."""

    def __init__(self, topic, publisher="", sim_ns="/conde_sim", timeout_s=TIMEOUT_S):
        self.topic, self.publisher, self.timeout_s = topic, publisher, timeout_s
        self.service = sim_ns + "/wait_for_messages"
        rospy.wait_for_service(self.service, timeout=timeout_s)
        self._wait = rospy.ServiceProxy(self.service, WaitForMessages, persistent=True)

    def wait(self, count):
        """The simulator's answer once it has `count` messages (0: at once, the count so far)."""
        try:
            response = self._wait(self.topic, self.publisher, count, self.timeout_s)
        except rospy.ServiceException as e:
            raise RuntimeError(f"{self.service} ({self.topic}): {e}") from e
        if not response.success:
            raise RuntimeError(f"{self.service}: {response.message}")
        return response

    def close(self):
        """Closes the persistent connection to the service."""
        self._wait.close()


class AcknowledgedPublisher:
    """A publisher whose messages are acknowledged by the simulator `sim_ns` (its node name)."""

    def __init__(self, publisher, sim_ns="/conde_sim", timeout_s=TIMEOUT_S):
        self.publisher = publisher
        self.topic = publisher.resolved_name
        self.received = ReceivedCount(self.topic, "", sim_ns, timeout_s)
        self.sent = self.received.wait(0).received  # the baseline

    def publish(self, message):
        """Publishes without waiting (acknowledge() later: the simulator gets them in order)."""
        self.publisher.publish(message)
        self.sent += 1

    def acknowledge(self):
        """Returns once the simulator has every message published so far; RuntimeError naming the
        topic after timeout_s of wall time otherwise."""
        self.received.wait(self.sent)

    def send(self, message):
        self.publish(message)
        self.acknowledge()

    def close(self):
        """Closes the persistent connection to the service."""
        self.received.close()


def subscribes(node, topic):
    """True when the ROS master lists `node` among the subscribers of `topic`."""
    import rosgraph
    _, subscribers, _ = rosgraph.Master(rospy.get_name()).getSystemState()
    return any(name == topic and node in nodes for name, nodes in subscribers)
