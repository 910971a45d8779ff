#include "conde_physics/physics_engine.h"

#include "bullet/bullet_engine.h"
#include "ode/ode_engine.h"

namespace conde_physics {

void PhysicsEngine::castRays(const std::vector<Vec3>& origins, const std::vector<Vec3>& directions, double max_range_m,
                             ModelId ignore_model, std::vector<RayHit>& hits) const {
  if (origins.size() != directions.size())
    throw std::invalid_argument(name() + ": castRays needs one direction per origin");
  ray_scene_.cast([this](int model, int body) { return bodyPose(model, body); }, origins, directions, max_range_m,
                  ignore_model, hits);
}

std::vector<std::string> availablePhysicsEngines() { return {"ode", "bullet"}; }

std::unique_ptr<PhysicsEngine> createPhysicsEngine(const std::string& name, const PhysicsSettings& settings) {
  if (name == "ode") return createOdeEngine(settings);
  if (name == "bullet") return createBulletEngine(settings);
  throw std::invalid_argument("unknown physics engine '" + name + "' (expected one of: ode, bullet)");
}

}  // namespace conde_physics
