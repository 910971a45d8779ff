"""Swing-foot trajectory of one step, free of ROS: the foot leaves and lands with zero velocity
and acceleration (quintic blend in x, y and yaw) and rises to the step height at mid-swing
(z = h (1 - cos 2 pi s) / 2, zero vertical velocity at lift-off and touch-down)."""

import math


def blend(s):
    """Quintic 0 -> 1 for s in [0, 1] with zero first and second derivatives at both ends."""
    s = min(1.0, max(0.0, s))
    return s * s * s * (10 - 15 * s + 6 * s * s)


def swing_pose(start, end, step_height_m, s):
    """(x, y, z [m], yaw [rad]) of the swing foot at phase `s` in [0, 1] between `start` and `end`
    (each (x, y, yaw)); z is the height above the ground."""
    b = blend(s)
    z = step_height_m * (1 - math.cos(2 * math.pi * min(1.0, max(0.0, s)))) / 2
    return (start[0] + b * (end[0] - start[0]), start[1] + b * (end[1] - start[1]), z,
            start[2] + b * (end[2] - start[2]))
