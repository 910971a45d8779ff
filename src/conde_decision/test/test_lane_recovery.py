"""The lane recovery (lane_recovery.py) alone, and in DecisionLogic driving a robot model steered by
conde_control's control law: a robot standing over the lane's outer line at an angle finds its lane
again; blind manoeuvres and standing states are not disturbed."""

import math
import os
from dataclasses import replace

import pytest
from road_model import DT_S, Lane
from test_decision_logic import CONFIG, CRUISE, FORWARD, PARKING, drive_to_parked, make, signal, states_passed

from conde_decision.lane_recovery import (AHEAD, BACK, GAVE_UP, IDLE, REJOIN, LaneRecovery, RecoveryCommand,
                                          RecoveryConfig, lost_lane_status)

RECOVERY = RecoveryConfig()


# --- the module alone ----------------------------------------------------------------------------

def drive(recovery, lost, yaw_rad, travelled_m, steps, step_m=0.005):
    """Steps with the lane lost; the path grows step_m per step, driven the way the last command
    said (backwards while it reversed, as DecisionLogic tells it).  Returns the commands and the path."""
    commands = []
    for _ in range(steps):
        backwards = bool(commands) and commands[-1].speed_mps < 0.0
        commands.append(recovery.step(lost, True, yaw_rad, travelled_m, backwards))
        travelled_m += step_m
    return commands, travelled_m


@pytest.mark.parametrize("since_lane_m", [0.3, 2.0])
def test_backs_the_way_it_came_then_creeps_ahead_toward_the_road_direction_bounded(since_lane_m):
    recovery = LaneRecovery(replace(RECOVERY, max_offset_m=10.0))  # the distances (the offset's bound: below)
    recovery.on_confident_lane(1.0, 0.2, 0.0, 5.0 - since_lane_m)  # the road runs at 0.8 rad
    commands, _ = drive(recovery, True, 1.3, 5.0, 1000)
    phases = [c.phase for c in commands]
    back = phases.index(AHEAD)
    assert phases[:back] == [BACK] * back
    # back: the way driven since the last confident lane, at most distance_m; ahead: distance_m
    assert back * 0.005 == pytest.approx(min(since_lane_m, RECOVERY.distance_m), abs=0.006)
    ahead = phases.index(IDLE, back) - back
    assert ahead * 0.005 == pytest.approx(RECOVERY.distance_m, abs=0.006)
    assert all(c.speed_mps == -RECOVERY.speed_mps and c.heading_error_rad == 0.0 for c in commands
               if c.phase == BACK)  # straight back
    assert all(c.speed_mps == RECOVERY.speed_mps and c.heading_error_rad == pytest.approx(0.5) for c in commands
               if c.phase == AHEAD)
    # bounded: max_tries tries, then it stands for good
    assert phases[-1] == GAVE_UP and recovery.tries == RECOVERY.max_tries
    assert 2 * RECOVERY.distance_m <= (len(phases) - phases.count(GAVE_UP)) * 0.005 <= 4 * RECOVERY.distance_m + 0.03


def test_the_offset_is_dead_reckoned_from_the_last_lane_seen():
    recovery = LaneRecovery()
    recovery.on_confident_lane(0.5, 0.5, -0.1, 0.0)  # road direction 0, 0.1 m right of the centre
    recovery.step(True, True, 0.5, 0.0)
    recovery.step(True, True, 0.5, 0.2)  # 0.2 m ahead, 0.5 rad to the left
    assert recovery.offset_m == pytest.approx(-0.1 + 0.2 * math.sin(0.5))
    recovery.step(True, True, 0.5, 0.3, backwards=True)  # 0.1 m back
    assert recovery.offset_m == pytest.approx(-0.1 + 0.1 * math.sin(0.5))


