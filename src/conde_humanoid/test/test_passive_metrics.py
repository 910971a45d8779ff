"""Energy, momentum and foot slip (conde_humanoid/passive_metrics.py)."""

import pytest

from conde_humanoid.passive_metrics import GRAVITY_M_S2, energy_and_momentum, link_masses, support_slips

URDF = """<robot name="r"><link name="base"/><link name="a"><inertial><mass value="2.0"/></inertial></link>
<link name="b"><inertial><mass value="0.5"/></inertial></link></robot>"""


def test_masses_come_from_the_links_with_an_inertial():
    assert link_masses(URDF) == {'a': 2.0, 'b': 0.5}


def test_energy_is_potential_plus_kinetic_and_momentum_the_vector_sum():
    states = {'a': ((0, 0, 1.0), (1.0, 0, 0)), 'b': ((5, 5, 0.0), (-4.0, 0, 0))}
    energy, momentum = energy_and_momentum(states, {'a': 2.0, 'b': 0.5})
    assert energy == pytest.approx(2.0 * GRAVITY_M_S2 + 0.5 * 2.0 + 0.5 * 0.5 * 16)
    assert momentum == pytest.approx(0.0)  # 2 kg at +1 m/s, 0.5 kg at -4 m/s


def test_slip_is_measured_on_the_support_foot():
    ankles = {(0, 'L', False): (0.0, 0.05), (0, 'L', True): (0.003, 0.05 + 0.004),
              (1, 'R', False): (0.04, -0.05), (1, 'R', True): (0.04, -0.05)}
    slips = support_slips(['R', 'L'], lambda i, side, end: ankles[(i, side, end)])
    assert slips == pytest.approx([0.005, 0.0])
