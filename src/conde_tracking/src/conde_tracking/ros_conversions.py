"""Small ROS message <-> numpy conversions (no rospy needed: plain message fields)."""
import numpy as np

#: encodings the lane measurement accepts, with their channel count
ENCODINGS = {"rgb8": 3, "bgr8": 3, "mono8": 1}


def image_to_array(msg):
    """sensor_msgs/Image (rgb8, bgr8 or mono8) -> (H, W) or (H, W, 3) uint8 array, RGB order."""
    channels = ENCODINGS.get(msg.encoding)
    if channels is None:
        raise ValueError(f"unsupported image encoding '{msg.encoding}' (expected one of: {', '.join(ENCODINGS)})")
    rows = np.frombuffer(msg.data, dtype=np.uint8).reshape(msg.height, msg.step)
    img = rows[:, :msg.width * channels].reshape(msg.height, msg.width, channels)
    if channels == 1:
        return img[:, :, 0].copy()
    return img[:, :, ::-1].copy() if msg.encoding == "bgr8" else img.copy()


def transform_to_matrix(transform):
    """geometry_msgs/Transform -> 4x4 homogeneous matrix."""
    t, q = transform.translation, transform.rotation
    x, y, z, w = q.x, q.y, q.z, q.w
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = (t.x, t.y, t.z)
    return T
