// Placeholder until the backend lands: it compiles, and every use fails loudly.
#include "ode/ode_engine.h"

namespace conde_physics {
std::unique_ptr<PhysicsEngine> createOdeEngine(const PhysicsSettings&) {
  throw std::runtime_error("the ode backend is not implemented yet");
}
}  // namespace conde_physics
