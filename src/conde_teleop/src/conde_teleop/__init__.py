"""conde_teleop: keyboard teleop for the Conde robot (key map and terminal input, both ROS-free)."""
