"""The lane recovery's closed-loop campaign on the unit tests' toy road (test_lane_recovery.py's
robot beside a straight lane, DecisionLogic, conde_control's law): 42 starts, the lane last seen
0.1-0.35 m right of its centre and 0.4-1.0 rad off its direction, for each width of the model
camera's view (the lane is seen only within +-cone_rad of its direction and 0.45 m of its centre).
A start counts as back on its lane when, at the end, the robot follows it (lane in view, not lost,
no recovery phase) within 0.05 m and 0.05 rad of its centre line.

    /usr/bin/python3 recovery_campaign.py [--seconds 30] [--cones 0.35,0.5,0.6,0.8]

prints a table (back on the lane / starts, the farthest off the lane's centre in any recovery
creeping ahead or rejoining [m]).  Pure: no ROS master."""

import argparse
import os
import sys
from dataclasses import dataclass

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from road_model import DT_S  # noqa: E402
from test_decision_logic import FORWARD, make, signal  # noqa: E402
from test_lane_recovery import BesideTheLane  # noqa: E402

from conde_decision.lane_recovery import AHEAD, IDLE, REJOIN  # noqa: E402

SEEN_M = (0.1, 0.15, 0.2, 0.25, 0.3, 0.35)  # last seen this far right of the lane's centre [m]
HEADINGS_RAD = (0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)  # ... pointing this far right of its direction [rad]
CONES_RAD = (0.35, 0.5, 0.6, 0.8)


@dataclass(frozen=True)
class StartResult:
    seen_m: float
    heading_rad: float
    back_on_lane: bool
    max_offset_m: float  # farthest off the lane's centre creeping ahead or rejoining [m]
    final_offset_m: float
    final_heading_rad: float
    last_phase: str


def run_start(seen_m: float, heading_rad: float, cone_rad: float, seconds: float = 30.0) -> StartResult:
    """One start: the lane seen for the last time seen_m right of its centre, heading_rad right of
    its direction; the robot drives on (lane lost), recovers, ... for `seconds` [s]."""
    road = make()
    signal(road, FORWARD)
    road.drive_m(3.0)
    robot = BesideTheLane(road, -seen_m, -heading_rad)
    robot.SEEN_HEADING_RAD = cone_rad
    for _ in range(int(seconds / DT_S)):
        robot.step()
    last = robot.outputs[-1]
    back = (robot.seen() and not last.lane_lost and last.recovery == IDLE
            and abs(robot.y_m) < 0.05 and abs(robot.heading_rad) < 0.05)
    in_recovery = [abs(y) for y, o in zip(robot.offsets_m, robot.outputs) if o.recovery in (AHEAD, REJOIN)]
    return StartResult(seen_m, heading_rad, back, max(in_recovery, default=0.0), robot.y_m, robot.heading_rad,
                       last.recovery)


def campaign(cone_rad: float, seconds: float = 30.0):
    return [run_start(s, h, cone_rad, seconds) for s in SEEN_M for h in HEADINGS_RAD]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=30.0, help="simulated time per start [s]")
    parser.add_argument("--cones", default=",".join(str(c) for c in CONES_RAD),
                        help="model camera's view half angles [rad], comma-separated")
    parser.add_argument("--verbose", action="store_true", help="one line per start")
    args = parser.parse_args(argv)
    cones = [float(c) for c in args.cones.split(",")]
    rows = []
    for cone in cones:
        results = campaign(cone, args.seconds)
        if args.verbose:
            for r in results:
                print("cone %.2f seen %.2f m heading %.1f rad: %s (end %+.3f m %+.3f rad, phase '%s', "
                      "max off %.3f m)" % (cone, r.seen_m, r.heading_rad, "back" if r.back_on_lane else "NOT back",
                                           r.final_offset_m, r.final_heading_rad, r.last_phase, r.max_offset_m))
        rows.append((sum(r.back_on_lane for r in results), len(results), max(r.max_offset_m for r in results)))
    print("| model camera's view angle (+- rad) | " + " | ".join("%.2f" % c for c in cones) + " |")
    print("|---|" + "---|" * len(cones))
    print("| back on the lane | " + " | ".join("%d/%d" % (n, total) for n, total, _ in rows) + " |")
    print("| farthest off the centre creeping ahead / rejoining [m] | "
          + " | ".join("%.3f" % m for _, _, m in rows) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
