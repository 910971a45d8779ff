#pragma once
#include <memory>

#include "conde_physics/physics_engine.h"

namespace conde_physics {
std::unique_ptr<PhysicsEngine> createOdeEngine(const PhysicsSettings& settings);
}
