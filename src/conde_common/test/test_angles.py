import math

import numpy as np
import pytest

from conde_common.angles import wrap_rad


@pytest.mark.parametrize("angle, wrapped", [
    (0.0, 0.0), (0.5, 0.5), (-0.5, -0.5), (math.pi + 0.1, -math.pi + 0.1), (-math.pi - 0.1, math.pi - 0.1),
    (4.0 * math.pi + 0.2, 0.2), (-7.0 * math.pi, -math.pi), (math.pi, -math.pi),
])
def test_wrap(angle, wrapped):
    assert wrap_rad(angle) == pytest.approx(wrapped)


def test_wrap_is_element_wise_on_arrays():
    assert wrap_rad(np.array([0.1, 2.0 * math.pi + 0.1, -math.pi - 0.1])) == pytest.approx([0.1, 0.1, math.pi - 0.1])
