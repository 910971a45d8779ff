#pragma once
#include <memory>

#include "conde_physics/physics_engine.h"

namespace conde_physics {
std::unique_ptr<PhysicsEngine> createBulletEngine(const PhysicsSettings& settings);
}
