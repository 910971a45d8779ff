"""Pixels of a sensor_msgs/Image (rgb8 or bgr8) as a numpy array; no ROS import needed."""
import numpy as np

SUPPORTED_ENCODINGS = ("rgb8", "bgr8")


def image_array(msg):
    """(H x W x 3 uint8 view, is_bgr) of an rgb8/bgr8 image message, honouring its row step;
    ValueError saying what is wrong with the encoding or the size otherwise."""
    if msg.encoding not in SUPPORTED_ENCODINGS:
        raise ValueError("encoding %r is not supported (expected rgb8 or bgr8)" % (msg.encoding,))
    if msg.width == 0 or msg.height == 0 or msg.step < 3 * msg.width or len(msg.data) < msg.step * msg.height:
        raise ValueError("size does not match the data: %d x %d px, step %d, %d bytes"
                         % (msg.width, msg.height, msg.step, len(msg.data)))
    rows = np.frombuffer(msg.data, np.uint8)[:msg.step * msg.height].reshape(msg.height, msg.step)
    return rows[:, :3 * msg.width].reshape(msg.height, msg.width, 3), msg.encoding == "bgr8"


def rgb_array(msg):
    """RGB uint8 copy of an rgb8/bgr8 image message."""
    image, is_bgr = image_array(msg)
    return image[:, :, ::-1].copy() if is_bgr else image.copy()
