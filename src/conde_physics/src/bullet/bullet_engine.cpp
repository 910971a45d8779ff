// Placeholder until the backend lands: it compiles, and every use fails loudly.
#include "bullet/bullet_engine.h"

namespace conde_physics {
std::unique_ptr<PhysicsEngine> createBulletEngine(const PhysicsSettings&) {
  throw std::runtime_error("the bullet backend is not implemented yet");
}
}  // namespace conde_physics
