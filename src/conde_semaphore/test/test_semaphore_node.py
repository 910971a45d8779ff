"""The conde_semaphore node against a real roscore on a free loopback port: rendered top-camera
images in, debounced /conde_signal out (rgb8 and bgr8, stamps passed through), the warning for
an unsupported encoding and the "waiting for images" log, both read from /rosout; the CPU timing
line the node prints at shutdown.

Needs the built workspace: `source devel/setup.bash` (the node is started with rosrun)."""
import os
import re
import signal
import subprocess
import time

import cv2
import pytest

try:
    import rospy
    from conde_msgs.msg import PanelSignal
    from rosgraph_msgs.msg import Log
    from sensor_msgs.msg import Image
except ImportError as error:
    raise ImportError("%s: build the workspace and source devel/setup.bash first" % error) from None

from conde_semaphore.panel_classifier import SIGNAL_CODES
from conde_testing.ros_harness import Roscore, TopicLog, joined_as_node, stop_process, wait_until

IMAGES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "images")
IMAGE_TOPIC = "/conde_camera_signalling_panel/image_raw"
TIMEOUT_S = 60.0  # generous: the machine may be busy
TIMING_LINE = re.compile(r"conde_semaphore: timing: (\d+) frames, "
                         r"mean (\d+\.\d\d) ms, max (\d+\.\d\d) ms CPU per frame")


@pytest.fixture(scope="module")
def ros():
    """roscore on a free port, this process as a ROS node, and conde_semaphore started by rosrun;
    yields (image publisher, /conde_signal log, /rosout log)."""
    with Roscore("conde_semaphore") as core, joined_as_node(core.uri, "conde_semaphore_test"):
        rosout = TopicLog("/rosout", Log)
        signals = TopicLog("/conde_signal", PanelSignal)
        publisher = rospy.Publisher(IMAGE_TOPIC, Image, queue_size=10)
        node = subprocess.Popen(["rosrun", "conde_semaphore", "conde_semaphore"], env=core.env,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        try:
            wait_until(lambda: publisher.get_num_connections() > 0 and signals.subscriber.get_num_connections() > 0,
                       "conde_semaphore to connect")
            yield publisher, signals, rosout
        finally:
            stop_process(node, group=True)


def image_message(file_name, encoding, stamp_s):
    bgr = cv2.imread(os.path.join(IMAGES_DIR, file_name), cv2.IMREAD_COLOR)
    assert bgr is not None, file_name
    pixels = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB) if encoding == "rgb8" else bgr
    msg = Image(height=pixels.shape[0], width=pixels.shape[1], encoding=encoding, step=pixels.shape[1] * 3,
                data=pixels.tobytes())
    msg.header.stamp = rospy.Time.from_sec(stamp_s)
    msg.header.frame_id = "camera_signalling_panel_optical"
    return msg


def publish_until(publisher, signals, msg_for_stamp, expected_code, first_stamp_s):
    """Publishes images (stamps first_stamp_s + k) until /conde_signal carries expected_code for one
    of them; returns (that message, {stamp: index} of the images sent)."""
    sent = {}
    deadline = time.monotonic() + TIMEOUT_S
    k = 0
    while time.monotonic() < deadline:
        stamp_s = first_stamp_s + k
        publisher.publish(msg_for_stamp(stamp_s))
        sent[round(stamp_s, 3)] = k
        k += 1
        time.sleep(0.1)
        for msg in signals.snapshot():
            if msg.signal == expected_code and round(msg.header.stamp.to_sec(), 3) in sent:
                return msg, sent
    raise AssertionError("no /conde_signal %d after %d images" % (expected_code, k))


def test_waiting_for_images_is_logged(ros):
    _, _, rosout = ros
    wait_until(lambda: any(m.name == "/conde_semaphore" and m.msg == "conde_semaphore: waiting for images on "
                           + IMAGE_TOPIC for m in rosout.snapshot()), "the waiting message on /rosout")


@pytest.mark.parametrize("signal_name, encoding", [
    ("stop", "rgb8"), ("left", "bgr8"), ("right", "rgb8"), ("forward", "rgb8"),
    ("end_of_trial", "bgr8"), ("parking", "rgb8"), ("none", "rgb8")])
