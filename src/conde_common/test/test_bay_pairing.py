"""conde_common.bay_pairing: the bays between the lines of the bay-parking area and which holds a box."""
import pytest

from conde_common.bay_pairing import BAY_WIDTH_M, pair_bays

BAY_M = 0.773  # on the competition track
SOUTH, DIVIDER, NORTH = 1.0, 1.0 + BAY_M, 1.0 + 2 * BAY_M  # the lines along the road [m]
BOX_INSET_M = 0.5 * (BAY_M - 0.6)  # a 0.6 m box in the middle of a bay begins this far into it


def test_neighbouring_lines_a_bay_apart_enclose_a_bay_twice_apart_two():
    assert pair_bays([SOUTH, DIVIDER, NORTH], []) == [(SOUTH, DIVIDER, False), (DIVIDER, NORTH, False)]
    assert pair_bays([NORTH, SOUTH], []) == [(SOUTH, pytest.approx(DIVIDER), False),
                                             (pytest.approx(DIVIDER), NORTH, False)]  # divider unseen
    assert pair_bays([SOUTH, SOUTH + 1.0], []) == []  # between one and two bays wide
    assert BAY_WIDTH_M[0] < BAY_M < BAY_WIDTH_M[1]


@pytest.mark.parametrize("error_m", [0.0, -0.25, 0.25])
@pytest.mark.parametrize("bay", [0, 1])
def test_a_box_counts_in_its_own_bay_only_even_seen_a_quarter_metre_off(bay, error_m):
    """The B2 failure mode: a box's near end seen short fell into the bay before it, and both bays
    counted as occupied."""
    near = SOUTH + bay * BAY_M + BOX_INSET_M + error_m
    for lines in ([SOUTH, DIVIDER, NORTH], [SOUTH, NORTH]):
        assert [b[2] for b in pair_bays(lines, [near])] == [bay == 0, bay == 1]


def test_a_box_beyond_the_bays_or_before_them_counts_in_none():
    assert [b[2] for b in pair_bays([SOUTH, DIVIDER, NORTH], [SOUTH - 1.0, NORTH + 0.1])] == [False, False]


def test_a_false_line_inside_a_bay_does_not_split_it():
    """B2 v1 on track seed 3 (order injected): the lines known were 1.58, 2.16 and 2.38 m along the
    road; 2.16 (too near either) had left no bay, and the robot gave up the bays."""
    assert pair_bays([1.58, 2.16, 2.38], [2.47]) == [(1.58, 2.38, False)]
    bays = pair_bays([1.58, 2.16, 2.38, 3.15], [2.47])
    assert [(a, b) for a, b, _ in bays] == [(1.58, 2.38), (2.38, 3.15)] and [b[2] for b in bays] == [False, True]
