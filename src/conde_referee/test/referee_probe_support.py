"""Helpers of the referee's system test."""
import subprocess


def conde_urdf():
    """Conde's URDF (xacro of conde_description)."""
    share = subprocess.run(["rospack", "find", "conde_description"], capture_output=True, text=True,
                           check=True).stdout.strip()
    return subprocess.run(["xacro", share + "/robots/conde.urdf.xacro"], capture_output=True, text=True,
                          check=True).stdout
