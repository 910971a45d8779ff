#include "conde_physics/physics_engine.h"

#include "bullet/bullet_engine.h"
#include "ode/ode_engine.h"

namespace conde_physics {

std::vector<std::string> availablePhysicsEngines() { return {"ode", "bullet"}; }

std::unique_ptr<PhysicsEngine> createPhysicsEngine(const std::string& name, const PhysicsSettings& settings) {
  if (name == "ode") return createOdeEngine(settings);
  if (name == "bullet") return createBulletEngine(settings);
  throw std::invalid_argument("unknown physics engine '" + name + "' (expected one of: ode, bullet)");
}

}  // namespace conde_physics
