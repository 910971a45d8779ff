"""Start-up and shutdown of the project's rospy nodes, one way for all of them.

    from conde_common import node_support

    node_support.init_node("conde_control", known_params=("config", "rate_hz"))
    ...                         # build the node; on bad configuration: node_support.fail("...")
    node_support.spin()         # until a signal, rosnode kill or rospy.signal_shutdown

- Private parameters are checked by name at start-up: a parameter the node does not know (a typo,
  a parameter of another node) stops it with "<node>: error: unknown parameter /<node>/<name>
  (known: ...)" and exit status 1, as conde_sim_node does for its plugins' keys.
- The node takes SIGINT and SIGTERM itself. rospy's own handler shuts ROS down inside the signal
  handler, on the main thread; a signal that lands while the main thread is inside rospy (a call
  to the master while a subscriber is made, a log line) deadlocks on the lock that call holds. The
  handler here only starts a thread that asks rospy to shut down, so the main thread finishes what
  it was doing and every wait that checks rospy.is_shutdown() ends.
"""
import os
import signal
import sys
import threading

_node_name = None


def unknown_private_params(param_names, node_name, known_params):
    """The private parameters of `node_name` (fully resolved, e.g. "/conde_control") among
    `param_names` (the master's list) whose first name element is not in `known_params`,
    sorted, as full names."""
    prefix = node_name.rstrip("/") + "/"
    known = set(known_params)
    unknown = set()
    for name in param_names:
        if name.startswith(prefix):
            first = name[len(prefix):].split("/")[0]
            if first not in known:
                unknown.add(prefix + first)
    return sorted(unknown)


def unknown_params_message(unknown, known_params):
    """The error line for unknown private parameters (without the "<node>: error: " prefix)."""
    known = ", ".join(sorted(known_params)) or "none"
    plural = "s" if len(unknown) > 1 else ""
    return "unknown parameter%s %s (known: %s)" % (plural, ", ".join(unknown), known)


def fail(message, status=1):
    """Ends a node that cannot go on: "<node>: error: <message>" on stderr, ROS shut down, exit
    status `status` (1 by default)."""
    name = _node_name or os.path.basename(sys.argv[0])  # before init: the script's name
    sys.stderr.write("%s: error: %s\n" % (name, message))
    sys.stderr.flush()
    import rospy  # here: the pure functions above need no ROS

    if rospy.core.is_initialized():
        rospy.signal_shutdown("error: " + message)
    sys.exit(status)


def _shut_down_on(signum, _frame):
    reason = "signal %s" % signal.Signals(signum).name
    import rospy

    threading.Thread(target=rospy.signal_shutdown, args=(reason,), name="shutdown", daemon=True).start()


def init_node(name, known_params, program=None, **init_args):
    """rospy.init_node(name) with the node's own SIGINT/SIGTERM handling, then the check of its
    private parameters against `known_params` (names without "~"). Exits through fail() on an
    unknown one. `program` names the node in error lines when that is not its ROS name."""
    import rospy

    rospy.init_node(name, disable_signals=True, **init_args)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, _shut_down_on)
    check_private_params(program or name, known_params)


def check_private_params(program, known_params):
    """For a node that was initialised by itself (one that handles its signals otherwise, as the
    teleops, which stop the robot first): exits through fail() on a private parameter not in
    `known_params`. `program` names the node in error lines."""
    global _node_name
    import rospy

    _node_name = program
    unknown = unknown_private_params(rospy.get_param_names(), rospy.get_name(), known_params)
    if unknown:
        fail(unknown_params_message(unknown, known_params))


def spin():
    """Waits on the main thread until ROS shuts down (a signal, rosnode kill, signal_shutdown)."""
    import rospy

    while not rospy.core.is_shutdown():
        rospy.rostime.wallsleep(0.1)


def synchronous_publisher(topic, data_class, **kwargs):
    """A rospy.Publisher whose publish() writes to every subscriber before it returns (rospy's
    queue_size=None), instead of handing the message to a thread per connection. In lock-step the
    simulator steps on once it has an answer; a publisher thread can then still hold the copy for
    another subscriber (the control node) while simulated time goes on, so that which messages it
    has at a given simulated instant would depend on the machine's load."""
    import warnings

    import rospy

    with warnings.catch_warnings():  # rospy warns about queue_size=None, which is the point here
        warnings.simplefilter("ignore", SyntaxWarning)
        return rospy.Publisher(topic, data_class, queue_size=None, **kwargs)