def test_the_way_back_counts_only_the_way_driven_backwards():
    """A robot still rolling forward when the try begins reverses that too, to where it saw its lane
    last; the creep's distance is its net way forward (before, the path either way counted: the way
    back ended short of that place by twice the roll, and the creep by its reversing start)."""
    recovery = LaneRecovery()
    recovery.on_confident_lane(0.0, 0.0, 0.0, 10.0)
    travelled_m, command = 10.0, None
    for step_m in [0.01] * 30:  # the hold: 0.3 m on
        travelled_m += step_m
        command = recovery.step(True, True, 0.0, travelled_m)
    assert command.phase == BACK
    moves = [+0.01] * 10 + [-0.005] * 200  # still rolling 0.1 m forward, then reversing
    position_m, phases = 0.3, []
    for move_m in moves:
        travelled_m += abs(move_m)
        position_m += move_m
        phases.append(recovery.step(True, True, 0.0, travelled_m, move_m < 0.0).phase)
        if phases[-1] != BACK:
            break
    assert phases[-1] == AHEAD and position_m == pytest.approx(0.0, abs=0.006)  # where the lane was last seen
    position_at_ahead_m = position_m
    for move_m in [-0.005] * 10 + [+0.005] * 400:  # the reverse ramps out, then forward
        travelled_m += abs(move_m)
        position_m += move_m
        if recovery.step(True, True, 0.0, travelled_m, move_m < 0.0).phase != AHEAD:
            break
    assert position_m - position_at_ahead_m == pytest.approx(RECOVERY.distance_m, abs=0.006)


def test_the_creep_ahead_stays_within_max_offset_of_the_lane_last_seen():
    recovery = LaneRecovery(RecoveryConfig(max_offset_m=0.3))
    recovery.on_confident_lane(0.0, 0.0, -0.25, 0.0)  # the road runs at 0 rad, the robot 0.25 m right
    commands, notes, travelled_m = [], [], 0.0
    for _ in range(400):  # heading 0.5 rad off to the right (the model holds it): it drifts out
        commands.append(recovery.step(True, True, -0.5, travelled_m, bool(commands) and commands[-1].speed_mps < 0))
        notes.append(recovery.note)
        travelled_m += 0.005
    phases = [c.phase for c in commands]
    ahead = phases.index(AHEAD)
    stop = phases.index(IDLE, ahead)  # the creep stops where the dead-reckoned offset passes the bound
    assert all(abs(c.lateral_offset_m) <= 0.3 for c in commands[ahead:stop])
    assert (stop - ahead) * 0.005 < RECOVERY.distance_m
    assert notes[stop].endswith("came -0.30 m off the lane's centre as last seen (odometry), more than "
                                "recovery_max_offset_m 0.30 m: stopped")


def test_no_creep_ahead_from_beyond_max_offset():
    recovery = LaneRecovery(RecoveryConfig(max_offset_m=0.3, max_tries=1))
    recovery.on_confident_lane(0.0, 0.0, -0.32, 0.0)  # the lane last seen 0.32 m to the left
    notes, travelled_m, command = [], 0.0, None
    for _ in range(300):
        command = recovery.step(True, True, 0.0, travelled_m, command is not None and command.speed_mps < 0.0)
        notes.append(recovery.note)
        travelled_m += 0.005
    assert AHEAD not in [n for n in notes] and command.phase == GAVE_UP
    assert ("lane recovery: try 1 of 1: -0.32 m off the lane's centre as last seen (odometry), more than "
            "recovery_max_offset_m 0.30 m: no creep ahead") in notes


def test_gives_up_with_a_note_and_starts_afresh_after_driving_on_a_lane():
    recovery = LaneRecovery(RecoveryConfig(max_tries=1))
    recovery.on_confident_lane(0.0, 0.0, 0.0, 0.0)
    notes = []
    travelled_m = 1.0
    command = None
    for _ in range(400):
        command = recovery.step(True, True, 0.0, travelled_m, command is not None and command.speed_mps < 0.0)
        notes.append(recovery.note)
        travelled_m += 0.005
    assert command.phase == GAVE_UP and not command.active and command.speed_mps == 0.0
    assert [n for n in notes if "standing" in n] == [
        "lane recovery: no lane after 1 tries (back and ahead %.2f m each): standing" % RECOVERY.distance_m]
    # the lane is back: the hold ends; after reset_m on the lane the tries count from 0 again
    assert recovery.step(False, True, 0.0, travelled_m).phase == IDLE
    recovery.on_confident_lane(0.0, 0.0, 0.0, travelled_m)
    recovery.on_confident_lane(0.0, 0.0, 0.0, travelled_m + RECOVERY.reset_m)
    assert recovery.tries == 0
    assert recovery.step(True, True, 0.0, travelled_m + RECOVERY.reset_m + 0.1).phase == BACK


