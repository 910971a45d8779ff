"""SignReporter: when a recognised sign is reported."""
from types import SimpleNamespace

import pytest

from conde_traffic_sign.sign_reporter import SignReporter


def seen(*names, distance_m=1.0):
    return [SimpleNamespace(name=n, distance_m=distance_m) for n in names]


def test_reported_once_after_confirm_frames_in_a_row():
    r = SignReporter(confirm_frames=3)
    assert r.update(0.0, seen("cattle")) == []
    assert r.update(0.1, seen("cattle")) == []
    assert r.update(0.2, seen("cattle")) == ["cattle"]
    assert [r.update(0.3 + 0.1 * k, seen("cattle")) for k in range(5)] == [[]] * 5


def test_a_gap_restarts_the_count_and_far_signs_do_not_count():
    r = SignReporter(confirm_frames=2, report_distance_m=1.5)
    assert r.update(0.0, seen("buses")) == []
    assert r.update(0.1, []) == []
    assert r.update(0.2, seen("buses")) == []
    assert r.update(0.3, seen("buses", distance_m=2.0)) == []
    assert r.update(0.4, seen("buses")) == []
    assert r.update(0.5, seen("buses")) == ["buses"]


def test_never_again_by_default_and_again_after_a_new_passing_when_asked():
    once = SignReporter(confirm_frames=1)
    assert once.update(0.0, seen("parking")) == ["parking"]
    assert once.update(100.0, seen("parking")) == []
    again = SignReporter(confirm_frames=1, repeat_after_s=5.0)
    assert again.update(0.0, seen("parking")) == ["parking"]
    assert again.update(4.0, seen("parking")) == []      # still in sight: the same passing
    assert again.update(8.0, seen("parking")) == []      # 4 s since last seen
    assert again.update(20.0, seen("parking")) == ["parking"]


@pytest.mark.parametrize("kwargs, message", [
    ({"confirm_frames": 0}, "confirm_frames must be >= 1, got 0"),
    ({"report_distance_m": 0.0}, "report_distance_m must be > 0, got 0.0"),
    ({"repeat_after_s": -1.0}, "repeat_after_s must be >= 0, got -1.0"),
])
def test_bad_parameters_are_named(kwargs, message):
    with pytest.raises(ValueError) as error:
        SignReporter(**kwargs)
    assert str(error.value) == message
