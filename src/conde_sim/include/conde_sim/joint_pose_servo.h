// Drives a joint to a position with a velocity motor whose effort is limited, free of ROS (the
// joint pose trajectory plugin sets poses with it).
//
// A motor asked for (target - position) / step reaches the target in one step only if its effort
// can stop the joint within that step; otherwise it swings past and never settles. The speed
// asked for is therefore also held to sqrt(2 a |error|), the speed from which the motor's
// deceleration a = effort / inertia stops the joint at the target.
#pragma once

namespace conde_sim {

class Simulation;

// Inertia [kg m^2] about a revolute joint's axis (mass [kg] for a prismatic joint) of every body
// the joint moves, at their current poses. Coupling through the joints beyond is ignored.
double jointLoadInertia(const Simulation& sim, int robot, int joint);

// Joint speed [rad/s or m/s] to ask of the motor for `error` [rad or m] = target - position, with
// steps of `step_s` [s] and a deceleration of at most `max_deceleration` [rad/s^2 or m/s^2].
double poseServoSpeed(double error, double step_s, double max_deceleration);

}  // namespace conde_sim
