"""One walking trial against a running, paused conde_sim with the NAO and nao_walk (nao.launch
controllers:=trajectory walk:=true paused:=true): step to the start, ask nao_walk for a walk,
step through it, and measure from the simulator's ground truth (/gazebo/get_link_state). Shared
by the walking rostest and walk_report. No sleeping on the wall clock for simulated time."""

import math
import time
from dataclasses import dataclass

import rospy
from conde_common.delivery import ReceivedCount
from conde_msgs.srv import StepSimulation
from gazebo_msgs.srv import GetLinkState

from conde_humanoid.srv import WalkTo

MODEL = 'nao'
FALLEN_TORSO_HEIGHT_M = 0.2   # torso origin lower than this: fallen (walking height 0.30 m)
WALK_NODE = '/nao_walk'        # publishes one joint trajectory per walk to the controller in conde_sim
FALLEN_TILT_RAD = 0.7         # or torso tilted more than this from upright


@dataclass
class Pose:
    x_m: float
    y_m: float
    z_m: float
    yaw_rad: float
    tilt_rad: float


@dataclass
class Trial:
    x_m: float            # torso displacement, in the start heading's frame
    y_m: float
    turned_rad: float     # yaw change (unwrapped over the walk)
    fell: bool
    sim_s: float          # simulated time of the walk [s]
    wall_s: float         # wall-clock time it took [s]
    final: Pose = None


def _pose(state):
    p, q = state.link_state.pose.position, state.link_state.pose.orientation
    yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
    up_z = 1 - 2 * (q.x * q.x + q.y * q.y)
    return Pose(p.x, p.y, p.z, yaw, math.acos(max(-1.0, min(1.0, up_z))))


class WalkTrials:
    def __init__(self, timeout_s=60.0):
        for name in ('/conde_sim/step', '/gazebo/get_link_state', WALK_NODE + '/walk_to'):
            rospy.wait_for_service(name, timeout=timeout_s)
        self._step = rospy.ServiceProxy('/conde_sim/step', StepSimulation)
        self._link = rospy.ServiceProxy('/gazebo/get_link_state', GetLinkState)
        self._walk = rospy.ServiceProxy(WALK_NODE + '/walk_to', WalkTo)
        # nao_walk's trajectories as the simulator's controller receives them (acknowledged delivery)
        controller = rospy.get_param(WALK_NODE + '/controller', 'nao_trajectory_controller')
        self._delivered = ReceivedCount('/%s/command' % controller, WALK_NODE, timeout_s=timeout_s)
        self.step_s = 0.001
        self.time_s = self._step(0).sim_time_s
        self._trajectories = 1  # nao_walk's latched posture trajectory
        self._delivered.wait(self._trajectories)

    def step_to(self, time_s):
        steps = int(round((time_s - self.time_s) / self.step_s))
        if steps > 0:
            response = self._step(steps)
            if not response.success:
                raise RuntimeError('/conde_sim/step: ' + response.message)
            self.time_s = response.sim_time_s
        return self.time_s

    def link_state(self, name):
        """gazebo_msgs/GetLinkState response for the robot's link `name` in the world."""
        return self._link(link_name='%s::%s' % (MODEL, name), reference_frame='world')

    def link(self, name):
        state = self.link_state(name)
        if not state.success:
            raise RuntimeError('/gazebo/get_link_state %s: %s' % (name, state.status_message))
        return _pose(state)

    def request_walk(self, distance_m, angle_rad, speed_fraction, start_time_s):
        """Asks nao_walk for a walk starting at `start_time_s` (not stepping); its answer."""
        answer = self._walk(distance_m=distance_m, angle_rad=angle_rad, speed_fraction=speed_fraction,
                            start_time_s=start_time_s)
        if not answer.accepted:
            raise RuntimeError('nao_walk refused the walk: ' + answer.message)
        self._trajectories += 1
        self._delivered.wait(self._trajectories)  # it reaches the controller before the simulation steps on
        return answer

    def wait_for_clock(self, timeout_s=30.0):
        """Waits until nao_walk's clock has caught up with the paused simulator (it answers for
        `now` from its own /clock subscription)."""
        end = time.monotonic() + timeout_s
        while rospy.get_time() < self.time_s - 1e-9 and time.monotonic() < end:
            time.sleep(0.01)
        time.sleep(0.2)  # the node's clock messages travel like ours

    def fallen(self, torso):
        return torso.z_m < FALLEN_TORSO_HEIGHT_M or torso.tilt_rad > FALLEN_TILT_RAD

    def walk(self, distance_m, angle_rad, speed_fraction, start_time_s, sample_s=0.05, slip_every_s=None):
        """Runs one walk starting at simulated `start_time_s` (> now); returns a Trial. Samples
        the torso every `sample_s` to detect a fall and unwrap the yaw."""
        wall0 = time.monotonic()
        self.step_to(start_time_s - 0.05)  # the previous walk (or the move to the posture) is over
        self.wait_for_clock()
        answer = self.request_walk(distance_m, angle_rad, speed_fraction, start_time_s)
        self.step_to(start_time_s)
        start = self.link('torso')
        yaw, last, fell = 0.0, start.yaw_rad, False
        t = start_time_s
        while t < answer.end_time_s - 1e-9:
            t = min(answer.end_time_s, t + sample_s)
            self.step_to(t)
            torso = self.link('torso')
            yaw += math.remainder(torso.yaw_rad - last, 2 * math.pi)
            last = torso.yaw_rad
            if self.fallen(torso):
                fell = True
                break
        end = self.link('torso')
        c, s = math.cos(start.yaw_rad), math.sin(start.yaw_rad)
        dx, dy = end.x_m - start.x_m, end.y_m - start.y_m
        return Trial(x_m=c * dx + s * dy, y_m=-s * dx + c * dy, turned_rad=yaw, fell=fell,
                     sim_s=self.time_s - start_time_s, wall_s=time.monotonic() - wall0, final=end)