def test_rendered_images_give_the_signal(ros, signal_name, encoding):
    publisher, signals, rosout = ros
    first_stamp_s = 1000.0 * (1 + list(SIGNAL_CODES).index(signal_name)) + (0.5 if encoding == "bgr8" else 0.0)
    msg, sent = publish_until(publisher, signals, lambda s: image_message(signal_name + "_1.png", encoding, s),
                              SIGNAL_CODES[signal_name], first_stamp_s)
    # Debounced: the first image of the new signal cannot have been reported yet.
    assert sent[round(msg.header.stamp.to_sec(), 3)] >= 2
    assert msg.header.frame_id == "camera_signalling_panel_optical"
    assert 0.5 <= msg.confidence <= 1.0
    wait_until(lambda: any(m.name == "/conde_semaphore" and "-> %s (confidence" % signal_name in m.msg
                           for m in rosout.snapshot()), "the change to be logged")


def test_unsupported_encoding_is_ignored_with_a_warning(ros):
    publisher, signals, rosout = ros
    # Establish a known signal first, then send mono8 images: they change nothing.
    publish_until(publisher, signals, lambda s: image_message("parking_0.png", "rgb8", s),
                  SIGNAL_CODES["parking"], 9000.0)
    count_before = len(signals.snapshot())
    for k in range(5):
        msg = Image(height=240, width=320, encoding="mono8", step=320, data=bytes(320 * 240))
        msg.header.stamp = rospy.Time.from_sec(9500.0 + k)
        publisher.publish(msg)
        time.sleep(0.1)
    expected = ("conde_semaphore: ignoring images on %s: encoding 'mono8' is not supported "
                "(expected rgb8 or bgr8)" % IMAGE_TOPIC)
    wait_until(lambda: any(m.level == Log.WARN and m.msg == expected for m in rosout.snapshot()),
               "the encoding warning on /rosout")
    assert all(m.header.stamp.to_sec() < 9500.0 for m in signals.snapshot()[count_before:])


def test_truncated_image_is_ignored_with_a_warning(ros):
    publisher, _, rosout = ros
    msg = Image(height=240, width=320, encoding="rgb8", step=960, data=bytes(960 * 100))
    for _ in range(3):
        publisher.publish(msg)
        time.sleep(0.1)
    expected = ("conde_semaphore: ignoring images on %s: size does not match the data: 320 x 240 px, "
                "step 960, 96000 bytes" % IMAGE_TOPIC)
    # The warning is throttled (5 s): the mono8 one may hide this one for that long.
    deadline = time.monotonic() + TIMEOUT_S
    while not any(m.msg == expected for m in rosout.snapshot()):
        assert time.monotonic() < deadline, "timed out waiting for the size warning on /rosout"
        publisher.publish(msg)
        time.sleep(0.5)


def test_cpu_timing_is_logged_at_shutdown(ros):
    """A second instance of the node on its own image topic (so that the shared one keeps running):
    images until it publishes a signal, then SIGINT; its stdout has the timing line. Before its
    debouncer has settled it answers each image with NONE (confidence 0)."""
    _, signals, _ = ros
    topic = "/conde_semaphore_timing_test/image_raw"
    publisher = rospy.Publisher(topic, Image, queue_size=10)
    node = subprocess.Popen(["rosrun", "conde_semaphore", "conde_semaphore", "__name:=conde_semaphore_timing_test",
                             "_image_topic:=" + topic], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            start_new_session=True)
    try:
        wait_until(lambda: publisher.get_num_connections() > 0 and signals.subscriber.get_num_connections() > 1,
                   "the second conde_semaphore to connect")  # its /conde_signal too: no answer missed
        first_stop, _ = publish_until(publisher, signals, lambda s: image_message("stop_1.png", "rgb8", s),
                                      SIGNAL_CODES["stop"], 20000.0)
    finally:
        os.killpg(node.pid, signal.SIGINT)
        log = node.communicate(timeout=60)[0]
        publisher.unregister()
    timing = TIMING_LINE.findall(log)
    assert timing, "no timing line in the node's output:\n" + log
    frames, mean_ms, max_ms = timing[-1]
    # The debouncer needs 3 images before the first signal; the two before it are answered with NONE.
    assert int(frames) >= 3 and 0.0 < float(mean_ms) <= float(max_ms), timing[-1]
    first_stop_s = first_stop.header.stamp.to_sec()
    before = [m for m in signals.snapshot() if 20000.0 <= m.header.stamp.to_sec() < first_stop_s]
    assert [(m.signal, m.confidence) for m in before] == [(PanelSignal.NONE, 0.0)] * 2, before