def test_a_confident_lane_ends_the_try():
    recovery = LaneRecovery()
    recovery.on_confident_lane(0.0, 0.0, 0.0, 0.0)
    assert recovery.step(True, True, 0.3, 2.0).phase == BACK
    recovery.on_confident_lane(0.3, 0.25, 0.0, 2.01)
    assert recovery.phase == REJOIN and recovery.note.startswith("lane recovery: lane seen again (back, try 1")
    assert recovery.road_direction_rad == pytest.approx(0.05)
    # slowly (speed_mps) on the lane found until rejoin_m on it
    assert recovery.step(False, True, 0.3, 2.02) == RecoveryCommand(REJOIN, RECOVERY.speed_mps)
    recovery.on_confident_lane(0.3, 0.25, 0.0, 2.02 + RECOVERY.rejoin_m)
    assert recovery.step(False, True, 0.3, 2.5).phase == IDLE


@pytest.mark.parametrize("may_move, yaw_rad, direction_known",
                         [(False, 0.0, True), (True, None, True), (True, 0.0, False)])
def test_no_recovery_where_the_robot_may_not_move_or_the_road_direction_is_unknown(
        may_move, yaw_rad, direction_known):
    recovery = LaneRecovery()
    if direction_known:
        recovery.on_confident_lane(0.0, 0.0, 0.0, 0.0)
    command = recovery.step(True, may_move, yaw_rad, 1.0)
    assert command.phase == IDLE and not command.active and command.speed_mps == 0.0


@pytest.mark.parametrize("name, value", [("speed_mps", 0.0), ("distance_m", -1.0), ("reset_m", float("nan")),
                                         ("max_tries", -1), ("max_tries", 1.5), ("max_offset_m", 0.0)])
def test_bad_settings_are_named(name, value):
    with pytest.raises(ValueError, match="recovery_" + name):
        replace(RECOVERY, **{name: value}).check()


def test_decision_config_names_the_bad_recovery_setting():
    from conde_decision.decision_logic import DecisionLogic
    from test_decision_logic import SPEC
    with pytest.raises(ValueError, match="recovery_max_tries"):
        DecisionLogic(SPEC, replace(CONFIG, recovery_max_tries=-2))


# --- closed loop: DecisionLogic, conde_control's law, a robot beside a straight lane ----------------

def controller():
    from conde_control.control_law import LaneFollowingController, load_config
    here = os.path.dirname(os.path.abspath(__file__))
    return LaneFollowingController(load_config(os.path.join(here, "..", "..", "conde_control", "config",
                                                            "control.yaml")))


class BesideTheLane:
    """A robot at lateral offset y_m [m] from its lane's centre (+ = left) heading heading_rad [rad]
    off the lane's direction (north), driven by conde_control's law.  The cameras see the lane
    (confidence 1) only while the robot heads within SEEN_HEADING_RAD of it and is within
    SEEN_OFFSET_M of its centre (standing over the outer line, pointing off the road, they see
    no lane), and in the first step: the robot's pose is where it saw its lane the last time."""

    SEEN_HEADING_RAD = 0.35
    SEEN_OFFSET_M = 0.45

    def __init__(self, road, y_m, heading_rad):
        self.logic, self.t = road.logic, road.t
        self.path_m, self.y_m, self.heading_rad = road.path_m, y_m, heading_rad
        self.control = controller()
        self.outputs = []
        self.offsets_m = []

    def seen(self):
        return not self.outputs or abs(self.heading_rad) < self.SEEN_HEADING_RAD and abs(self.y_m) < self.SEEN_OFFSET_M

    def step(self):
        self.logic.on_odometry(0.5 * math.pi + self.heading_rad, self.path_m)
        lane = Lane(self.y_m, self.heading_rad, confidence=1.0 if self.seen() else 0.0)
        out = self.logic.on_lane(lane, self.t)
        self.outputs.append(out)
        v_mps, omega_radps = self.control.update(out, DT_S)
        self.y_m += v_mps * math.sin(self.heading_rad) * DT_S
        self.offsets_m.append(self.y_m)
        self.heading_rad += omega_radps * DT_S
        self.path_m += abs(v_mps) * DT_S
        self.t += DT_S
        return out


