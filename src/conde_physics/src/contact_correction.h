// How fast a rigid contact pushes penetrating bodies apart, shared by the ODE and Bullet
// backends.
//
// Both engines correct a penetration deeper than the surface layer with a velocity
// erp * (depth - layer) / step: a body spawned 5 cm into the ground (a robot spawned at z = 0
// whose origin is its chassis centre) leaves it at 0.2 * 0.049 / 0.001 s = 10 m/s, i.e. it is
// thrown. Gazebo caps that velocity per surface with <surface><contact><ode><max_vel>, whose SDF
// default is 0.01 m/s (the world-wide contact_max_correcting_vel, 100 m/s, rarely bites), so
// there such a robot rises out of the ground slowly and rests. We cap rigid contacts the same
// way, by presenting at most the depth that gives that velocity to the solver. Contacts with a
// stiffness (<kp>) are left alone: their spring force is made from this very correction, and
// capping it would change how every robot with <kp> rests and rolls.
#pragma once

#include <algorithm>

namespace conde_physics {

// Gazebo's default <max_vel> of a surface [m/s].
constexpr double kRigidContactMaxCorrectingVelMps = 0.01;

// Deepest penetration [m] a rigid contact may present to the solver: the surface layer
// `layer_m` [m] plus what a correction of kRigidContactMaxCorrectingVelMps makes with `erp` over
// one step of `step_s` [s]. Without a usable erp, no cap.
inline double rigidContactSolverDepthM(double layer_m, double erp, double step_s) {
  if (!(erp > 0.0) || !(step_s > 0.0)) return 1e9;
  return std::max(0.0, layer_m) + kRigidContactMaxCorrectingVelMps * step_s / erp;
}

}  // namespace conde_physics
