"""rate_limit: clamping, one step toward a target, and the rate limiter over time."""
import pytest

from conde_common.rate_limit import RateLimiter, approach, clamp, clip


def test_clamp_and_clip():
    assert clamp(5.0, -1.0, 2.0) == 2.0
    assert clamp(-5.0, -1.0, 2.0) == -1.0
    assert clamp(0.5, -1.0, 2.0) == 0.5
    assert clip(3.0, 1.5) == 1.5 and clip(-3.0, 1.5) == -1.5 and clip(0.2, 1.5) == 0.2


def test_approach_reaches_a_near_target_exactly():
    assert approach(0.0, 0.05, 0.1) == 0.05
    assert approach(1.0, 0.0, 0.25) == 0.75
    assert approach(0.0, -1.0, 0.25) == -0.25
    assert approach(0.3, 0.3, 0.0) == 0.3


def test_rate_limiter_ramps_at_its_rate_and_stops_at_the_target():
    limiter = RateLimiter(1.0)  # [unit/s]
    values = [limiter.step(0.5, 0.1) for _ in range(8)]
    assert values[:5] == pytest.approx([0.1, 0.2, 0.3, 0.4, 0.5])
    assert values[5:] == [0.5, 0.5, 0.5]
    assert limiter.step(-0.5, 0.25) == pytest.approx(0.25)
    assert limiter.step(0.0, 0.0) == pytest.approx(0.25)  # no time, no change
    limiter.reset()
    assert limiter.value == 0.0


@pytest.mark.parametrize("rate", [0.0, -1.0, float("inf"), float("nan")])
def test_bad_rate(rate):
    with pytest.raises(ValueError, match="max_rate_per_s must be finite and > 0, got"):
        RateLimiter(rate)


@pytest.mark.parametrize("dt_s", [-0.1, float("inf"), float("nan")])
def test_bad_time_step(dt_s):
    with pytest.raises(ValueError, match="dt_s must be finite and >= 0, got"):
        RateLimiter(1.0).step(1.0, dt_s)