def test_a_robot_over_the_outer_line_at_an_angle_finds_its_lane_again():
    road = make()
    signal(road, FORWARD)
    road.drive_m(3.0)
    # the lane seen for the last time 0.3 m right of its centre pointing 34 deg off the road: holding
    # its course for lane_lost_timeout_s the robot crosses the outer (right) line
    robot = BesideTheLane(road, -0.3, -0.6)
    for _ in range(int(20.0 / DT_S)):
        robot.step()
    outs = robot.outputs
    assert min(y for y in robot.offsets_m) < -0.45  # over the outer line
    phases = [o.recovery for o in outs]
    assert BACK in phases and GAVE_UP not in phases
    first_back = phases.index(BACK)
    assert outs[first_back].lane_lost  # only after the hold
    assert REJOIN in phases and all(o.linear_velocity_mps <= RECOVERY.speed_mps + 1e-9 for o in outs
                                    if o.recovery == REJOIN)
    assert min(o.linear_velocity_mps for o in outs) == pytest.approx(-RECOVERY.speed_mps)
    # back on its lane, following it at cruise speed
    assert abs(robot.y_m) < 0.05 and abs(robot.heading_rad) < 0.05 and robot.seen()
    assert outs[-1].state == "follow_lane" and outs[-1].linear_velocity_mps == pytest.approx(CRUISE)
    assert not outs[-1].lane_lost and outs[-1].recovery == IDLE


def test_the_lost_lane_status_says_what_the_robot_does():
    assert lost_lane_status(IDLE, 0, 2) == "holding the robot"
    assert lost_lane_status(BACK, 1, 2) == "recovering: reversing the way it came (try 1 of 2)"
    assert lost_lane_status(AHEAD, 2, 2) == "recovering: creeping ahead onto the lane by odometry (try 2 of 2)"
    assert lost_lane_status(GAVE_UP, 2, 2) == "the recovery gave up after 2 tries: holding the robot"


def test_the_node_log_line_holds_only_while_the_robot_stands():
    """The node logs lost_lane_status(out.recovery, ...) while out.lane_lost: "holding" only where the
    speed commanded goes to 0, "reversing" / "creeping ahead" while it is driven that way (the line
    said "holding the robot" all along before)."""
    road = make()
    signal(road, FORWARD)
    road.drive_m(3.0)
    robot = BesideTheLane(road, -0.3, -0.6)
    robot.SEEN_OFFSET_M = 0.0  # nothing to see anywhere (but in the first step): every status in turn
    recovery = road.logic.recovery
    lost, v_before = [], 0.0
    for _ in range(int(40.0 / DT_S)):
        out = robot.step()
        if out.lane_lost:
            lost.append((lost_lane_status(out.recovery, recovery.tries, recovery.config.max_tries),
                         v_before, out.linear_velocity_mps))
        v_before = out.linear_velocity_mps
    kinds = [status.split(" (")[0] for status, _, _ in lost]
    assert set(kinds) == {"holding the robot", "recovering: reversing the way it came",
                          "recovering: creeping ahead onto the lane by odometry",
                          "the recovery gave up after 2 tries: holding the robot"}
    assert "try 1 of 2" in lost[kinds.index("recovering: reversing the way it came")][0]
    for status, v_before_mps, v_mps in lost:
        if "reversing" in status:
            assert v_mps < v_before_mps or v_mps == pytest.approx(-RECOVERY.speed_mps)
        elif "creeping ahead" in status:
            assert v_mps > v_before_mps or v_mps == pytest.approx(RECOVERY.speed_mps)
        else:  # holding: the speed goes to 0
            assert abs(v_mps) < abs(v_before_mps) or v_mps == 0.0
    assert lost[-1][0].startswith("the recovery gave up") and lost[-1][2] == 0.0


