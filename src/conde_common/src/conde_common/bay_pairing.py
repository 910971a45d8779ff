"""The bays of the bay-parking area from its lines across the road and the boxes seen in it: the
one rule conde_tracking (parking_area.bays_between, one frame) and conde_decision (parking.BayFinder,
sightings along the road) share.  Pure Python.

Positions are along the road [m] (ahead of the robot, or along its route), in one frame.
"""
from typing import List, Sequence, Tuple

#: Neighbouring bay lines this far apart along the road [m] enclose one bay (0.773 m on the
#: competition track); twice that apart, two bays (the dashed divider between is often unseen).
BAY_WIDTH_M = (0.6, 0.95)


def pair_bays(lines_m: Sequence[float], box_near_ends_m: Sequence[float],
              width_m: Tuple[float, float] = BAY_WIDTH_M) -> List[Tuple[float, float, bool]]:
    """(start, end, occupied) of each bay between neighbouring lines (positions [m]), in order.
    Lines less than a bay's width beyond a line are skipped: the bay ends at the next line at
    least that far (B2 on track seed 3: a false line 0.58 m after the south border, 0.22 m
    before the divider, had split the south bay into none).

    A bay is occupied when the near end of a box standing off the road lies within one bay width
    before the bay's centre: a box in the bay covers its middle (a 0.6 m box in a 0.77 m bay
    begins 0.3 m before it); a box in the next bay begins beyond the centre, one in the bay before
    about a bay width earlier, so a near end seen up to ~0.3 m off still counts in its own bay only."""
    lo, hi = width_m
    out = []
    lines = sorted(lines_m)
    i = 0
    while i < len(lines) - 1:
        a = lines[i]
        # a line nearer than a bay's width is no bay's end (the "P" painted in a bay, a dashed
        # divider seen twice): the bay ends at the next line at least that far
        j = next((k for k in range(i + 1, len(lines)) if lines[k] - a >= lo), None)
        if j is None:
            break
        b, i = lines[j], j
        if b - a <= hi:
            edges = [a, b]
        elif 2 * lo <= b - a <= 2 * hi:
            edges = [a, 0.5 * (a + b), b]
        else:
            continue
        for start, end in zip(edges, edges[1:]):
            centre = 0.5 * (start + end)
            occupied = any(centre - (end - start) <= near <= centre for near in box_near_ends_m)
            out.append((start, end, occupied))
    return out
