"""path_primitives: poses along segments and arcs, built from a pose, and chained into paths."""
import math

import numpy as np
import pytest

from conde_worlds.path_primitives import Arc, Path, Segment, boxes_overlap, points_box


def test_segment_from_pose():
    seg = Segment.from_pose(1.0, 2.0, math.pi / 2, 3.0)
    assert seg.length == pytest.approx(3.0) and seg.curvature == 0.0
    assert seg.point(1.5) == pytest.approx([1.0, 3.5])
    assert float(seg.heading(0.0)) == pytest.approx(math.pi / 2)
    s, lateral = seg.project([[0.5, 3.0]])
    assert s == pytest.approx([1.0]) and lateral == pytest.approx([0.5])  # left of a northbound line


@pytest.mark.parametrize("turn_rad, centre, end", [
    (math.pi / 2, (0.0, 2.0), (2.0, 2.0)),     # left: centre on the left, ends heading north
    (-math.pi / 2, (0.0, -2.0), (2.0, -2.0)),  # right
])
def test_arc_from_pose(turn_rad, centre, end):
    arc = Arc.from_pose(0.0, 0.0, 0.0, 2.0, turn_rad)
    assert arc.centre == pytest.approx(centre)
    assert arc.length == pytest.approx(math.pi) and arc.curvature == pytest.approx(math.copysign(0.5, turn_rad))
    assert arc.point(0.0) == pytest.approx([0.0, 0.0], abs=1e-12)
    assert float(arc.heading(0.0)) == pytest.approx(0.0)
    assert arc.point(arc.length) == pytest.approx(end)
    assert float(arc.heading(arc.length)) == pytest.approx(turn_rad)


def test_arc_project_and_offset():
    arc = Arc((0.0, 0.0), 1.0, 0.0, math.pi)  # counter-clockwise, upper half circle
    s, lateral = arc.project([[0.0, 0.5], [0.0, 2.0]])
    assert s == pytest.approx([math.pi / 2] * 2) and lateral == pytest.approx([0.5, -1.0])
    assert arc.offset(0.25).radius == 0.75  # to the left = toward the centre
    with pytest.raises(ValueError, match="collapses an arc"):
        arc.offset(1.0)


def test_chain_closes_a_rectangle_with_rounded_corners():
    pieces = [(4.0,), (1.0, math.pi / 2), (2.0,), (1.0, math.pi / 2)] * 2
    path = Path.chain(0.0, 0.0, 0.0, pieces)
    assert path.length == pytest.approx(2 * (4.0 + 2.0 + math.pi))
    assert path.point(path.length) == pytest.approx([0.0, 0.0], abs=1e-12)
    assert math.remainder(float(path.heading(path.length)), 2 * math.pi) == pytest.approx(0.0, abs=1e-12)
    i, along = path.locate(np.array([0.0, 4.0, 5.0, path.length]))
    assert list(i) == [0, 1, 1, 7] and along[2] == pytest.approx(1.0)
    assert path.point(4.0 + math.pi / 2) == pytest.approx([5.0, 1.0])  # end of the first corner


def test_reversed_and_mirrored_paths():
    path = Path([Segment((0.0, 0.0), (1.0, 0.0)), Arc((1.0, 1.0), 1.0, -math.pi / 2, math.pi / 2)])
    back = path.reversed()
    assert back.point(0.0) == pytest.approx(path.point(path.length))
    assert back.point(back.length) == pytest.approx([0.0, 0.0])
    assert path.mirrored_y().point(path.length) == pytest.approx([2.0, -1.0])


@pytest.mark.parametrize("prim", [Segment((1.0, -2.0), (4.0, 2.0)), Segment((0.0, 0.0), (0.0, -3.0)),
                                  Arc((0.5, 0.5), 2.0, 0.3, 2.5), Arc((-1.0, 2.0), 0.8, 4.0, -4.5)])
def test_box_holds_every_point_within_the_lateral_reach_of_the_s_range(prim):
    """box(s0, s1, lateral) is what lets callers skip a primitive: no point that project() puts in
    the s range and lateral reach may lie outside it, and a point far outside is outside."""
    rng = np.random.default_rng(5)
    s0, s1, lateral = -0.2 * prim.length, 0.7 * prim.length, 0.15
    x0, y0, x1, y1 = prim.box(s0, s1, lateral)
    pts = rng.uniform(-5.0, 5.0, size=(40000, 2))
    s, lat = prim.project(pts)
    inside = (s >= s0) & (s <= s1) & (np.abs(lat) <= lateral)
    assert inside.sum() > 100  # the check sees points near the primitive
    reach = pts[inside]
    assert np.all((reach[:, 0] >= x0) & (reach[:, 0] <= x1) & (reach[:, 1] >= y0) & (reach[:, 1] <= y1))
    assert not boxes_overlap((x0, y0, x1, y1), (x1 + 0.01, y0, x1 + 1.0, y1))
    assert boxes_overlap((x0, y0, x1, y1), points_box(reach))


def test_zero_length_segment_box_overlaps_nothing():
    """project() of a zero-length segment is NaN (no point is on it): its box overlaps no box."""
    box = Segment((1.0, 1.0), (1.0, 1.0)).box(0.0, 0.0, 0.1)
    assert not boxes_overlap(box, (-10.0, -10.0, 10.0, 10.0))
    assert points_box(np.array([[np.nan, 1.0], [2.0, 3.0], [0.5, np.inf]])) == (2.0, 3.0, 2.0, 3.0)
