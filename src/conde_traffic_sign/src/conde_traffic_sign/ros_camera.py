"""A camera (the top camera unless told) as a sign_recognition.Camera: K and D from its CameraInfo,
its pose in the robot frame from TF (ROS plumbing shared by the node and the accuracy script)."""
import numpy as np
import rospy
import tf2_ros
from sensor_msgs.msg import CameraInfo

from conde_tracking.ros_conversions import transform_to_matrix
from conde_traffic_sign.sign_recognition import Camera

TOP_CAMERA_IMAGE = "/conde_camera_signalling_panel/image_raw"
TOP_CAMERA_INFO = "/conde_camera_signalling_panel/camera_info_top"
#: Conde's V1 sign camera (xacro arg sign_camera): 0.66 m behind the drive axle, 0.9 m high, turned 130 deg left
SIGN_CAMERA_IMAGE = "/conde_camera_signs_rear/image_raw"
SIGN_CAMERA_INFO = "/conde_camera_signs_rear/camera_info"
#: The cameras by name (the scripts' --camera): (image topic, CameraInfo topic)
CAMERAS = {"top": (TOP_CAMERA_IMAGE, TOP_CAMERA_INFO), "signs_rear": (SIGN_CAMERA_IMAGE, SIGN_CAMERA_INFO)}
ROBOT_FRAME = "base_footprint"


def camera_from_info(info, camera_to_base):
    return Camera(np.array(info.K, float).reshape(3, 3), np.array(info.D, float), camera_to_base)


def wait_for_camera(info_topic=TOP_CAMERA_INFO, robot_frame=ROBOT_FRAME, timeout_s=60.0, tf_buffer=None):
    """The camera once its CameraInfo and its pose in robot_frame are known; RuntimeError naming
    the topic or the frames otherwise.  While the simulation is paused, call this from a thread
    that keeps stepping it (or pass a tf_buffer filled already)."""
    try:
        info = rospy.wait_for_message(info_topic, CameraInfo, timeout=timeout_s)
    except rospy.ROSException:
        raise RuntimeError("no CameraInfo on %s within %.0f s" % (info_topic, timeout_s))
    if tf_buffer is None:
        tf_buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(tf_buffer)
    try:
        stamped = tf_buffer.lookup_transform(robot_frame, info.header.frame_id, rospy.Time(0),
                                             rospy.Duration(timeout_s))
    except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException) as e:
        raise RuntimeError("no transform %s -> %s: %s" % (robot_frame, info.header.frame_id, e))
    return camera_from_info(info, transform_to_matrix(stamped.transform))