def test_a_robot_that_never_sees_a_lane_stands_after_its_tries():
    road = make()
    signal(road, FORWARD)
    road.drive_m(3.0)
    robot = BesideTheLane(road, -0.3, -0.6)
    robot.SEEN_OFFSET_M = 0.0  # nothing to see anywhere (but in the first step)
    for _ in range(int(40.0 / DT_S)):
        robot.step()
    outs = robot.outputs
    assert outs[-1].recovery == GAVE_UP and outs[-1].lane_lost and outs[-1].linear_velocity_mps == 0.0
    driven_m = sum(abs(o.linear_velocity_mps) * DT_S for o in outs[int(2.0 / DT_S):])
    assert driven_m <= 2 * RECOVERY.distance_m * RECOVERY.max_tries + 0.05


@pytest.mark.parametrize("seen_m, heading_rad", [(-0.3, -0.6), (-0.3, -1.0), (-0.2, -0.8), (-0.34, -0.4)])
def test_back_to_where_the_lane_was_seen_and_the_creep_stays_within_max_offset(seen_m, heading_rad):
    """Closed loop, a lane never seen again: the way back ends where the robot saw its lane last
    (before: short of it by twice the forward roll as the hold began: 0.13 m off at 34 deg), and the
    creep ahead, steering by the lane dead-reckoned from there, keeps the robot within
    recovery_max_offset_m of its centre (before: up to 0.58 m, over the outer line)."""
    road = make()
    signal(road, FORWARD)
    road.drive_m(3.0)
    robot = BesideTheLane(road, seen_m, heading_rad)
    robot.SEEN_OFFSET_M = 0.0
    for _ in range(int(30.0 / DT_S)):
        robot.step()
    phases = [o.recovery for o in robot.outputs]
    first_ahead = phases.index(AHEAD)
    assert robot.offsets_m[first_ahead - 1] == pytest.approx(seen_m, abs=0.015)
    assert max(abs(y) for y, p in zip(robot.offsets_m, phases) if p == AHEAD) <= CONFIG.recovery_max_offset_m + 0.01
    assert phases[-1] == GAVE_UP


def test_a_lane_last_seen_beyond_max_offset_is_not_crept_onto():
    road = make()
    signal(road, FORWARD)
    road.drive_m(3.0)
    robot = BesideTheLane(road, -(CONFIG.recovery_max_offset_m + 0.03), -0.5)
    robot.SEEN_OFFSET_M = 0.0
    notes = []
    for _ in range(int(20.0 / DT_S)):
        robot.step()
        notes.extend(road.logic.notes)
    phases = [o.recovery for o in robot.outputs]
    assert BACK in phases and AHEAD not in phases and phases[-1] == GAVE_UP
    assert robot.y_m == pytest.approx(-(CONFIG.recovery_max_offset_m + 0.03), abs=0.015)  # back where it saw the lane
    assert any(n.endswith("no creep ahead") for n in notes)


def test_parking_without_a_lane_in_view_is_not_disturbed():
    """The parking manoeuvres are blind (creep / reverse): no lane there is no lane lost."""
    runs = []
    for lane_seen in (True, False):
        road = make(parking_place="parallel")
        road.run(100 * DT_S)
        signal(road, PARKING)
        while road.logic.machine.command.speed not in ("creep", "reverse"):
            road.step()
        road.lane_confidence = 1.0 if lane_seen else 0.0
        drive_to_parked(road)
        road.run(2.0)
        runs.append(road)
    seen, unseen = runs
    assert states_passed(unseen) == states_passed(seen)
    assert unseen.positions == pytest.approx(seen.positions)
    assert all(o.recovery == IDLE for o in unseen.outputs)


def test_a_standing_state_without_a_lane_stays_standing():
    road = make()
    road.lane_confidence = 0.0
    outs = road.run(5.0)  # waiting for the go at the start
    assert all(o.recovery == IDLE and o.linear_velocity_mps == 0.0 for o in outs)
