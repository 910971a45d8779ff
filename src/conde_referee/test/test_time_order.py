"""TimeOrder: inputs of several topics handed on in simulated-time order, whatever their arrival."""
import math

import pytest

from arrival_orders import arrivals
from conde_referee.time_order import TimeOrder, judging_due, progress_mark


def judged_in_order(order, inputs):
    """(what the order hands on, in sequence, from the inputs in their arrival order; how many came late)."""
    out, late = [], 0
    for stamp, rank, item in inputs:
        late += order.late(stamp)
        order.push(stamp, rank, item)
        out += order.release()
    return out + order.flush(), late


def test_released_in_time_order_once_old_enough():
    order = TimeOrder(lag_s=0.1)
    order.push(0.02, 1, "contacts 0.02")
    order.push(0.04, 0, "odom 0.04")
    order.push(0.02, 0, "odom 0.02")  # arrived after the contacts of its step and a later odom
    assert order.release() == []  # newest 0.04: nothing is 0.1 s older yet
    order.push(0.12, 0, "odom 0.12")
    assert order.release() == [(0.02, "odom 0.02"), (0.02, "contacts 0.02")]  # rank orders equal stamps
    order.push(0.14, 0, "odom 0.14")
    assert order.release() == [(0.04, "odom 0.04")]
    assert order.flush() == [(0.12, "odom 0.12"), (0.14, "odom 0.14")]
    assert len(order) == 0


def test_equal_stamp_and_rank_keep_their_arrival_order():
    order = TimeOrder(lag_s=0.0)
    order.push(1.0, 2, "a")
    order.push(1.0, 2, "b")
    assert order.release() == [(1.0, "a"), (1.0, "b")]


def test_any_arrival_order_gives_the_same_sequence():
    # Three topics of one simulated run: each in order on its own connection, interleaved at random.
    streams = [[(0.02 * k, 0, "odom%d" % k) for k in range(50)],
               [(0.02 * k, 1, "contacts%d" % k) for k in range(50)],
               [(0.01 * k, 2, "poses%d" % k) for k in range(100)]]
    results = []
    for seed in range(20):
        # a connection may run up to 0.06 s ahead of the others (within the lag)
        out, _ = judged_in_order(TimeOrder(lag_s=0.1), arrivals(streams, seed, skew_s=0.06))
        results.append(out)
    assert all(r == results[0] for r in results)
    assert [t for t, _ in results[0]] == sorted(t for t, _ in results[0])


def test_late_input_is_recognised():
    order = TimeOrder(lag_s=0.1)
    order.push(0.5, 0, "x")
    order.push(0.7, 0, "y")
    order.release()
    assert order.late(0.4) and not order.late(0.5) and not order.late(0.6)


@pytest.mark.parametrize("lag", [-0.1, math.nan, math.inf, "0.1"])
def test_bad_lag_is_refused(lag):
    with pytest.raises(ValueError, match="lag_s must be a finite number >= 0"):
        TimeOrder(lag_s=lag)


def test_judging_due_on_a_grid_of_simulated_time():
    assert judging_due(0.01, None, 0.1)
    stamps = [round(0.01 * k, 2) for k in range(1, 40)]
    judged, last = [], None
    for t in stamps:
        if judging_due(t, last, 0.1):
            judged.append(t)
            last = t
    assert judged == [0.01, 0.1, 0.2, 0.3]
    # the same grid whatever the first stamp
    judged, last = [], None
    for t in stamps[4:]:
        if judging_due(t, last, 0.1):
            judged.append(t)
            last = t
    assert judged == [0.05, 0.1, 0.2, 0.3]


def test_progress_marks_once_per_period_of_released_time():
    assert progress_mark(-math.inf, None, 0.1) is None  # nothing judged yet
    assert progress_mark(0.02, None, 0.1) == 0.02  # the first mark
    assert progress_mark(0.08, 0.02, 0.1) is None  # the same period
    assert progress_mark(0.1, 0.02, 0.1) == 0.1  # a new period begins
    assert progress_mark(0.1, 0.1, 0.1) is None  # nothing new
    assert progress_mark(0.37, 0.1, 0.1) == 0.37  # periods skipped: one mark at the newest
    assert progress_mark(0.2, 0.37, 0.1) is None  # never backwards


def test_progress_marks_follow_the_released_inputs():
    order, marks, last = TimeOrder(lag_s=0.1), [], None
    for k in range(1, 31):  # odometry every 0.02 s
        order.push(0.02 * k, 0, k)
        order.release()
        mark = progress_mark(order.released_until_s, last, 0.1)
        if mark is not None:
            marks.append(round(mark, 6))
            last = mark
    # released up to 0.6 - 0.1 = 0.5 s: one mark per 0.1 s of judged time, each an input's stamp
    assert marks == [0.02, 0.1, 0.2, 0.3, 0.4, 0.5]


