"""Engine comparison beyond the seed paper, free of ROS: mechanical energy and linear momentum of
the robot's links from their states, and the slip of a support foot over one step.

Energy [J] = sum over links of m g z + m v^2 / 2 (rotational energy left out: the NAO's link
inertias are small, and at rest it is 0 either way); momentum [kg m/s] = |sum m v|. A robot lying
still should keep both constant (energy) and zero (momentum): what an engine adds or loses there
is its drift.
"""

import math
import xml.etree.ElementTree as ET

GRAVITY_M_S2 = 9.81


def link_masses(urdf_xml):
    """{link name: mass [kg]} of the URDF's links that have an inertial."""
    masses = {}
    for link in ET.fromstring(urdf_xml).findall('link'):
        mass = link.find('inertial/mass')
        if mass is not None and float(mass.get('value')) > 0:
            masses[link.get('name')] = float(mass.get('value'))
    return masses


def energy_and_momentum(states, masses):
    """(energy [J], momentum [kg m/s]) of {link: (position (x, y, z) [m], velocity (vx, vy, vz) [m/s])}."""
    energy, momentum = 0.0, [0.0, 0.0, 0.0]
    for name, (position, velocity) in states.items():
        m = masses[name]
        energy += m * GRAVITY_M_S2 * position[2] + 0.5 * m * sum(v * v for v in velocity)
        for i in range(3):
            momentum[i] += m * velocity[i]
    return energy, math.sqrt(sum(p * p for p in momentum))


def support_slips(step_sides, ankle_at):
    """Slip [m] of the support foot over each step: the horizontal distance its ankle moved from
    the step's start to its end. `step_sides` lists the swinging side per step ('L' | 'R');
    `ankle_at(i, side, end)` gives that ankle's (x, y) at the start (end=False) or end of step i."""
    slips = []
    for i, swing in enumerate(step_sides):
        support = 'R' if swing == 'L' else 'L'
        (x0, y0), (x1, y1) = ankle_at(i, support, False), ankle_at(i, support, True)
        slips.append(math.hypot(x1 - x0, y1 - y0))
    return slips
