"""sensor_msgs/Image -> numpy, for the nodes (no ROS import: the message's plain fields)."""
import numpy as np

#: the encodings read here, with their channel count
CHANNELS = {"rgb8": 3, "bgr8": 3, "mono8": 1}


def image_view(msg, encodings=tuple(CHANNELS)):
    """(H x W x C uint8 view of the pixels, honouring the row step; the encoding) of an image in one
    of `encodings`; ValueError saying what is wrong with the encoding or the size otherwise."""
    if msg.encoding not in encodings or msg.encoding not in CHANNELS:
        raise ValueError("encoding %r is not supported (expected %s)" % (msg.encoding, " or ".join(encodings)))
    channels = CHANNELS[msg.encoding]
    if msg.width == 0 or msg.height == 0 or msg.step < channels * msg.width or len(msg.data) < msg.step * msg.height:
        raise ValueError("size does not match the data: %d x %d px, step %d, %d bytes"
                         % (msg.width, msg.height, msg.step, len(msg.data)))
    rows = np.frombuffer(msg.data, np.uint8)[:msg.step * msg.height].reshape(msg.height, msg.step)
    return rows[:, :channels * msg.width].reshape(msg.height, msg.width, channels), msg.encoding


def image_to_array(msg):
    """A copy of the pixels: H x W x 3 in RGB order for rgb8 and bgr8, H x W for mono8."""
    view, encoding = image_view(msg)
    if encoding == "mono8":
        return view[:, :, 0].copy()
    return view[:, :, ::-1].copy() if encoding == "bgr8" else view.copy()