def test_a_regular_stream_that_falls_behind_holds_the_release():
    # Odometry every 0.02 s is regular; the object poses (every 0.1 s) run 0.5 s ahead of it, as when
    # the odometry's connection falls behind on a busy machine. Nothing comes out of order.
    order = TimeOrder(lag_s=0.1, regular_ranks=(0,))
    order.push(0.0, 0, "odom 0.00")
    order.push(0.02, 0, "odom 0.02")
    for k in range(1, 6):
        order.push(0.1 * k, 3, "poses %.1f" % (0.1 * k))
    # odometry's next is due at 0.04: only what is earlier goes
    assert order.release() == [(0.0, "odom 0.00"), (0.02, "odom 0.02")]
    order.push(0.04, 0, "odom 0.04")
    order.push(0.06, 0, "odom 0.06")
    order.push(0.08, 0, "odom 0.08")
    assert order.release() == [(0.04, "odom 0.04"), (0.06, "odom 0.06"), (0.08, "odom 0.08")]
    order.push(0.1, 0, "odom 0.10")
    # equal stamps: the odometry (rank 0) before the poses (rank 3)
    assert order.release() == [(0.1, "odom 0.10"), (0.1, "poses 0.1")]
    assert not order.late(0.12)
    # Without the regular stream the poses would have been handed on first and odometry come late.
    loose = TimeOrder(lag_s=0.1)
    loose.push(0.0, 0, "odom 0.00")
    for k in range(1, 6):
        loose.push(0.1 * k, 3, "poses %.1f" % (0.1 * k))
    loose.release()
    assert loose.late(0.02)


def test_a_regular_stream_that_stopped_holds_nothing():
    order = TimeOrder(lag_s=0.1, regular_ranks=(0, 2), stopped_after_s=1.0)
    order.push(0.0, 2, "contacts 0.0")
    order.push(0.02, 2, "contacts 0.02")  # the contacts end here
    for k in range(0, 60):
        order.push(0.02 * k, 0, "odom %d" % k)
    # odometry at 1.18 s: the contacts are 1.16 s behind, stopped; odometry's next is due at 1.20
    released = order.release()
    assert released[-1] == (pytest.approx(1.08), "odom 54")  # the lag (0.1 s) bounds it
    assert len(order) == 5
    # within stopped_after_s a silent regular stream holds everything after its next stamp
    held = TimeOrder(lag_s=0.1, regular_ranks=(0, 2), stopped_after_s=1.0)
    held.push(0.0, 2, "contacts 0.0")
    held.push(0.02, 2, "contacts 0.02")
    for k in range(0, 40):
        held.push(0.02 * k, 0, "odom %d" % k)
    assert held.release()[-1] == (pytest.approx(0.02), "contacts 0.02")


def test_arrival_order_with_a_lagging_regular_stream_gives_the_same_sequence():
    # As test_any_arrival_order_gives_the_same_sequence, but a connection may run up to 0.5 s ahead
    # (five times the lag): with every stream regular the sequence is still the same.
    streams = [[(0.02 * k, 0, "odom%d" % k) for k in range(100)],
               [(0.02 * k, 2, "contacts%d" % k) for k in range(100)],
               [(0.1 * k, 3, "poses%d" % k) for k in range(20)]]
    results = []
    for seed in range(20):
        out, late = judged_in_order(TimeOrder(lag_s=0.1, regular_ranks=(0, 2, 3)), arrivals(streams, seed, skew_s=0.5))
        assert late == 0
        results.append(out)
    assert all(r == results[0] for r in results)
    assert [t for t, _ in results[0]] == sorted(t for t, _ in results[0])


def test_a_regular_stream_not_seen_yet_holds_everything_for_a_while():
    order = TimeOrder(lag_s=0.1, regular_ranks=(0, 2), stopped_after_s=1.0)
    for k in range(0, 50):  # odometry from 0 to 0.98 s, no contacts yet
        order.push(0.02 * k, 0, "odom %d" % k)
    assert order.release() == []
    order.push(0.5, 2, "contacts 0.5")  # the contacts begin later than the odometry
    assert order.release()[-1] == (pytest.approx(0.5), "contacts 0.5")
    # a stream that never begins holds nothing once the newest is stopped_after_s past the first
    never = TimeOrder(lag_s=0.1, regular_ranks=(0, 2), stopped_after_s=1.0)
    for k in range(0, 52):  # to 1.02 s
        never.push(0.02 * k, 0, "odom %d" % k)
    assert never.release()[-1] == (pytest.approx(0.92), "odom 46")


def test_an_early_irregular_input_does_not_end_the_wait_for_a_regular_stream():
    # A sign report taken at time 0 (unstamped, before any stamp was seen), then odometry from 50 s:
    # the contacts (regular, not seen yet) still hold the release for stopped_after_s of odometry.
    order = TimeOrder(lag_s=0.1, regular_ranks=(0, 2), stopped_after_s=1.0)
    order.push(0.0, 4, "sign")
    for k in range(0, 10):
        order.push(50.0 + 0.02 * k, 0, "odom %d" % k)
    assert order.release() == []
    order.push(50.1, 2, "contacts 50.1")
    assert [item for _, item in order.release()][:2] == ["sign", "odom 0"]
