"""The cart-table preview controller (conde_humanoid/preview_control.py): its ZMP tracks a
stepping reference, and the CoM comes to rest over the last reference."""

import numpy as np
import pytest

from conde_humanoid.preview_control import PreviewController

DT_S = 0.01


def stepping_reference():
    """1 s at 0, then 0.5 s at +0.05 m and -0.05 m alternately (feet), then 2 s at 0."""
    ref = [0.0] * 100
    for i in range(8):
        ref += [0.05 if i % 2 == 0 else -0.05] * 50
    return np.array(ref + [0.0] * 200)


def test_gains_come_from_the_riccati_equation():
    c = PreviewController(0.28, DT_S)
    assert c.k.shape == (3,) and c.f.shape == (160,)
    assert np.all(np.abs(np.linalg.eigvals(c.a - c.b @ c.k[None, :])) < 1)  # the closed loop is stable
    assert abs(c.f[-1]) < 1e-3 * abs(c.f[0])  # the far future counts for little


def test_zmp_tracks_the_reference():
    ref = stepping_reference()
    com, zmp = PreviewController(0.28, DT_S).run(ref)
    error = np.abs(zmp - ref)
    assert error.max() < 0.05      # at the reference's 0.1 m jumps, which no CoM motion follows at once
    assert np.median(error) < 0.002
    assert com.max() < 0.05 and com.min() > -0.05  # the CoM sways less than the feet
    assert com[-1] == pytest.approx(0.0, abs=1e-3)


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError):
        PreviewController(0.0, DT_S)
