"""Scripted runs for the referee's tests: poses over time (t [s], x, y [m], yaw [rad]) along the
track's lane centres or straight lines, and a helper that feeds them to a Referee."""
import math

from conde_worlds import track_geometry as tg

from conde_referee.course import Course
from conde_referee.footprint import Footprint
from conde_referee.referee import Referee, judge_recorded
from conde_referee.rules import load_rules

#: A robot 0.4 m long and 0.3 m wide, its reference point in the middle, 0.3 m high.
FOOTPRINT = Footprint(-0.2, 0.2, -0.15, 0.15, 0.3)
EAST_LANE_X = tg.X_REF + tg.LANE_OFFSET
WEST_LANE_X = tg.X_REF - tg.LANE_OFFSET
DT_S = 0.1
SPEED_MPS = 0.5


def line(points, speed=SPEED_MPS):
    """Poses along the polyline `points` [(x, y)], heading along each piece, 0.05 m apart."""
    out = []
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        n = max(1, int(math.hypot(x1 - x0, y1 - y0) / (speed * DT_S)))
        yaw = math.atan2(y1 - y0, x1 - x0)
        out += [(x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n, yaw) for k in range(n)]
    return out


def stand(x, y, yaw, seconds):
    return [(x, y, yaw)] * int(round(seconds / DT_S))


def laps(route="north_ccw", n=1, spacing=SPEED_MPS * DT_S):
    """n laps from the start pose (east lane, y = -0.33, northbound) along a route's lane centre."""
    lc = tg.build_track().lane_centres(spacing)[route]
    out = line([(EAST_LANE_X, -0.33), (EAST_LANE_X, 0.0)])
    for _ in range(n):
        out += [(float(x), float(y), float(h)) for (x, y), h in zip(lc["xy"], lc["heading"])]
    return out + [(EAST_LANE_X, 0.0, math.pi / 2)]


def judge(challenge, poses, panel=((0.0, "forward"),), reports=(), variant=None, seed=0, t0=0.0):
    """Feeds the poses (one per DT_S from t0), the panel changes and the sign reports [(t, value)]
    in time order; returns (referee, report)."""
    referee = Referee(load_rules(), Course.from_layout(challenge, variant, seed), FOOTPRINT)
    poses = [(t0 + i * DT_S,) + tuple(p) for i, p in enumerate(poses)]
    return referee, judge_recorded(referee, poses, panel, reports)


def kinds(report):
    return [e["kind"] for e in report["events"]]


def straight(x, y0, y1):
    return line([(x, y0), (x, y1)])
