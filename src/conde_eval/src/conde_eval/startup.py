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


def static_transforms_out(system_state, senders, sim_name, topic="/tf_static"):
    """True once at least one node other than the simulator (sim_name) publishes `topic` and each of
    them has sent a message (senders: the caller ids whose message has come; /tf_static is latched,
    so a message sent before the subscription still comes). The lock-step pre-roll steps until
    then: robot_state_publisher's fixed transforms come from a one-shot timer on simulated time. The
    simulator is left out: it sends its cameras' optical frames when it loads them, before any
    step, and advertises the topic even when it has none to send."""
    publishers = {t: set(nodes) for t, nodes in system_state[0]}.get(topic, set()) - {sim_name}
    return bool(publishers) and publishers <= set(senders)


def lockstep_links_missing(config, sim_name, system_state, bus_info):
    """What the simulator (node sim_name) still lacks before a lock-step run can start the same way
    every time: for each rule of the lock-step config ({rules: [{answer, inputs}]}, names relative to
    the simulator's namespace), a connection from every publisher of the answer topic and to every
    subscriber of each input (/clock aside: every node has it). bus_info: the simulator's
    getBusInfo() rows [id, peer, direction 'i'|'o', transport, topic, ...]. Returns "topic: why"
    strings, sorted; empty when every link is up. An input the simulator does not publish itself
    (a chain: /conde_lane answers the cameras and is the input of the decision) needs a connection
    from its publishers, as an answer. A node that subscribes to its camera only after
    its start-up (conde_tracking waits for CameraInfo and TF) thus holds the start. A rule with
    wait_for_first_answer false whose answer has no publisher at all is left out (its node is not
    part of this run, and the simulator owes it nothing until it answers), and so is an input that
    no node publishes or subscribes to (V1's sign camera on a robot built without it)."""
    namespace = sim_name.rsplit("/", 1)[0] + "/"
    publishers, subscribers, _services = system_state
    own = {topic for topic, nodes in publishers if sim_name in nodes}
    pubs = {topic: set(nodes) - {sim_name} for topic, nodes in publishers}
    subs = {topic: set(nodes) - {sim_name} for topic, nodes in subscribers}
    links = {}
    for row in bus_info:
        if len(row) >= 5 and (len(row) < 6 or row[5]):
            links[(row[2], row[4])] = links.get((row[2], row[4]), 0) + 1
    missing = set()

    def check_publishers(topic):
        if not pubs.get(topic):
            missing.add(f"{topic}: no publisher yet")
        elif links.get(("i", topic), 0) < len(pubs[topic]):
            missing.add(f"{topic}: not connected to its publisher yet")

    for rule in config.get("rules", []):
        if rule.get("wait_for_first_answer", True) is False and not pubs.get(resolve(rule["answer"], namespace)):
            continue  # owes nothing before its first answer: a node this run does not start (V1's signs)
        check_publishers(resolve(rule["answer"], namespace))
        for name in rule.get("inputs", []):
            topic = resolve(name, namespace)
            if topic == "/clock":
                continue
            if topic not in own:
                if not pubs.get(topic) and not subs.get(topic):
                    continue  # nobody publishes or listens (a camera this robot does not have): owes nothing
                check_publishers(topic)
            elif not subs.get(topic):
                missing.add(f"{topic}: no subscriber yet")
            elif links.get(("o", topic), 0) < len(subs[topic]):
                missing.add(f"{topic}: not connected to its subscribers yet")
    return sorted(missing)


def resolve(name, namespace):
    """A topic name relative to namespace ('/' or '/robot1/'), made global."""
    return name if name.startswith("/") else namespace + name
