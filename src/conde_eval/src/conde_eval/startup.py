"""Which nodes of a launch are up: the pure part of start_when_ready.

roslaunch names each process it starts '<namespace>/<node name>-<counter>'; a node is up once it
has registered a topic of its own with the master (a publication or a subscription other than
/rosout and /clock, which rospy sets up inside init_node, before the node's own set-up).
"""

# Topics every rospy/roscpp node registers during initialisation, before its own set-up.
INIT_TOPICS = frozenset(("/rosout", "/clock"))
# Processes roslaunch runs that are not nodes of the launch file ('roslaunch -p' starts a master).
CORE_PROCESSES = frozenset(("master",))


def node_name_of_process(process_name):
    """'robot1/conde_tracking-12' -> '/robot1/conde_tracking' (roslaunch's process naming)."""
    base, sep, counter = process_name.rpartition("-")
    if not sep or not counter.isdigit() or not base:
        raise ValueError(f"'{process_name}' is not a roslaunch process name (<node>-<counter>)")
    return "/" + base.lstrip("/")


def registrations(system_state):
    """Master's getSystemState() -> {node: set of topics it publishes or subscribes to}, without
    the topics every node registers during initialisation."""
    publishers, subscribers, _services = system_state
    topics_of = {}
    for topic, nodes in list(publishers) + list(subscribers):
        for node in nodes:
            topics = topics_of.setdefault(node, set())
            if topic not in INIT_TOPICS:
                topics.add(topic)
    return topics_of


def nodes_not_up(expected_nodes, system_state):
    """The expected nodes that have not yet registered a topic of their own, sorted."""
    topics_of = registrations(system_state)
    return sorted(n for n in expected_nodes if not topics_of.get(n))


def graph_of(expected_nodes, system_state):
    """What the expected nodes have registered, comparable between two looks at the master."""
    topics_of = registrations(system_state)
    return {n: frozenset(topics_of.get(n, ())) for n in expected_nodes}
